//! An ASF skeleton as bvhview's `Skeleton`: each bone's fixed axis, its degrees of freedom as
//! channels, and where each AMC value goes.

use super::parsed::{Asf, Bone, Dof};
use crate::acclaim::rotation::{axis_rotation, bone_joint};
use crate::model::skeleton::{Channel, Joint, RotationOrder, Skeleton, Source};
use glam::Vec3;

/// Where one AMC line's values go: the joint's first MOTION column, and per value the channel
/// slot (relative to it) it fills.
///
/// ```
/// use bvhview::acclaim::load_asf;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let asf = load_asf("tests/data/asf_amc/heiden_12.asf".as_ref(), 1 << 20)?;
/// let (skeleton, maps) = asf.to_skeleton();
/// assert_eq!((maps[0].name.as_str(), maps[0].first_channel), ("root", 0));
/// // `order TX TY TZ RX RY RZ`: translations in order, then rotations reversed.
/// assert_eq!(maps[0].slots, [0, 1, 2, 5, 4, 3]);
/// assert_eq!(maps[0].rotations, [false, false, false, true, true, true]);
/// assert_eq!(skeleton.joints[0].name, "root");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ValueMap {
    /// The AMC line's name: `root` or a bone's.
    pub name: String,
    /// The joint's first column in a MOTION row.
    pub first_channel: usize,
    /// Per value, the channel slot it fills, counted from `first_channel`.
    pub slots: Vec<usize>,
    /// Per value: a rotation (converted from radians when the file uses them) or a translation.
    pub rotations: Vec<bool>,
}

impl Asf {
    /// The skeleton the ASF/AMC article describes, as joints (a bone starts at its parent's end,
    /// turning about its fixed axis), and for each AMC line name (the root first, then bones in
    /// :bonedata order) where its values go.
    pub fn to_skeleton(&self) -> (Skeleton, Vec<ValueMap>) {
        let mut joints: Vec<Joint> = Vec::new();
        let mut maps = Vec::new();
        let mut column = 0;

        // The root: translations in their listed order, then rotations reversed.
        let mut root = bone_joint(
            "root",
            Some(axis_rotation(self.root.orientation, self.root.axis_order)),
        );
        root.offset = Vec3::from_array(self.root.position.map(|v| v as f32));
        let (channels, slots) = channels_for(&self.root.order);
        root.channels = channels;
        root.rotation_order = RotationOrder::get_flags(&root.channels);
        root.first_channel = column;
        column += root.channels.len();
        let rotations = self.root.order.iter().map(|d| d.is_rotation()).collect();
        maps.push(ValueMap {
            name: "root".into(),
            first_channel: root.first_channel,
            slots,
            rotations,
        });
        joints.push(root);

        let mut bone_maps: Vec<Option<ValueMap>> = vec![None; self.bones.len()];
        // Pre-order from the root, children in hierarchy order.
        // (bone, its parent's joint, its parent bone if it is not the root)
        let mut stack: Vec<(usize, usize, Option<usize>)> = self
            .root_children
            .iter()
            .rev()
            .map(|&b| (b, 0, None))
            .collect();
        while let Some((bone_index, parent_joint, parent_bone)) = stack.pop() {
            let bone = &self.bones[bone_index];
            let mut joint = bone_joint(&bone.name, Some(axis_rotation(bone.axis, bone.axis_order)));
            joint.parent = Some(parent_joint);
            // A bone starts where its parent bone ends; bones under the root start at the root.
            joint.offset = parent_bone.map_or(Vec3::ZERO, |p| bone_vector(&self.bones[p]));
            let (channels, slots) = channels_for(&bone.dof);
            joint.channels = channels;
            joint.rotation_order = RotationOrder::get_flags(&joint.channels);
            joint.first_channel = column;
            column += joint.channels.len();
            bone_maps[bone_index] = Some(ValueMap {
                name: bone.name.clone(),
                first_channel: joint.first_channel,
                slots,
                rotations: bone.dof.iter().map(|d| d.is_rotation()).collect(),
            });
            let index = joints.len();
            joints[parent_joint].children.push(index);
            joints.push(joint);
            if self.children[bone_index].is_empty() {
                let mut end = Joint::new("Site".into(), Some(index));
                end.end_site = true;
                end.offset = bone_vector(bone);
                end.first_channel = column;
                let end_index = joints.len();
                joints[index].children.push(end_index);
                joints.push(end);
            } else {
                for &child in self.children[bone_index].iter().rev() {
                    stack.push((child, index, Some(bone_index)));
                }
            }
        }
        maps.extend(bone_maps.into_iter().flatten());
        (
            Skeleton {
                joints,
                source: Source::Acclaim,
                y_up_stated: false,
            },
            maps,
        )
    }
}

/// `direction × length`.
pub(super) fn bone_vector(bone: &Bone) -> Vec3 {
    Vec3::from_array(bone.direction.map(|d| (d * bone.length) as f32))
}

/// Channels for a dof list (translations as listed, then rotations reversed, so that the
/// rotations multiply as Acclaim applies them) and, per dof, its channel slot.
pub(super) fn channels_for(dofs: &[Dof]) -> (Vec<Channel>, Vec<usize>) {
    let mut channels: Vec<Channel> = dofs
        .iter()
        .filter(|d| !d.is_rotation())
        .map(|d| d.channel())
        .collect();
    channels.extend(
        dofs.iter()
            .rev()
            .filter(|d| d.is_rotation())
            .map(|d| d.channel()),
    );
    let slots = dofs
        .iter()
        .map(|d| {
            channels
                .iter()
                .position(|&c| c == d.channel())
                .expect("every dof has a channel")
        })
        .collect();
    (channels, slots)
}
