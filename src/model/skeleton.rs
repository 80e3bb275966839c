//! The skeleton: joints in pre-order with parent indices, each with its channels in file order.
//!
//! C++: `class BVHJoint`. The article keeps a fixed array of 16 children and a 24-byte name per joint
//! and links them by pointers; here joints live in one `Vec` in the order the file lists them (the
//! article's pre-order), so the MOTION columns of a joint are one contiguous slice.

use glam::{Quat, Vec3};
use std::fmt;

/// One MOTION column's meaning, as written in a CHANNELS line.
///
/// ```
/// use bvhview::Channel;
///
/// assert_eq!(Channel::Zrotation.name(), "Zrotation");
/// assert_eq!(Channel::Zrotation.axis(), 2);
/// assert!(!Channel::Xposition.is_rotation());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    /// A translation along X.
    Xposition,
    /// A translation along Y.
    Yposition,
    /// A translation along Z.
    Zposition,
    /// A rotation about X, in degrees.
    Xrotation,
    /// A rotation about Y, in degrees.
    Yrotation,
    /// A rotation about Z, in degrees.
    Zrotation,
}

impl Channel {
    /// Reads a channel name; case does not matter (`Xrotation`, `XROTATION`).
    pub fn parse(name: &str) -> Option<Channel> {
        const ALL: [(&str, Channel); 6] = [
            ("Xposition", Channel::Xposition),
            ("Yposition", Channel::Yposition),
            ("Zposition", Channel::Zposition),
            ("Xrotation", Channel::Xrotation),
            ("Yrotation", Channel::Yrotation),
            ("Zrotation", Channel::Zrotation),
        ];
        ALL.iter()
            .find(|(text, _)| text.eq_ignore_ascii_case(name))
            .map(|&(_, channel)| channel)
    }

    /// The name a BVH file uses for this channel.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Xposition => "Xposition",
            Channel::Yposition => "Yposition",
            Channel::Zposition => "Zposition",
            Channel::Xrotation => "Xrotation",
            Channel::Yrotation => "Yrotation",
            Channel::Zrotation => "Zrotation",
        }
    }

    /// 0, 1 or 2 for the X, Y or Z axis.
    pub fn axis(self) -> usize {
        match self {
            Channel::Xposition | Channel::Xrotation => 0,
            Channel::Yposition | Channel::Yrotation => 1,
            Channel::Zposition | Channel::Zrotation => 2,
        }
    }

    /// Whether the channel is an angle (`Xrotation`, `Yrotation`, `Zrotation`).
    pub fn is_rotation(self) -> bool {
        matches!(
            self,
            Channel::Xrotation | Channel::Yrotation | Channel::Zrotation
        )
    }

    /// Whether the channel is a translation (`Xposition`, `Yposition`, `Zposition`).
    pub fn is_position(self) -> bool {
        !self.is_rotation()
    }
}

impl fmt::Display for Channel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// C++: the anonymous `enum { ZYX = 1, YZX = 2, ZXY = 3, XZY = 5, YXZ = 6, XYZ = 7 }` and
/// `BVHJoint::flags`: the order of a joint's three rotation channels. The article packs the three
/// axis letters into one number (`getFlags`); the discriminants keep its values so `print` writes
/// the same digits.
///
/// ```
/// use bvhview::{Channel, RotationOrder};
///
/// let channels = [Channel::Xposition, Channel::Zrotation, Channel::Xrotation, Channel::Yrotation];
/// let order = RotationOrder::get_flags(&channels).unwrap();
/// assert_eq!((order.letters(), order.flag()), ("zxy", 3)); // the article's ZXY = 3
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RotationOrder {
    /// `Zrotation Yrotation Xrotation`: the article's `ZYX = 1`.
    Zyx = 1,
    /// `Yrotation Zrotation Xrotation`: `YZX = 2`.
    Yzx = 2,
    /// `Zrotation Xrotation Yrotation`: `ZXY = 3`.
    Zxy = 3,
    /// `Xrotation Zrotation Yrotation`: `XZY = 5`.
    Xzy = 5,
    /// `Yrotation Xrotation Zrotation`: `YXZ = 6`.
    Yxz = 6,
    /// `Xrotation Yrotation Zrotation`: `XYZ = 7`.
    Xyz = 7,
}

impl RotationOrder {
    /// The article's flag value (1, 2, 3, 5, 6 or 7).
    pub fn flag(self) -> u8 {
        self as u8
    }

    /// Lower-case letters in file order, as the article's `printRecursive` writes them.
    pub fn letters(self) -> &'static str {
        match self {
            RotationOrder::Zyx => "zyx",
            RotationOrder::Yzx => "yzx",
            RotationOrder::Zxy => "zxy",
            RotationOrder::Xzy => "xzy",
            RotationOrder::Yxz => "yxz",
            RotationOrder::Xyz => "xyz",
        }
    }

    /// The order whose axes (0 = X, 1 = Y, 2 = Z) come in this sequence; `None` unless the three
    /// are distinct.
    pub fn from_axes(axes: [usize; 3]) -> Option<RotationOrder> {
        Some(match axes {
            [2, 1, 0] => RotationOrder::Zyx,
            [1, 2, 0] => RotationOrder::Yzx,
            [2, 0, 1] => RotationOrder::Zxy,
            [0, 2, 1] => RotationOrder::Xzy,
            [1, 0, 2] => RotationOrder::Yxz,
            [0, 1, 2] => RotationOrder::Xyz,
            _ => return None,
        })
    }

    /// C++: `BVH::getFlags`. The article reads the first letter of three words at fixed byte
    /// distances (`p`, `p+10`, `p+20`), which breaks on any other spacing and on position channels
    /// listed after rotations; here the order comes from the parsed channels, whatever their layout.
    /// `None` when the joint does not have exactly three rotation channels on distinct axes.
    pub fn get_flags(channels: &[Channel]) -> Option<RotationOrder> {
        let mut axes = [0usize; 3];
        let mut count = 0;
        for channel in channels.iter().filter(|c| c.is_rotation()) {
            if count == 3 {
                return None;
            }
            axes[count] = channel.axis();
            count += 1;
        }
        if count == 3 {
            RotationOrder::from_axes(axes)
        } else {
            None
        }
    }
}

/// C++: `class BVHJoint`: a joint or End Site. `x, y, z` become `offset`; `flags` becomes
/// `channels` (all of them, in file order) plus `rotation_order`; the 16-slot child array becomes
/// `children` with no limit, and the 24-byte name a `String`.
///
/// ```
/// use bvhview::Take;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_simple.bvh")?;
/// let root = &take.skeleton.joints[0];
/// assert_eq!(root.parent, None);
/// assert!(root.channels.len() >= 3);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// The name after `ROOT` or `JOINT` (exports call an End Site `<parent>_End`).
    pub name: String,
    /// The parent joint's index; `None` for a root.
    pub parent: Option<usize>,
    /// The children's indices, in file order.
    pub children: Vec<usize>,
    /// C++: `x, y, z`: the OFFSET from the parent, in file units.
    pub offset: Vec3,
    /// The CHANNELS, in file order (empty for an End Site).
    pub channels: Vec<Channel>,
    /// Index of this joint's first column in a MOTION row.
    pub first_channel: usize,
    /// Written `End Site` (or, by some exporters, `JOINT Site` with `CHANNELS 0` and no children).
    pub end_site: bool,
    /// The order of the three rotation channels; `None` unless the joint has exactly three, on
    /// distinct axes.
    pub rotation_order: Option<RotationOrder>,
    /// A fixed rotation C around the channels' rotation: local = T · C · R · C⁻¹. ASF bones have
    /// one (their `axis`); BVH joints never do.
    pub axis: Option<Quat>,
}

impl Joint {
    /// The axes (0 x, 1 y, 2 z) of the rotation channels, in file order.
    pub fn rotation_axes(&self) -> Vec<usize> {
        self.channels
            .iter()
            .filter(|c| c.is_rotation())
            .map(|c| c.axis())
            .collect()
    }

    /// [`Joint::axis`] in f64, normalised; the identity without one.
    pub fn axis_f64(&self) -> glam::DQuat {
        self.axis
            .map_or(glam::DQuat::IDENTITY, |c| c.as_dquat().normalize())
    }

    /// A joint called `name` under `parent`, at the parent's origin, with no channels, children
    /// or axis.
    pub fn new(name: String, parent: Option<usize>) -> Joint {
        Joint {
            name,
            parent,
            children: Vec::new(),
            offset: Vec3::ZERO,
            channels: Vec::new(),
            first_channel: 0,
            end_site: false,
            rotation_order: None,
            axis: None,
        }
    }

    /// This joint's values in one MOTION row.
    pub fn values<'a>(&self, frame: &'a [f32]) -> &'a [f32] {
        &frame[self.first_channel..self.first_channel + self.channels.len()]
    }
}

/// Where a skeleton came from, which decides how its points are named in exports.
///
/// ```
/// use bvhview::{Take, model::skeleton::Source};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let bvh = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// assert_eq!(bvh.skeleton.source, Source::Bvh);
/// assert!(bvh.point_names().contains(&"Neck_End".to_string()));
/// let asf = Take::open("tests/data/asf_amc/heiden_12.asf")?;
/// assert_eq!(asf.skeleton.source, Source::Acclaim);
/// assert!(asf.point_names().contains(&"lfemur".to_string())); // the femur's end point
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Source {
    /// Joints are named; End Sites are `<parent>_End`.
    #[default]
    Bvh,
    /// ASF bones: a joint sits at the start of its bone, and a bone's name labels its end point.
    Acclaim,
}

/// All joints of a file in pre-order (a parent always comes before its children).
///
/// ```
/// use bvhview::Take;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let skeleton = Take::open("tests/data/bvh/bvhparser_simple.bvh")?.skeleton;
/// let root = skeleton.roots().next().unwrap();
/// println!("{} has {} children", skeleton.joints[root].name, skeleton.joints[root].children.len());
/// for joint in &skeleton.joints {
///     if let Some(parent) = joint.parent {
///         assert!(skeleton.joints[parent].children.iter().any(|&c| skeleton.joints[c].name == joint.name));
///     }
/// }
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skeleton {
    /// Every joint and End Site, a parent before its children.
    pub joints: Vec<Joint>,
    /// The format it was read from, for how exports name its points.
    pub source: Source,
    /// The file states its axes and the reader turned them to bvhview's +Y up (glTF by its
    /// specification, FBX by its header): the up axis is read, never guessed from the motion (a
    /// fox spreads along its length). `false` for BVH and ASF, which state nothing.
    pub y_up_stated: bool,
}

impl Skeleton {
    /// Columns in one MOTION row.
    pub fn channel_count(&self) -> usize {
        self.joints.iter().map(|j| j.channels.len()).sum()
    }

    /// A short name for this skeleton's shape, the same in every run, build and machine: 12
    /// hex digits of a 64-bit FNV-1a hash of every joint's name and parent, in file order.
    /// `info` prints it; a map file keys one skeleton's pairs by it (`[skeleton.<fingerprint>]`).
    ///
    /// ```
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let walk = bvhview::Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
    /// let fingerprint = walk.skeleton.fingerprint();
    /// assert_eq!(fingerprint.len(), 12);
    /// // Motion, offsets and channels aside, the same joints give the same fingerprint.
    /// assert_eq!(walk.trim(0..2).skeleton.fingerprint(), fingerprint);
    /// # Ok(())
    /// # }
    /// ```
    pub fn fingerprint(&self) -> String {
        // FNV-1a, written out: std's hashers may change between releases, and eight lines do
        // not need a crate.
        let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |bytes: &[u8]| {
            for &b in bytes {
                hash ^= u64::from(b);
                hash = hash.wrapping_mul(0x0100_0000_01b3);
            }
        };
        for joint in &self.joints {
            eat(joint.name.as_bytes());
            eat(&[0]);
            eat(&joint.parent.map_or(u64::MAX, |p| p as u64).to_le_bytes());
        }
        format!("{:012x}", hash >> 16)
    }

    /// Indices of joints without a parent (BVH files usually have one).
    pub fn roots(&self) -> impl Iterator<Item = usize> + '_ {
        self.joints
            .iter()
            .enumerate()
            .filter(|(_, j)| j.parent.is_none())
            .map(|(i, _)| i)
    }

    /// How many of the joints are End Sites.
    pub fn end_site_count(&self) -> usize {
        self.joints.iter().filter(|j| j.end_site).count()
    }
}

/// The name an export uses for a joint: its own, or `<parent>_End` for an End Site.
pub fn export_name(skeleton: &Skeleton, index: usize) -> String {
    let joint = &skeleton.joints[index];
    match (joint.end_site, joint.parent) {
        (true, Some(parent)) => format!("{}_End", skeleton.joints[parent].name),
        _ => joint.name.clone(),
    }
}
