//! A skeleton's joints named as a family names them (`convert --names smpl22`), by the
//! retarget's map.

use crate::io::error::Error;
use crate::model::skeleton::Skeleton;
use crate::retarget::map::Map;

/// Every joint of `skeleton` that the reading of the body maps onto a joint of `family` (the
/// retarget's map, [`crate::retarget::Map::guess`]: roles first, then equal names) takes that
/// joint's name; the others keep theirs. What changed is said, once. Refused when a name would
/// then be two joints'.
///
/// ```
/// use bvhview::Take;
/// use bvhview::retarget::names_of_family;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = Take::open("tests/data/bvh/bvh11_131_01.bvh")?;
/// let smpl = Take::open("smpl22")?;
/// let (named, said) = names_of_family(&walk.skeleton, &smpl.skeleton)?;
/// assert_eq!(named.joints[0].name, "pelvis"); // was Hips
/// assert!(named.joints.iter().any(|j| j.name == "left_knee"));
/// assert!(said[0].starts_with("22 joints take"));
/// # Ok(())
/// # }
/// ```
pub fn names_of_family(
    skeleton: &Skeleton,
    family: &Skeleton,
) -> Result<(Skeleton, Vec<String>), Error> {
    let map = Map::guess(skeleton, family);
    let mut named = skeleton.clone();
    let mut taken = vec![false; skeleton.joints.len()];
    let mut changed = Vec::new();
    for (t, source) in map.source_of.iter().enumerate() {
        let Some(s) = *source else { continue };
        if taken[s] || skeleton.joints[s].end_site || family.joints[t].end_site {
            continue;
        }
        taken[s] = true;
        let name = &family.joints[t].name;
        if named.joints[s].name != *name {
            changed.push(format!("{} → {name}", skeleton.joints[s].name));
            named.joints[s].name = name.clone();
        }
    }
    for (i, joint) in named.joints.iter().enumerate() {
        if joint.end_site {
            continue;
        }
        if let Some(k) = named.joints[..i]
            .iter()
            .position(|other| !other.end_site && other.name == joint.name)
        {
            return Err(Error::usage(format!(
                "the names of the family: '{}' and '{}' would both be named '{}'",
                crate::limits::quoted(&skeleton.joints[k].name),
                crate::limits::quoted(&skeleton.joints[i].name),
                crate::limits::quoted(&joint.name)
            )));
        }
    }
    let said = match changed.len() {
        0 => Vec::new(),
        n => vec![format!(
            "{n} joints take the family's names ({}{})",
            changed[..n.min(3)].join(", "),
            if n > 3 { ", …" } else { "" }
        )],
    };
    Ok((named, said))
}
