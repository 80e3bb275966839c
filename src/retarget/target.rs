//! The skeleton a take is put on: a file, or a built-in skeleton (`smpl22`).

use super::*;

/// What a refusal by [`Target::check_body`] ends with: how to go ahead anyway.
/// Python's messages read it as "`any_body` retargets it anyway".
pub const ANY_BODY: &str = "`--any-body` retargets it anyway";

/// The built-in target skeletons: `smpl22`, the 22 body joints of SMPL in the layout of
/// HumanML3D, AMASS and most text-to-motion models, in centimetres, T-pose, Y up, facing +z.
pub const BUILT_IN: &[(&str, &[u8])] = &[("smpl22", include_bytes!("../../assets/smpl22.bvh"))];

/// A built-in skeleton by name (see [`BUILT_IN`]), with its one rest frame.
pub fn built_in(name: &str) -> Option<(Skeleton, Motion)> {
    let (_, bytes) = BUILT_IN
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))?;
    let file = crate::bvh::load_bytes(bytes, name).ok()?;
    Some((file.skeleton, file.motion))
}

/// A skeleton to retarget onto: a file's or a built-in one, with its up axis and the name to
/// show in messages (`bvhview retarget --onto`, `dataset --onto`).
///
/// ```
/// use bvhview::Take;
/// use bvhview::retarget::Target;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let target = Target::load("smpl22", u64::MAX)?;
/// assert_eq!(target.name, "smpl22");
/// assert_eq!(target.skeleton.joints[0].name, "pelvis");
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?.trim(0..30);
/// let (skeleton, motion) = target.apply("walk", &take.skeleton, &take.motion, &[], 1)?;
/// assert_eq!(skeleton, target.skeleton);
/// assert_eq!(motion.frame_count(), 30);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    /// The name messages give it: the file's path, or the built-in skeleton's name.
    pub name: String,
    /// The skeleton takes are put on.
    pub skeleton: Skeleton,
    /// Its up axis: its take's guessed stance's, or its rest pose's (see [`Target::new`]).
    pub up: Up,
    /// Five frames spread over its take (none for a rest pose alone): how it stands, for
    /// [`Target::check_body`] (a rig's rest pose may lie down where its takes stand).
    poses: Motion,
}

impl Target {
    /// `onto` as a file (.bvh, or .asf: only the skeleton is used) when it exists, else a
    /// built-in skeleton's name (see [`BUILT_IN`]).
    pub fn load(onto: &str, max_size: u64) -> Result<Target, Error> {
        let path = std::path::Path::new(onto);
        if !path.exists() {
            if let Some((skeleton, motion)) = built_in(onto) {
                return Ok(Target::new(onto.to_string(), skeleton, &motion));
            }
            if crate::take::extension(path).is_empty() {
                let names: Vec<&str> = BUILT_IN.iter().map(|(n, _)| *n).collect();
                return Err(Error::Usage(format!(
                    "--onto {onto}: neither a file nor a built-in skeleton ({})",
                    names.join(", ")
                )));
            }
        }
        let loaded =
            crate::take::load_checked(path, None, None, crate::io::parallel::cores(), max_size)?;
        Ok(Target::new(
            path.display().to_string(),
            loaded.skeleton,
            &loaded.motion,
        ))
    }

    /// A target whose up axis is its take's, or its rest pose's when it has one frame or none.
    pub fn new(name: String, skeleton: Skeleton, motion: &Motion) -> Target {
        let up = if motion.frame_count() > 1 {
            crate::model::stance::Stance::guess(&skeleton, motion, OffsetMode::Replace, None).up
        } else if Body::of(&skeleton).legs_not_two(&skeleton).is_some() {
            // No legs or many: no figure to stand up by, the file's Y (as `Stance::guess`).
            Up::Y
        } else {
            Up::guess(&skeleton)
        };
        let frames = motion.frame_count();
        let mut data = Vec::new();
        let picked: Vec<usize> = match frames {
            0 => Vec::new(),
            _ => (0..5).map(|k| k * (frames - 1) / 4).collect(),
        };
        for &frame in &picked {
            data.extend_from_slice(motion.frame(frame));
        }
        let poses = Motion::new(motion.frame_time, motion.channels, picked.len(), data);
        Target {
            name,
            skeleton,
            up,
            poses,
        }
    }

    /// A take on this skeleton by the guessed map (`pairs` override it), refused with the
    /// reason when the map cannot stand, on up to `threads` threads. `source_name` names the
    /// take in messages.
    ///
    /// A take whose body does not stand on two legs (a quadruped rigged with 3ds Max Biped's
    /// human names) is refused onto a target that does, and a two-legged take onto a target
    /// that does not (a person's walk onto a fox), with the reason ([`Target::check_body`]);
    /// [`Target::apply_any_body`] retargets it anyway.
    pub fn apply(
        &self,
        source_name: &str,
        skeleton: &Skeleton,
        motion: &Motion,
        pairs: &[(String, String)],
        threads: usize,
    ) -> Result<(Skeleton, Motion), Error> {
        self.check_body(source_name, skeleton, motion)?;
        self.apply_any_body(source_name, skeleton, motion, pairs, threads)
    }

    /// Fails when one of the take's body and this target's stands on two legs and the other
    /// does not (its reading's [`Doubt::NotBiped`]): the limbs would be carried over as a
    /// person's (a front leg as an arm, or a person's arms onto a fox's front legs), which no
    /// map fixes. The one rule of every command that puts a take on another skeleton
    /// (`retarget`, `dataset --onto`, `--character`; Python's `retarget`, `dress`,
    /// `compile_dataset`), each with its `--any-body` (`any_body=True`) to go ahead anyway.
    pub fn check_body(
        &self,
        source_name: &str,
        skeleton: &Skeleton,
        motion: &Motion,
    ) -> Result<(), Error> {
        // Many legs (a crab) is refused as a body that does not stand on two is.
        let two_legged = |skeleton: &Skeleton, motion: &Motion| {
            Body::of(skeleton)
                .doubts(skeleton, motion, OffsetMode::Replace)
                .into_iter()
                .find_map(|d| match d {
                    Doubt::ManyLegs(n) => Some(Doubt::NotBiped(format!("it has {n} legs"))),
                    Doubt::NotBiped(_) | Doubt::NoTwoLegs => Some(d),
                    _ => None,
                })
        };
        let target_doubt = two_legged(&self.skeleton, &self.poses);
        match (two_legged(skeleton, motion), target_doubt) {
            (Some(Doubt::NotBiped(why)), None) => Err(Error::Usage(format!(
                "{source_name}: not a two-legged body ({why}), and {} is one: its limbs would \
                 be carried over as a person's; {ANY_BODY}",
                crate::limits::quoted(&self.name)
            ))),
            (None, Some(Doubt::NotBiped(why))) => Err(Error::Usage(format!(
                "{source_name}: a two-legged body, and {} is not ({why}): a person's limbs \
                 would be carried onto it as if it were one; {ANY_BODY}",
                crate::limits::quoted(&self.name)
            ))),
            _ => Ok(()),
        }
    }

    /// What retargeting the take onto this target by the same map as [`Target::apply`] cannot
    /// carry, said in words: each mapped source joint (not the hips, nor above them) whose
    /// position channels move it from its OFFSET, by more than 1e-4 of the legs' length on
    /// some frame, onto a target joint without position channels, which keeps its OFFSET.
    pub fn uncarried_translations(
        &self,
        skeleton: &Skeleton,
        motion: &Motion,
        pairs: &[(String, String)],
    ) -> Result<Vec<String>, Error> {
        let mut map = Map::guess(skeleton, &self.skeleton);
        map.apply(pairs, skeleton, &self.skeleton)?;
        let moves = |joint: &Joint| joint.channels.iter().any(|c| c.is_position());
        let hips = map.source_body.hips;
        let candidates: Vec<(usize, usize)> = (0..self.skeleton.joints.len())
            .filter_map(|t| Some((map.source_of[t]?, t)))
            .filter(|&(s, t)| {
                let joint = &skeleton.joints[s];
                moves(joint)
                    && !moves(&self.skeleton.joints[t])
                    && joint.parent.is_some()
                    && !hips.is_some_and(|h| is_ancestor(skeleton, s, h))
            })
            .collect();
        if candidates.is_empty() {
            return Ok(Vec::new());
        }
        let mode = source_offset_mode(skeleton, motion);
        let mut rest = Vec::new();
        world_transforms_f64(skeleton, &[], OffsetMode::Replace, &mut rest);
        let legs = map.source_body.leg_length(&rest).unwrap_or(1.0);
        let mut farthest = vec![0.0f64; candidates.len()];
        let mut world = Vec::new();
        for frame in 0..motion.frame_count() {
            world_transforms_f64(skeleton, motion.frame(frame), mode, &mut world);
            for (far, &(s, _)) in farthest.iter_mut().zip(&candidates) {
                let joint = &skeleton.joints[s];
                let (rotation, at) = world[joint.parent.unwrap_or(s)];
                let moved = world[s].1 - (at + rotation * joint.offset.as_dvec3());
                *far = far.max(moved.length());
            }
        }
        Ok(candidates
            .iter()
            .zip(farthest)
            .filter(|&(_, far)| far > 1e-4 * legs)
            .map(|(&(s, t), far)| {
                format!(
                    "{}'s position channels move it up to {far:.4} from its OFFSET ({:.1} % of \
                     the legs' length); {} has no position channels, so that move is not carried",
                    skeleton.joints[s].name,
                    100.0 * far / legs,
                    self.skeleton.joints[t].name
                )
            })
            .collect())
    }

    /// [`super::check()`] of `output`, which [`Target::apply`] made of `skeleton` and `motion`
    /// with `pairs`: the output measured against its source by the same map and up axes.
    pub fn check(
        &self,
        skeleton: &Skeleton,
        motion: &Motion,
        output_skeleton: &Skeleton,
        output: &Motion,
        pairs: &[(String, String)],
    ) -> super::Check {
        let mut map = Map::guess(skeleton, &self.skeleton);
        // The pairs were applied once already, by the retarget this output came from.
        let _ = map.apply(pairs, skeleton, &self.skeleton);
        let ups = self.ups(skeleton, motion);
        super::check(
            skeleton,
            motion,
            output_skeleton,
            output,
            &map,
            ups,
            Some(&self.poses),
        )
    }

    /// The take's up axis (guessed, or stated by its file) and this target's.
    fn ups(&self, skeleton: &Skeleton, motion: &Motion) -> Ups {
        Ups {
            source: crate::model::stance::Stance::guess(
                skeleton,
                motion,
                OffsetMode::Replace,
                None,
            )
            .up,
            target: self.up,
        }
    }

    /// [`Target::apply`] without the body check: any body onto any target.
    pub fn apply_any_body(
        &self,
        source_name: &str,
        skeleton: &Skeleton,
        motion: &Motion,
        pairs: &[(String, String)],
        threads: usize,
    ) -> Result<(Skeleton, Motion), Error> {
        crate::limits::retarget_values(
            &format!("{source_name} onto {}", self.name),
            motion.frame_count(),
            skeleton.channel_count(),
            self.skeleton.joints.len(),
            self.skeleton.channel_count(),
        )?;
        let mut map = Map::guess(skeleton, &self.skeleton);
        map.apply(pairs, skeleton, &self.skeleton)?;
        map.check(source_name, &self.name)?;
        let ups = self.ups(skeleton, motion);
        super::retarget_posed(
            skeleton,
            motion,
            &self.skeleton,
            Some(&self.poses),
            &map,
            ups,
            threads,
        )
    }
}
