//! The joints as FBX writes them: each one's rest translation, Euler order and keys, taken from
//! the take's channels.

use super::ids::{AXES, PROPERTIES, attribute_id, curve_id, curve_node_id, model_id};
use super::records::{Records, Value};
use crate::io::error::Error;
use crate::model::euler;
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, joint_translation, local_rotation_f64};
use crate::model::skeleton::{RotationOrder, Skeleton, export_name};

/// One joint (or End Site) as a `Model`.
pub(super) struct Bone {
    /// Its name, as `positions` names it (an End Site is `<parent>_End`).
    pub(super) name: String,
    pub(super) parent: Option<usize>,
    /// The rest translation (the OFFSET), in written units.
    pub(super) translation: [f64; 3],
    /// FBX's `RotationOrder` (0 is XYZ, FBX's default).
    order: i32,
    /// Per frame, the translation in written units, when the joint has position channels.
    moves: Option<Vec<[f32; 3]>>,
    /// Per frame, the rotation in degrees about X, Y and Z, when it has rotation channels.
    turns: Option<Vec<[f32; 3]>>,
}

impl Bone {
    /// What is not finite in it (an OFFSET or a key past 32-bit floats, in written units), if
    /// anything: `joint 'Hips', frame 3: a translation that is not finite`.
    pub(super) fn not_finite(&self) -> Option<String> {
        let name = crate::io::error::quoted(&self.name);
        // Written as 64-bit, read back as 32-bit: past 3.4e38 in written units is refused.
        if !self
            .translation
            .iter()
            .all(|v| v.abs() <= f64::from(f32::MAX))
        {
            return Some(format!(
                "joint {name}: an OFFSET that is not finite in centimetres as a 32-bit float"
            ));
        }
        for (what, keys) in [("translation", &self.moves), ("rotation", &self.turns)] {
            let frame = keys
                .iter()
                .flatten()
                .position(|k| !k.iter().all(|v| v.is_finite()));
            if let Some(frame) = frame {
                return Some(format!(
                    "joint {name}, frame {frame}: a {what} that is not finite"
                ));
            }
        }
        None
    }

    /// A node at the origin that never moves (what a mesh bone bound to no joint links to).
    pub(super) fn fixed(name: &str) -> Bone {
        Bone {
            name: name.to_string(),
            parent: None,
            translation: [0.0; 3],
            order: 0,
            moves: None,
            turns: None,
        }
    }

    /// Curves this bone's motion takes: three per animated property.
    pub(super) fn curve_count(&self) -> usize {
        3 * self.animated_properties().count()
    }

    /// The animated properties (0 translation, 1 rotation).
    pub(super) fn animated_properties(&self) -> impl Iterator<Item = usize> + '_ {
        [self.moves.is_some(), self.turns.is_some()]
            .into_iter()
            .enumerate()
            .filter_map(|(p, animated)| animated.then_some(p))
    }

    /// Its `NodeAttribute` and `Model`.
    pub(super) fn write_objects(&self, out: &mut Records, index: usize) -> Result<(), Error> {
        let attribute = format!("{}\0\x01NodeAttribute", self.name);
        out.open(
            "NodeAttribute",
            &[
                Value::I64(attribute_id(index)),
                Value::Str(&attribute),
                Value::Str("LimbNode"),
            ],
        )?;
        out.leaf("TypeFlags", &[Value::Str("Skeleton")])?;
        out.close()?;
        let model = format!("{}\0\x01Model", self.name);
        out.open(
            "Model",
            &[
                Value::I64(model_id(index)),
                Value::Str(&model),
                Value::Str("LimbNode"),
            ],
        )?;
        out.leaf("Version", &[Value::I32(232)])?;
        out.open("Properties70", &[])?;
        if self.order != 0 {
            out.property("RotationOrder", ["enum", "", ""], &[Value::I32(self.order)])?;
            // Maya and the FBX SDK apply a rotation order only to a node whose rotation is
            // "active".
            out.property("RotationActive", ["bool", "", ""], &[Value::I32(1)])?;
        }
        // No scale is written: the inheritance is the SDK's default for joints.
        out.property("InheritType", ["enum", "", ""], &[Value::I32(1)])?;
        let [x, y, z] = self.translation;
        out.property(
            "Lcl Translation",
            ["Lcl Translation", "", "A"],
            &[Value::F64(x), Value::F64(y), Value::F64(z)],
        )?;
        let zero = [Value::F64(0.0); 3];
        out.property("Lcl Rotation", ["Lcl Rotation", "", "A"], &zero)?;
        let one = [Value::F64(1.0); 3];
        out.property("Lcl Scaling", ["Lcl Scaling", "", "A"], &one)?;
        out.close()?;
        out.leaf("Shading", &[Value::Bool(true)])?;
        out.leaf("Culling", &[Value::Str("CullingOff")])?;
        out.close()
    }

    /// Its curve nodes and curves, keyed at `times`.
    pub(super) fn write_curves(
        &self,
        out: &mut Records,
        index: usize,
        times: &[i64],
    ) -> Result<(), Error> {
        for (p, keys) in [&self.moves, &self.turns].into_iter().enumerate() {
            let Some(keys) = keys else { continue };
            let node = format!("{}\0\x01AnimCurveNode", PROPERTIES[p].1);
            out.open(
                "AnimationCurveNode",
                &[
                    Value::I64(curve_node_id(index, p)),
                    Value::Str(&node),
                    Value::Str(""),
                ],
            )?;
            out.open("Properties70", &[])?;
            for (axis, name) in AXES.iter().enumerate() {
                let first = keys.first().map_or(0.0, |k| f64::from(k[axis]));
                out.property(name, ["Number", "", "A"], &[Value::F64(first)])?;
            }
            out.close()?;
            out.close()?;
            for axis in 0..3 {
                let values: Vec<f32> = keys.iter().map(|k| k[axis]).collect();
                write_curve(out, curve_id(index, p, axis), times, &values)?;
            }
        }
        Ok(())
    }
}

/// One `AnimationCurve`: linear keys at `times` with `values`.
fn write_curve(out: &mut Records, id: i64, times: &[i64], values: &[f32]) -> Result<(), Error> {
    out.open(
        "AnimationCurve",
        &[
            Value::I64(id),
            Value::Str("\0\x01AnimCurve"),
            Value::Str(""),
        ],
    )?;
    out.leaf("Default", &[Value::F64(0.0)])?;
    out.leaf("KeyVer", &[Value::I32(4009)])?;
    out.array("KeyTime", times)?;
    out.array("KeyValueFloat", values)?;
    // One attribute for every key: linear interpolation (FBX's eInterpolationLinear).
    out.array("KeyAttrFlags", &[LINEAR])?;
    out.array("KeyAttrDataFloat", &[0.0f32; 4])?;
    out.array("KeyAttrRefCount", &[values.len() as i32])?;
    out.close()
}

/// `KeyAttrFlags` of a linear key.
const LINEAR: i32 = 0x0000_0004;

/// FBX's `RotationOrder` of a BVH rotation order. BVH lists the outermost rotation first
/// (`Zrotation Xrotation Yrotation` is Rz·Rx·Ry); FBX names them in the order they apply
/// (eEulerYXZ: Y first, then X, then Z), so each is the other read backwards.
fn fbx_order(order: RotationOrder) -> i32 {
    match order {
        RotationOrder::Zyx => 0, // eEulerXYZ
        RotationOrder::Yzx => 1, // eEulerXZY
        RotationOrder::Zxy => 3, // eEulerYXZ
        RotationOrder::Xzy => 2, // eEulerYZX
        RotationOrder::Yxz => 4, // eEulerZXY
        RotationOrder::Xyz => 5, // eEulerZYX
    }
}

/// Each joint's name as the file holds it and a reader takes it back: one FBX can hold
/// ([`fbx_name`]), trimmed, `node<k>` for an empty one (as bvhview's reader names it,
/// `model::baked`), and a joint's name met again — in the order a reader meets the nodes, by
/// depth, then in file order — given Blender's suffix `.001`; an End Site is its parent's name
/// so written with `_End` (as `positions` names it; the End Sites of one joint share it, which
/// FBX allows and a reader reads back as End Sites of that joint). A take read back writes the
/// same names again.
fn reader_names(skeleton: &Skeleton) -> Result<Vec<String>, Error> {
    use std::collections::HashSet;
    let count = skeleton.joints.len();
    let mut depth = vec![0usize; count];
    for (i, joint) in skeleton.joints.iter().enumerate() {
        depth[i] = joint.parent.map_or(0, |p| depth[p] + 1);
    }
    let mut met: Vec<usize> = (0..count).collect();
    met.sort_by_key(|&i| depth[i]);
    let own = |k: usize, i: usize| {
        crate::model::baked::joint_name(&fbx_name(&skeleton.joints[i].name), k)
            .map_err(|why| Error::usage(format!("cannot write FBX: {why}")))
    };
    let mut taken: HashSet<String> = HashSet::new();
    for (k, &i) in met.iter().enumerate() {
        if !skeleton.joints[i].end_site {
            taken.insert(own(k, i)?);
        }
    }
    let mut names = vec![String::new(); count];
    let mut seen: HashSet<String> = HashSet::new();
    for (k, &i) in met.iter().enumerate() {
        let joint = &skeleton.joints[i];
        let name = match (joint.end_site, joint.parent) {
            (true, Some(parent)) => format!("{}_End", names[parent]),
            _ => {
                let name = own(k, i)?;
                if seen.contains(&name) {
                    (1..)
                        .map(|n| format!("{name}.{n:03}"))
                        .find(|candidate| !taken.contains(candidate) && !seen.contains(candidate))
                        .expect("some suffix is free")
                } else {
                    name
                }
            }
        };
        taken.insert(name.clone());
        seen.insert(name.clone());
        names[i] = name;
    }
    Ok(names)
}

/// A name FBX can hold: no control character (FBX separates a name from its class with
/// `\0\x01`); each one becomes `_`.
pub(super) fn fbx_name(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_control() { '_' } else { c })
        .collect()
}

/// A Z-up take turned to Y up as it is written, exactly: every point (x, y, z) becomes
/// (x, z, −y), a quarter turn Q about X. A joint's rotation R becomes Q·R·Q⁻¹, whose channels
/// are the same angles about the turned axes: about X stays about X, about Y becomes about −Z
/// (the angle negated), about Z becomes about Y. The channel values are moved and negated, never
/// split again, and the Euler order is the turned axes' order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Turn {
    z_up: bool,
}

impl Turn {
    /// The turn that stands a take of `up` up in Y (none for a Y-up take).
    pub(super) fn to_y_up(up: crate::model::pose::Up) -> Turn {
        Turn {
            z_up: up == crate::model::pose::Up::Z,
        }
    }

    /// The axis (0 X, 1 Y, 2 Z) and sign that a value along or about `axis` goes to.
    pub(super) fn axis(self, axis: usize) -> (usize, f32) {
        match (self.z_up, axis) {
            (false, a) | (true, a @ 0) => (a, 1.0),
            (true, 1) => (2, -1.0),
            (true, _) => (1, 1.0),
        }
    }

    /// A point or direction turned.
    pub(super) fn point(self, v: [f64; 3]) -> [f64; 3] {
        let mut out = [0.0; 3];
        for (a, value) in v.into_iter().enumerate() {
            let (to, sign) = self.axis(a);
            out[to] = value * f64::from(sign);
        }
        out
    }

    /// The matrix of the turn (entries 0 and ±1: products with it are exact).
    pub(super) fn matrix(self) -> glam::DMat4 {
        let [x, y, z] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            .map(|column| glam::DVec3::from_array(self.point(column)).extend(0.0));
        glam::DMat4::from_cols(x, y, z, glam::DVec4::W)
    }

    /// Q·q·Q⁻¹: the rotation about the turned axis, by the same angle.
    fn rotation(self, q: glam::DQuat) -> glam::DQuat {
        let [x, y, z] = self.point([q.x, q.y, q.z]);
        glam::DQuat::from_xyzw(x, y, z, q.w)
    }

    /// The Euler order of `order`'s rotation once turned.
    fn order(self, order: RotationOrder) -> RotationOrder {
        let mut axes = [0; 3];
        for (slot, letter) in axes.iter_mut().zip(order.letters().bytes()) {
            *slot = self.axis(usize::from(letter - b'x')).0;
        }
        RotationOrder::from_axes(axes).unwrap_or(order)
    }
}

/// Every joint of `skeleton` as a bone, its keys from `motion`, lengths times `scale`, turned
/// by `turn`; and the names changed on the way.
pub(super) fn of(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    scale: f64,
    turn: Turn,
) -> Result<(Vec<Bone>, Vec<String>), Error> {
    let baked = crate::edit::baked_for_bvh(skeleton, motion)?;
    let (skeleton, motion) = baked.as_ref().map_or((skeleton, motion), |(s, m)| (s, m));
    let mut renamed = Vec::new();
    let names = reader_names(skeleton)?;
    let bones = (0..skeleton.joints.len())
        .map(|i| {
            let joint = &skeleton.joints[i];
            let written = export_name(skeleton, i);
            let name = names[i].clone();
            if name != written {
                renamed.push(format!("{written:?} → {name:?}"));
            }
            // Rounded to 32 bits, as the keys are: read back as a take's OFFSET (32-bit), it
            // writes the same 64-bit value again.
            let offset = turn
                .point(joint.offset.to_array().map(|v| f64::from(v) * scale))
                .map(|v| f64::from(v as f32));
            let has = |rotation: bool| joint.channels.iter().any(|c| c.is_rotation() == rotation);
            let frames = || (0..motion.frame_count()).map(|f| joint.values(motion.frame(f)));
            let animated = motion.frame_count() > 0;
            let moves = (animated && has(false)).then(|| {
                frames()
                    .map(|values| {
                        let t = joint_translation(joint, values, mode).to_array();
                        turn.point(t.map(|v| f64::from(v) * scale))
                            .map(|v| v as f32)
                    })
                    .collect()
            });
            // A leaf joint without channels that is not an End Site keys a rotation of 0: a
            // leaf never keyed reads back as an End Site.
            let keyless_leaf = !joint.end_site && joint.children.is_empty() && !has(false);
            let (order, turns) = match (animated && has(true), joint.rotation_order) {
                (false, _) if animated && keyless_leaf => {
                    (0, Some(vec![[0.0; 3]; motion.frame_count()]))
                }
                (false, _) => (0, None),
                (true, Some(order)) => (
                    fbx_order(turn.order(order)),
                    Some(continuous(
                        frames()
                            .map(|values| {
                                let mut xyz = [0.0f32; 3];
                                for (channel, &value) in joint.channels.iter().zip(values) {
                                    if channel.is_rotation() {
                                        let (axis, sign) = turn.axis(channel.axis());
                                        xyz[axis] = sign * value;
                                    }
                                }
                                xyz
                            })
                            .collect(),
                    )),
                ),
                // Two rotation channels, or one axis twice: the rotation they make, split
                // into FBX's default order (XYZ), continuous from frame to frame (and made so
                // as the other joints' keys are, which a second write of it does again).
                (true, None) => (0, Some(continuous(split_frames(joint, frames(), turn)))),
            };
            Bone {
                name,
                parent: joint.parent,
                translation: offset,
                order,
                moves,
                turns,
            }
        })
        .collect();
    Ok((bones, renamed))
}

/// `turns` (degrees per frame) with each angle moved by whole turns to within 180° of the frame
/// before, as [`split_frames`] keeps a split continuous: the same rotation at every key, and a
/// curve that does not spin the long way round between two frames where a channel passes ±180°
/// (FBX interpolates each angle on its own; three.js's FBXLoader, r187, also loses the key that
/// follows a step of 180° or more).
///
/// Each angle is first taken to within one turn of 0 by its exact remainder (`%` is exact in
/// floating point), so that a channel of 1e8 degrees keys the rotation it means: a reader
/// interpolating or taking the sine of the value as written loses it (ufbx's evaluation did,
/// found by fuzzing).
fn continuous(mut turns: Vec<[f32; 3]>) -> Vec<[f32; 3]> {
    for angle in turns.iter_mut().flatten() {
        *angle %= 360.0;
    }
    for f in 1..turns.len() {
        let before = turns[f - 1];
        for (angle, before) in turns[f].iter_mut().zip(before) {
            *angle = nearest_turn(*angle, before);
        }
    }
    turns
}

/// `angle` moved by whole turns into (before − 180°, before + 180°]: one value for every angle of
/// the same remainder (exactly half a turn away is always the one above), so that the values
/// written, read back and made continuous again are the same.
fn nearest_turn(angle: f32, before: f32) -> f32 {
    let (angle, before) = (f64::from(angle), f64::from(before));
    let mut moved = (angle + 360.0 * ((before - angle) / 360.0).round()) as f32;
    // Checked on the 32-bit value written: one rounded past an edge is moved back.
    for _ in 0..2 {
        let value = f64::from(moved);
        if value <= before - 180.0 {
            moved = (value + 360.0) as f32;
        } else if value > before + 180.0 {
            moved = (value - 360.0) as f32;
        } else {
            break;
        }
    }
    moved
}

/// Each frame's rotation of `joint`, turned by `turn`, split into X, Y and Z degrees of FBX's
/// XYZ order (BVH's `Zrotation Yrotation Xrotation`), continuous from frame to frame.
fn split_frames<'a>(
    joint: &crate::model::skeleton::Joint,
    frames: impl Iterator<Item = &'a [f32]>,
    turn: Turn,
) -> Vec<[f32; 3]> {
    let mut previous = None;
    frames
        .map(|values| {
            // Within a turn of 0 first (an exact remainder), as `continuous` takes them.
            let values: Vec<f32> = joint
                .channels
                .iter()
                .zip(values)
                .map(|(channel, &v)| if channel.is_rotation() { v % 360.0 } else { v })
                .collect();
            let angles = euler::split(
                turn.rotation(local_rotation_f64(joint, &values)),
                RotationOrder::Zyx,
                previous,
            );
            previous = Some(angles);
            // File order Z, Y, X.
            [angles[2], angles[1], angles[0]].map(|a| a.to_degrees() as f32)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{RotationOrder, Turn, continuous, fbx_name, fbx_order};

    /// Turned, each order's channels (moved to the turned axes, negated where the axis flips)
    /// make Q·R·Q⁻¹ for every order: the same rotation seen Y up, no split.
    #[test]
    fn a_z_up_rotation_turns_by_moving_its_channels() {
        use crate::model::euler::compose;
        let turn = Turn::to_y_up(crate::model::pose::Up::Z);
        let q = glam::DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2);
        assert!((turn.matrix() - glam::DMat4::from_quat(q)).abs_diff_eq(glam::DMat4::ZERO, 1e-15));
        for order in [
            RotationOrder::Zyx,
            RotationOrder::Yzx,
            RotationOrder::Zxy,
            RotationOrder::Xzy,
            RotationOrder::Yxz,
            RotationOrder::Xyz,
        ] {
            let angles = [0.3, -1.1, 2.5];
            let axes: Vec<usize> = order
                .letters()
                .bytes()
                .map(|c| usize::from(c - b'x'))
                .collect();
            let turned: Vec<f64> = axes
                .iter()
                .zip(angles)
                .map(|(&a, angle)| angle * f64::from(turn.axis(a).1))
                .collect();
            let want = q * compose(angles, order) * q.conjugate();
            let got = compose([turned[0], turned[1], turned[2]], turn.order(order));
            assert!(
                want.dot(got).abs() > 1.0 - 1e-12,
                "{order:?}: {want} vs {got}"
            );
        }
        let none = Turn::to_y_up(crate::model::pose::Up::Y);
        assert_eq!(none.point([1.0, 2.0, 3.0]), [1.0, 2.0, 3.0]);
        assert_eq!(turn.point([1.0, 2.0, 3.0]), [1.0, 3.0, -2.0]);
    }

    #[test]
    fn angles_move_by_whole_turns_to_within_half_a_turn_of_the_frame_before() {
        let turns = vec![
            [-101.86, -80.77, -98.91],
            [132.67, -81.86, 136.8],
            [170.0, 10.0, -170.0],
        ];
        assert_eq!(
            continuous(turns),
            [
                [-101.86, -80.77, -98.91],
                [132.67 - 360.0, -81.86, 136.8 - 360.0],
                [170.0 - 360.0, 10.0, -170.0],
            ]
        );
    }

    /// Half a turn from the frame before is always the value above it, however the angle came:
    /// made continuous twice, keys are the same.
    #[test]
    fn half_a_turn_away_is_always_above_and_twice_continuous_is_once() {
        assert_eq!(super::nearest_turn(180.0, 0.0), 180.0);
        assert_eq!(super::nearest_turn(-180.0, 0.0), 180.0);
        assert_eq!(super::nearest_turn(540.0, 0.0), 180.0);
        assert_eq!(super::nearest_turn(-190.0, 0.0), 170.0);
        let turns = vec![
            [0.0, 10.0, 170.0],
            [-180.0, 190.0, -10.0],
            [540.0, -170.0, 350.0],
        ];
        let once = continuous(turns);
        assert_eq!(
            once,
            [
                [0.0, 10.0, 170.0],
                [180.0, 190.0, 350.0],
                [180.0, 190.0, 350.0]
            ]
        );
        assert_eq!(continuous(once.clone()), once);
    }

    #[test]
    fn names_lose_only_control_characters_and_orders_read_backwards() {
        assert_eq!(fbx_name("mixamorig:Hips"), "mixamorig:Hips");
        assert_eq!(fbx_name("a\0\x01b\nc"), "a__b_c");
        assert_eq!(fbx_order(RotationOrder::Zxy), 3);
        assert_eq!(fbx_order(RotationOrder::Zyx), 0);
        assert_eq!(fbx_order(RotationOrder::Xyz), 5);
    }
}
