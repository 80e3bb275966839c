//! What an ASF file says, as read: its units, root, bones and tree. A file of their own, so
//! that the skeleton beside it takes them from a sibling rather than from the reader above.

use crate::model::skeleton::Channel;

/// One degree of freedom as the ASF names it.
///
/// ```
/// use bvhview::acclaim::{asf::Dof, load_asf};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let asf = load_asf("tests/data/asf_amc/heiden_12.asf".as_ref(), 1 << 20)?;
/// // `order TX TY TZ RX RY RZ`
/// assert_eq!(asf.root.order, [Dof::Tx, Dof::Ty, Dof::Tz, Dof::Rx, Dof::Ry, Dof::Rz]);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dof {
    /// `rx`: a rotation about X.
    Rx,
    /// `ry`: a rotation about Y.
    Ry,
    /// `rz`: a rotation about Z.
    Rz,
    /// `tx`: a translation along X.
    Tx,
    /// `ty`: a translation along Y.
    Ty,
    /// `tz`: a translation along Z.
    Tz,
}

impl Dof {
    pub(super) fn parse(text: &str) -> Option<Dof> {
        Some(match text.to_ascii_lowercase().as_str() {
            "rx" => Dof::Rx,
            "ry" => Dof::Ry,
            "rz" => Dof::Rz,
            "tx" => Dof::Tx,
            "ty" => Dof::Ty,
            "tz" => Dof::Tz,
            _ => return None,
        })
    }

    pub(super) fn channel(self) -> Channel {
        match self {
            Dof::Rx => Channel::Xrotation,
            Dof::Ry => Channel::Yrotation,
            Dof::Rz => Channel::Zrotation,
            Dof::Tx => Channel::Xposition,
            Dof::Ty => Channel::Yposition,
            Dof::Tz => Channel::Zposition,
        }
    }

    pub(super) fn is_rotation(self) -> bool {
        matches!(self, Dof::Rx | Dof::Ry | Dof::Rz)
    }
}

/// `:units`.
///
/// ```
/// use bvhview::acclaim::load_asf;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let asf = load_asf("tests/data/asf_amc/heiden_12.asf".as_ref(), 1 << 20)?;
/// assert_eq!(asf.units.length, 0.45); // `length 0.45`
/// assert!(asf.units.degrees); // `angle deg`
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Units {
    /// `mass`: the mass unit (1 when the file does not say).
    pub mass: f64,
    /// `length`: the length unit the file states (CMU's `0.45`; 1 when the file does not say).
    pub length: f64,
    /// `angle deg` (true) or `angle rad`.
    pub degrees: bool,
}

/// `:root`.
///
/// ```
/// use bvhview::acclaim::load_asf;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let asf = load_asf("tests/data/asf_amc/heiden_12.asf".as_ref(), 1 << 20)?;
/// assert_eq!(asf.root.order.len(), 6); // `order TX TY TZ RX RY RZ`
/// assert_eq!(asf.root.axis_order, [0, 1, 2]); // `axis XYZ`
/// assert_eq!(asf.root.position, [0.0; 3]);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Root {
    /// The AMC root line's values, in this order.
    pub order: Vec<Dof>,
    /// The order of the orientation's rotations (`axis XYZ`).
    pub axis_order: [usize; 3],
    /// `position`: where the root starts, in file units.
    pub position: [f64; 3],
    /// Degrees.
    pub orientation: [f64; 3],
}

/// One `begin … end` block of `:bonedata`.
///
/// ```
/// use bvhview::acclaim::load_asf;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let asf = load_asf("tests/data/asf_amc/heiden_12.asf".as_ref(), 1 << 20)?;
/// let femur = asf.bones.iter().find(|bone| bone.name == "lfemur").unwrap();
/// assert_eq!((femur.id, femur.axis), (Some(2), [0.0, 0.0, 20.0]));
/// assert_eq!(femur.dof.len(), femur.limits.len()); // `dof rx ry rz`, one limit each
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Bone {
    /// `id`, if the block has one.
    pub id: Option<i64>,
    /// `name`: how the hierarchy and the AMC lines call the bone.
    pub name: String,
    /// `direction`: the unit vector from the bone's start to its end, in world axes.
    pub direction: [f64; 3],
    /// `length`: how far the bone's end is from its start, in file units.
    pub length: f64,
    /// Degrees.
    pub axis: [f64; 3],
    /// The order of the `axis` rotations (`XYZ` is `[0, 1, 2]`).
    pub axis_order: [usize; 3],
    /// The AMC line's values for this bone, in this order.
    pub dof: Vec<Dof>,
    /// `(min, max)` per dof, in degrees for rotations; infinite where the file says `inf`.
    pub limits: Vec<(f64, f64)>,
    /// Where the block starts, for messages.
    pub line: usize,
}

/// A parsed ASF file.
///
/// ```
/// use bvhview::acclaim::load_asf;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let asf = load_asf("tests/data/asf_amc/heiden_12.asf".as_ref(), 1 << 20)?;
/// assert_eq!(asf.bones.len(), 30);
/// assert_eq!(asf.children.len(), asf.bones.len());
/// let names: Vec<&str> = asf.root_children.iter().map(|&b| asf.bones[b].name.as_str()).collect();
/// assert!(names.contains(&"lhipjoint"));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Asf {
    /// `:units`.
    pub units: Units,
    /// `:root`.
    pub root: Root,
    /// `:bonedata`, in file order.
    pub bones: Vec<Bone>,
    /// Children of the root, as bone indices.
    pub root_children: Vec<usize>,
    /// Children of each bone, as bone indices.
    pub children: Vec<Vec<usize>>,
    /// What was read but changed or left out (a direction rescaled to a unit vector, a bone
    /// missing from `:hierarchy`).
    pub warnings: Vec<String>,
}
