//! The map from target joints to source joints: guessed by role, then by equal names,
//! overridden by `SRC = DST` pairs, shown as TOML, and checked for the joints every take needs.

use crate::io::error::Error;
use crate::io::error::quoted;
use crate::io::message::Message;
use crate::model::body::{Body, Limb, Role, Side, path_between};
use crate::model::skeleton::Skeleton;

/// The roles a take must have on both skeletons for a guessed map to stand (the chain).
pub const REQUIRED: [Role; 9] = [
    Role::Hips,
    Role::Limb(Side::Left, Limb::UpperArm),
    Role::Limb(Side::Left, Limb::ForeArm),
    Role::Limb(Side::Right, Limb::UpperArm),
    Role::Limb(Side::Right, Limb::ForeArm),
    Role::Limb(Side::Left, Limb::Thigh),
    Role::Limb(Side::Left, Limb::Shin),
    Role::Limb(Side::Right, Limb::Thigh),
    Role::Limb(Side::Right, Limb::Shin),
];

/// How a target joint came to its source joint.
///
/// ```
/// use bvhview::Take;
/// use bvhview::model::body::{Limb, Role, Side};
/// use bvhview::retarget::{How, Map, Target};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// let smpl = Target::load("smpl22", u64::MAX)?.skeleton;
/// let mut map = Map::guess(&take.skeleton, &smpl);
/// let knee = smpl.joints.iter().position(|j| j.name == "left_knee").unwrap();
/// assert_eq!(map.how[knee], Some(How::Role(Role::Limb(Side::Left, Limb::Shin))));
/// map.apply(&[("LeftUpLeg".into(), "left_knee".into())], &take.skeleton, &smpl)?;
/// assert_eq!(map.how[knee], Some(How::Given));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum How {
    /// The joint has this role in both skeletons' readings.
    Role(Role),
    /// The same name (prefixes and case aside) in both.
    Name,
    /// The one joint left between two mapped pairs, when the source has one there too (CMU's
    /// ASF `lhand` and its BVH's `LeftFingerBase`, `upperneck` and `Neck1`).
    Between,
    /// Given by the user (`--map`, `names=`).
    Given,
}

/// Which source joint drives each target joint.
///
/// ```
/// use bvhview::Take;
/// use bvhview::retarget::{Map, Target};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// let target = Target::load("smpl22", u64::MAX)?;
/// let map = Map::guess(&take.skeleton, &target.skeleton);
/// let elbow = target.skeleton.joints.iter().position(|j| j.name == "left_elbow").unwrap();
/// let source = map.source_of[elbow].unwrap();
/// assert_eq!(take.skeleton.joints[source].name, "LeftForeArm");
/// map.check("walk", &target.name)?; // every required role is mapped
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Map {
    /// One entry per target joint: the source joint it takes its rotation from.
    pub source_of: Vec<Option<usize>>,
    /// One entry per target joint: how its source joint was found (`None`: unmapped).
    pub how: Vec<Option<How>>,
    /// The roles of the two skeletons, as guessed.
    pub source_body: Body,
    /// The target skeleton's roles, as guessed.
    pub target_body: Body,
}

/// A name for matching: the part after the last `:` or `|`, in lower case.
pub(super) fn bare_name(name: &str) -> String {
    name.rsplit([':', '|'])
        .next()
        .unwrap_or(name)
        .to_ascii_lowercase()
}

impl Map {
    /// The guess: every role both skeletons have (the spine chains spread end to end over each
    /// other when their lengths differ), then joints of the same name among the rest.
    pub fn guess(source: &Skeleton, target: &Skeleton) -> Map {
        let source_body = Body::of(source);
        let target_body = Body::of(target);
        let count = target.joints.len();
        let mut map = Map {
            source_of: vec![None; count],
            how: vec![None; count],
            source_body,
            target_body,
        };
        for (role, t) in map.target_body.roles() {
            if matches!(role, Role::Spine(_)) {
                continue;
            }
            if let Some(s) = map.source_body.joint(role) {
                map.source_of[t] = Some(s);
                map.how[t] = Some(How::Role(role));
            }
        }
        // Spine chains: first to first, last to last, the others at the same fraction up.
        let (ts, ss) = (&map.target_body.spine, &map.source_body.spine);
        let pairs: Vec<(usize, usize)> = match (ts.len(), ss.len()) {
            (0, _) | (_, 0) => Vec::new(),
            (1, _) => vec![(0, 0)],
            (_, 1) => vec![(0, 0)],
            (t, s) if t <= s => (0..t)
                .map(|k| (k, (k * (s - 1) + (t - 1) / 2) / (t - 1)))
                .collect(),
            (t, s) => (0..s)
                .map(|k| ((k * (t - 1) + (s - 1) / 2) / (s - 1), k))
                .collect(),
        };
        for (k, i) in pairs {
            let t = map.target_body.spine[k];
            map.source_of[t] = Some(map.source_body.spine[i]);
            map.how[t] = Some(How::Role(Role::Spine(k)));
        }
        // The rest by name.
        let mut used = vec![false; source.joints.len()];
        for s in map.source_of.iter().flatten() {
            used[*s] = true;
        }
        let mut by_name = std::collections::HashMap::new();
        for (s, joint) in source.joints.iter().enumerate() {
            if !joint.end_site && !used[s] {
                by_name.entry(bare_name(&joint.name)).or_insert(s);
            }
        }
        for (t, joint) in target.joints.iter().enumerate() {
            if joint.end_site || map.source_of[t].is_some() {
                continue;
            }
            if let Some(s) = by_name.remove(&bare_name(&joint.name)) {
                map.source_of[t] = Some(s);
                map.how[t] = Some(How::Name);
                used[s] = true;
            }
        }
        // A joint left alone between two mapped pairs takes the one unused source joint
        // between their sources: the bone it moves is the bone that one moves.
        for (t, joint) in target.joints.iter().enumerate() {
            let Some(p) = joint.parent else { continue };
            if joint.end_site || map.source_of[t].is_some() {
                continue;
            }
            let Some(sp) = map.source_of[p] else { continue };
            for d in mapped_below(target, &map.source_of, t) {
                let Some(sd) = map.source_of[d] else { continue };
                if path_between(target, p, d) != [t] {
                    continue;
                }
                if let [x] = path_between(source, sp, sd)[..]
                    && !used[x]
                    && !source.joints[x].end_site
                {
                    map.source_of[t] = Some(x);
                    map.how[t] = Some(How::Between);
                    used[x] = true;
                    break;
                }
            }
        }
        map
    }

    /// Overrides the map with `(source joint, target joint)` pairs, by exact name; an empty
    /// target name unmaps the source joint. A source joint given a target loses the targets
    /// the guess gave it. Errors name the joint: one neither skeleton has, or two source
    /// joints given one target joint.
    pub fn apply(
        &mut self,
        pairs: &[(String, String)],
        source: &Skeleton,
        target: &Skeleton,
    ) -> Result<(), Error> {
        let find = |skeleton: &Skeleton, name: &str| {
            skeleton
                .joints
                .iter()
                .position(|j| !j.end_site && j.name == name)
        };
        let mut given: Vec<(usize, usize)> = Vec::new();
        for (src, dst) in pairs {
            let s = find(source, src).ok_or_else(|| {
                Error::usage(format!(
                    "map: the source has no joint named {} (it has {})",
                    quoted(src),
                    some_names(source)
                ))
            })?;
            if dst.is_empty() {
                // A later "leave out" wins over an earlier pair of the same joint.
                given.retain(|&(o, _)| o != s);
                for t in 0..self.source_of.len() {
                    if self.source_of[t] == Some(s) {
                        self.source_of[t] = None;
                        self.how[t] = None;
                    }
                }
                continue;
            }
            let t = find(target, dst).ok_or_else(|| {
                Error::usage(format!(
                    "map: the target has no joint named {} (it has {})",
                    quoted(dst),
                    some_names(target)
                ))
            })?;
            if let Some(&(other, _)) = given.iter().find(|&&(o, tt)| tt == t && o != s) {
                return Err(Error::usage(format!(
                    "map: two source joints, {} and {}, mapped to one target joint {}",
                    quoted(&source.joints[other].name),
                    quoted(src),
                    quoted(dst)
                )));
            }
            given.push((s, t));
        }
        for &(s, t) in &given {
            for other in 0..self.source_of.len() {
                if self.source_of[other] == Some(s) && self.how[other] != Some(How::Given) {
                    self.source_of[other] = None;
                    self.how[other] = None;
                }
            }
            self.source_of[t] = Some(s);
            self.how[t] = Some(How::Given);
        }
        Ok(())
    }

    /// Fails unless the chain is mapped: every [`REQUIRED`] role of the target has a source
    /// joint. A map the user gave joints to needs only two mapped joints.
    pub fn check(&self, source_name: &str, target_name: &str) -> Result<(), Error> {
        if self.how.contains(&Some(How::Given)) {
            if self.source_of.iter().flatten().count() >= 2 {
                return Ok(());
            }
            return Err(Error::usage(format!(
                "{target_name}: fewer than two joints mapped; nothing to retarget"
            )));
        }
        let missing = |body: &Body| -> Vec<String> {
            REQUIRED
                .iter()
                .filter(|&&r| body.joint(r).is_none())
                .map(|r| r.to_string())
                .collect()
        };
        for (name, body, what) in [
            (target_name, &self.target_body, "target"),
            (source_name, &self.source_body, "source"),
        ] {
            let missing = missing(body);
            if !missing.is_empty() {
                return Err(Error::usage(
                    Message::from(format!(
                        "{name}: the {what} has no mappable chain: no joint found for {} \
                         (name them with ",
                        missing.join(", ")
                    ))
                    .argument("map", Some("SRC=DST"))
                    .text(" or a map file)"),
                ));
            }
        }
        Ok(())
    }

    /// The map as text: TOML that `--map FILE` reads back (`"source" = "target"  # role`),
    /// then what stays unmapped on either side, as comments.
    pub fn show(&self, source: &Skeleton, target: &Skeleton) -> String {
        let quote = |s: &str| serde_json::to_string(s).unwrap_or_default();
        let mut text =
            String::from("# bvhview retarget map: \"source joint\" = \"target joint\"\n");
        for (t, s) in self.source_of.iter().enumerate() {
            let Some(s) = s else { continue };
            let how = match self.how[t] {
                Some(How::Role(role)) => role.to_string(),
                Some(How::Name) => "same name".to_string(),
                Some(How::Between) => "between".to_string(),
                Some(How::Given) => "given".to_string(),
                None => String::new(),
            };
            text.push_str(&format!(
                "{} = {}  # {how}\n",
                quote(&source.joints[*s].name),
                quote(&target.joints[t].name)
            ));
        }
        let unmapped: Vec<String> = target
            .joints
            .iter()
            .enumerate()
            .filter(|(t, j)| !j.end_site && self.source_of[*t].is_none())
            .map(|(_, j)| j.name.clone())
            .collect();
        let mut used = vec![false; source.joints.len()];
        for s in self.source_of.iter().flatten() {
            used[*s] = true;
        }
        let unused: Vec<String> = source
            .joints
            .iter()
            .enumerate()
            .filter(|(s, j)| !j.end_site && !used[*s])
            .map(|(_, j)| j.name.clone())
            .collect();
        text.push_str(&format!(
            "# target joints left at rest ({}): {}\n",
            unmapped.len(),
            if unmapped.is_empty() {
                "none".into()
            } else {
                unmapped.join(" ")
            }
        ));
        text.push_str(&format!(
            "# source joints not used ({}): {}\n",
            unused.len(),
            if unused.is_empty() {
                "none".into()
            } else {
                unused.join(" ")
            }
        ));
        text
    }
}

/// The first few joint names, for an error.
pub(super) fn some_names(skeleton: &Skeleton) -> String {
    let names: Vec<&str> = skeleton
        .joints
        .iter()
        .filter(|j| !j.end_site)
        .map(|j| j.name.as_str())
        .collect();
    let shown: Vec<String> = names.iter().take(8).map(|n| format!("{n:?}")).collect();
    if names.len() > 8 {
        format!("{} … ({} joints)", shown.join(", "), names.len())
    } else {
        shown.join(", ")
    }
}

/// Nearest mapped joints below `joint`: down each branch to the first mapped one.
pub(super) fn mapped_below(skeleton: &Skeleton, map: &[Option<usize>], joint: usize) -> Vec<usize> {
    let mut found = Vec::new();
    let mut stack: Vec<usize> = skeleton.joints[joint].children.clone();
    while let Some(j) = stack.pop() {
        if map[j].is_some() {
            found.push(j);
        } else {
            stack.extend(skeleton.joints[j].children.iter().copied());
        }
    }
    found.sort_unstable();
    found
}
