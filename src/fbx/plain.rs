//! A plain FBX take read exactly: the file's own channels, in its own units.
//!
//! A take whose joints are plain nodes — no pre- or post-rotation, no pivots or offsets, no
//! scale, no geometric transform, every rotation zero at rest (a BVH's rest pose), parented
//! only to each other and the scene's root — and whose one layer keys `Lcl Translation` and
//! `Lcl Rotation` with all three curves at every frame of the take, is a BVH written as FBX:
//! each joint's `RotationOrder` is one of BVH's six orders, its rotation keys are its channels
//! in degrees, its translation keys its position channels, its rest translation its OFFSET.
//! Such a take is read as it is written: key values as they are (32-bit in the file), in the
//! file's units (`UnitScaleFactor`, stated, not guessed), each joint in its own Euler order.
//! Nothing is evaluated or split, so a take bvhview wrote reads back with the values it wrote,
//! and writes again the same bytes.
//!
//! The reader takes this way only where it gives what ufbx's evaluation of the whole scene
//! gives at the keys' times (checked at the first, middle and last frames: the world places, scaled to metres,
//! within a millionth of the figure's size, and the world rotations); every other take is
//! evaluated and baked (see [`super::read`]). `load_bytes_baked` reads any file the baked way,
//! and a test proves the two equal on every take of the corpus written as FBX.

use crate::model::baked::Node;
use crate::model::motion::Motion;
use crate::model::skeleton::{Channel, Joint, RotationOrder, Skeleton};

/// Node properties that must hold their plain value (absent is plain too): `(name, value)`.
const PLAIN_PROPERTIES: [(&str, f64); 11] = [
    ("PreRotation", 0.0),
    ("PostRotation", 0.0),
    ("RotationOffset", 0.0),
    ("RotationPivot", 0.0),
    ("ScalingOffset", 0.0),
    ("ScalingPivot", 0.0),
    ("GeometricTranslation", 0.0),
    ("GeometricRotation", 0.0),
    ("GeometricScaling", 1.0),
    ("Lcl Scaling", 1.0),
    ("Lcl Rotation", 0.0),
];

/// The rotation channel about X, Y and Z.
const ROTATIONS: [Channel; 3] = [Channel::Xrotation, Channel::Yrotation, Channel::Zrotation];

/// What a plain take's keys are: a joint's translation or its rotation.
const TRANSLATION: &str = "Lcl Translation";
const ROTATION: &str = "Lcl Rotation";

/// The take of `stack` read exactly, when its joints and keys are plain (see the module's
/// documentation), else `None`. `order`: the joints' scene nodes, `nodes`: their names and
/// parents (indices into `order`); `begin`, `count`, `fps`: the take's frames. The skeleton's
/// joints come in pre-order, End Sites where a leaf is never keyed (as the baked way makes
/// them); `to_node[j]` is joint `j`'s index in `order`.
pub(super) fn read(
    scene: &ufbx::Scene,
    stack: &ufbx::AnimStack,
    order: &[usize],
    nodes: &[Node],
    span: (f64, usize, f64),
) -> Option<Plain> {
    let (begin, count, fps) = span;
    if stack.layers.len() != 1 {
        return None;
    }
    let layer = &stack.layers[0];
    // One layer: its blend mode (FBX's default is additive) has nothing below it to blend with.
    if layer.weight != 1.0 || layer.weight_is_animated || count == 0 {
        return None;
    }
    let mut joint_of = std::collections::HashMap::with_capacity(order.len());
    for (k, &n) in order.iter().enumerate() {
        joint_of.insert(n, k);
    }
    let mut offsets = Vec::with_capacity(order.len());
    let mut orders = Vec::with_capacity(order.len());
    for (k, &n) in order.iter().enumerate() {
        let node = &scene.nodes[n];
        if !is_plain(node) || !parented_plainly(scene, node, nodes[k].parent.map(|p| order[p])) {
            return None;
        }
        orders.push(bvh_order(node.rotation_order)?);
        let t = node
            .element
            .props
            .find_prop(TRANSLATION)
            .map_or([0.0; 3], |p| {
                [p.value_vec4.x, p.value_vec4.y, p.value_vec4.z]
            });
        let offset = glam::DVec3::from_array(t).as_vec3();
        if !offset.is_finite() {
            return None;
        }
        offsets.push(offset);
    }
    let mut moves: Vec<Option<[Vec<f32>; 3]>> = vec![None; order.len()];
    let mut turns: Vec<Option<[Vec<f32>; 3]>> = vec![None; order.len()];
    let mut times: Option<Vec<f64>> = None;
    for prop in layer.anim_props.iter() {
        let element = &prop.element;
        if element.type_ != ufbx::ElementType::Node {
            continue;
        }
        let Some(&k) = joint_of.get(&(element.typed_id as usize)) else {
            continue;
        };
        let name: &str = &prop.prop_name;
        let slot = match name {
            TRANSLATION => &mut moves[k],
            ROTATION => &mut turns[k],
            // Any other part of a joint's transform animated: not plain.
            other if is_transform_property(other) => return None,
            _ => continue,
        };
        if slot.is_some() {
            return None;
        }
        *slot = Some(keys(&prop.anim_value, begin, count, fps, &mut times)?);
    }
    let times = times?;
    let mut plain = Plain::build(nodes, offsets, orders, moves, turns, count, fps);
    plain.times = times;
    Some(plain)
}

/// A take read exactly: its skeleton and motion in the file's units, and where each joint came
/// from.
pub(super) struct Plain {
    pub(super) skeleton: Skeleton,
    pub(super) motion: Motion,
    /// Joint `j`'s index in the nodes the take was read from.
    pub(super) to_node: Vec<usize>,
    /// The time of each frame's keys, in seconds (every curve keys the same times).
    pub(super) times: Vec<f64>,
}

impl Plain {
    fn build(
        nodes: &[Node],
        offsets: Vec<glam::Vec3>,
        orders: Vec<RotationOrder>,
        moves: Vec<Option<[Vec<f32>; 3]>>,
        turns: Vec<Option<[Vec<f32>; 3]>>,
        count: usize,
        fps: f64,
    ) -> Plain {
        let mut children = vec![Vec::new(); nodes.len()];
        for (k, node) in nodes.iter().enumerate() {
            if let Some(p) = node.parent {
                children[p].push(k);
            }
        }
        let joints: Vec<Joint> = nodes
            .iter()
            .enumerate()
            .map(|(k, node)| {
                let mut joint = Joint::new(node.name.clone(), node.parent);
                joint.offset = offsets[k];
                joint.children = children[k].clone();
                joint.end_site = node.parent.is_some()
                    && children[k].is_empty()
                    && moves[k].is_none()
                    && turns[k].is_none();
                if moves[k].is_some() {
                    joint.channels.extend([
                        Channel::Xposition,
                        Channel::Yposition,
                        Channel::Zposition,
                    ]);
                }
                if turns[k].is_some() {
                    let order = orders[k];
                    joint
                        .channels
                        .extend(crate::model::euler::axes(order).map(|a| ROTATIONS[a]));
                    joint.rotation_order = Some(order);
                }
                joint
            })
            .collect();
        let to_node = crate::model::baked::pre_order(nodes, &children);
        let (skeleton, channels) = crate::model::baked::sorted_skeleton(&joints, &to_node);
        let mut data = Vec::with_capacity(count * channels);
        for f in 0..count {
            for &k in &to_node {
                if let Some(keys) = &moves[k] {
                    data.extend(keys.iter().map(|axis| axis[f]));
                }
                if let Some(keys) = &turns[k] {
                    let axes = crate::model::euler::axes(orders[k]);
                    data.extend(axes.iter().map(|&a| keys[a][f]));
                }
            }
        }
        Plain {
            skeleton,
            motion: Motion::new(1.0 / fps, channels, count, data),
            to_node,
            times: Vec::new(),
        }
    }
}

/// Whether `node`'s transform is plain: its Euler rotation and translation alone.
fn is_plain(node: &ufbx::Node) -> bool {
    if node.is_scale_helper
        || node.is_geometry_transform_helper
        || node.scale_helper.is_some()
        || node.geometry_transform_helper.is_some()
        || node.has_geometry_transform
        || node.inherit_mode != ufbx::InheritMode::Normal
    {
        return false;
    }
    PLAIN_PROPERTIES.iter().all(|&(name, plain)| {
        node.element.props.find_prop(name).is_none_or(|p| {
            let v = &p.value_vec4;
            [v.x, v.y, v.z] == [plain; 3]
        })
    })
}

/// Whether `node`'s parent in the file is `parent` (a scene node index), or the scene's root
/// where it has none: no node the take leaves out stands between two joints.
fn parented_plainly(scene: &ufbx::Scene, node: &ufbx::Node, parent: Option<usize>) -> bool {
    let above = node.parent.as_ref();
    match (parent, above) {
        (None, Some(p)) => p.is_root,
        (Some(p), Some(q)) => q.element.typed_id as usize == p && !scene.nodes[p].is_root,
        (_, None) => false,
    }
}

/// Whether a property named `name` is part of a node's transform (animated, a take that keys
/// it is not plain).
fn is_transform_property(name: &str) -> bool {
    name == "RotationOrder"
        || name == "InheritType"
        || PLAIN_PROPERTIES.iter().any(|&(plain, _)| plain == name)
}

/// The BVH order of an FBX Euler order: FBX names the axes in the order they apply (eEulerXYZ
/// turns about X first), BVH lists the outermost first, so each is the other read backwards.
fn bvh_order(order: ufbx::RotationOrder) -> Option<RotationOrder> {
    use ufbx::RotationOrder as Fbx;
    Some(match order {
        Fbx::Xyz => RotationOrder::Zyx,
        Fbx::Xzy => RotationOrder::Yzx,
        Fbx::Yzx => RotationOrder::Xzy,
        Fbx::Yxz => RotationOrder::Zxy,
        Fbx::Zxy => RotationOrder::Yxz,
        Fbx::Zyx => RotationOrder::Xyz,
        Fbx::Spheric => return None,
    })
}

/// The three curves of `value`, one key at each of the `count` frames from `begin` at `fps`
/// (within a ten-thousandth of a frame), as 32-bit values; `None` when a curve is missing, a
/// key falls between frames, a value is not finite, or the keys' times are not exactly `times`
/// (the first curve's, which `times` takes when it is `None`).
fn keys(
    value: &ufbx::AnimValue,
    begin: f64,
    count: usize,
    fps: f64,
    times: &mut Option<Vec<f64>>,
) -> Option<[Vec<f32>; 3]> {
    let mut out: [Vec<f32>; 3] = Default::default();
    for (axis, curve) in value.curves.iter().enumerate() {
        let curve = curve.as_ref()?;
        let keys = &curve.keyframes;
        if keys.len() != count {
            return None;
        }
        let at: Vec<f64> = keys.iter().map(|key| key.time).collect();
        match times {
            Some(times) if *times != at => return None,
            Some(_) => {}
            None => {
                let on_frames = at
                    .iter()
                    .enumerate()
                    .all(|(f, time)| ((time - begin) * fps - f as f64).abs() <= 1e-4);
                if !on_frames {
                    return None;
                }
                *times = Some(at);
            }
        }
        let values: Vec<f32> = keys.iter().map(|key| key.value as f32).collect();
        if !values.iter().all(|v| v.is_finite()) {
            return None;
        }
        out[axis] = values;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::bvh_order;
    use crate::model::euler::compose;

    /// FBX's eEulerXYZ applies X, then Y, then Z: R = Rz·Ry·Rx, BVH's `Zrotation Yrotation
    /// Xrotation`; each of the six orders so.
    #[test]
    fn fbx_orders_are_bvh_orders_read_backwards() {
        use ufbx::RotationOrder as Fbx;
        let (x, y, z) = (0.3f64, -0.7, 1.1);
        let (rx, ry, rz) = (
            glam::DQuat::from_rotation_x(x),
            glam::DQuat::from_rotation_y(y),
            glam::DQuat::from_rotation_z(z),
        );
        for (fbx, applied) in [
            (Fbx::Xyz, rz * ry * rx),
            (Fbx::Xzy, ry * rz * rx),
            (Fbx::Yzx, rx * rz * ry),
            (Fbx::Yxz, rz * rx * ry),
            (Fbx::Zxy, ry * rx * rz),
            (Fbx::Zyx, rx * ry * rz),
        ] {
            let order = bvh_order(fbx).unwrap();
            let angles = crate::model::euler::axes(order).map(|a| [x, y, z][a]);
            assert!(
                compose(angles, order).dot(applied).abs() > 1.0 - 1e-15,
                "{fbx:?}"
            );
        }
        assert_eq!(bvh_order(Fbx::Spheric), None);
    }
}
