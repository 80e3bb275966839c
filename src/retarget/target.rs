//! The skeleton a take is put on: a file, or a built-in skeleton (`smpl22`).

use crate::bvh::built_in::{BUILT_IN, built_in};
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::body::{Body, Doubt, is_ancestor};
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, Up, world_transforms_f64};
use crate::model::skeleton::{Joint, Skeleton};
use crate::retarget::align::{Ups, source_offset_mode};
use crate::retarget::map::Map;
use crate::take::Take;

/// What a refusal by [`Target::check_body`] ends with: how to go ahead anyway (the command
/// line says "`--any-body` retargets it anyway", Python "`any_body` retargets it anyway").
fn any_body_goes_ahead() -> Message {
    Message::from("`")
        .argument("any_body", None)
        .text("` retargets it anyway")
}

/// What a refusal by [`Check::refusal`](crate::retarget::Check::refusal) ends with: how to write
/// the output anyway.
fn force_goes_ahead() -> Message {
    Message::from("`")
        .argument("force", None)
        .text("` writes it anyway")
}

/// How far a caller goes against [`Target::apply`]'s refusals: `any_body` puts a body on a
/// skeleton of another kind (four legs onto two) and does not hold it to a person's widths;
/// `force` keeps an output whose check finds a side crossed or a width collapsed.
///
/// ```
/// use bvhview::retarget::Insist;
///
/// let insist = Insist { force: true, ..Insist::default() };
/// assert!(!insist.any_body);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Insist {
    /// Any body onto any skeleton (`--any-body`).
    pub any_body: bool,
    /// Written though its check refuses it (`--force`).
    pub force: bool,
}

/// A take put on a target by [`Target::apply`]: the target's skeleton, the motion on it, and
/// what the output measures against its source.
///
/// ```
/// use bvhview::Take;
/// use bvhview::retarget::{Insist, Target};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?.trim(0..60);
/// let target = Target::load("smpl22", u64::MAX)?;
/// let put = target.apply(&walk.name, &walk.skeleton, &walk.motion, &[], Insist::default(), 1)?;
/// assert_eq!(put.motion.frame_count(), 60);
/// assert!(put.forced.is_none() && put.check.refusal().is_none(), "{}", put.check.line());
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Retargeted {
    /// The target's skeleton.
    pub skeleton: Skeleton,
    /// The take's motion on it.
    pub motion: Motion,
    /// The output measured against its source.
    pub check: crate::retarget::check::Check,
    /// Why the check refuses the output, when [`Insist::force`] kept it anyway.
    pub forced: Option<String>,
    /// What the map could not carry, said in words: each mapped source joint (not the hips,
    /// nor above them) whose position channels move it from its OFFSET, by more than 1e-4 of
    /// the legs' length on some frame, onto a target joint without position channels, which
    /// keeps its OFFSET.
    pub uncarried: Vec<String>,
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
/// let put = target.apply("walk", &take.skeleton, &take.motion, &[], Default::default(), 1)?;
/// assert_eq!(put.skeleton, target.skeleton);
/// assert_eq!(put.motion.frame_count(), 30);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    /// The name messages give it: the file's path, or the built-in skeleton's name.
    pub name: String,
    /// The skeleton takes are put on.
    pub skeleton: Skeleton,
    /// Its up axis: its take's guessed stance's, or its rest pose's (see [`Target::new`]), or
    /// the one the user gave ([`Target::of_take`]).
    pub up: Up,
    /// The units of its lengths when the user gave them (`--onto-units`, a take loaded with
    /// `units=`); `None`: guessed from its figure wherever they are needed.
    pub units: Option<crate::model::stance::Units>,
    /// Whether [`Target::up`] was given by the user rather than guessed.
    pub up_given: bool,
    /// What reading it said once (a target turned to stand along y as it was read, for one).
    pub warnings: Vec<crate::io::message::Message>,
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
                return Err(Error::invalid(
                    "onto",
                    onto,
                    format!(
                        "neither a file nor a built-in skeleton ({})",
                        names.join(", ")
                    ),
                ));
            }
        }
        let loaded = crate::take::OpenOptions::new()
            .max_size(max_size)
            .open(path)?;
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
            units: None,
            up_given: false,
            warnings: Vec::new(),
            poses,
        }
    }

    /// The target a take is, with what its caller said of it: the up axis given
    /// ([`Take::stated_up`](crate::Take::stated_up), over the guess) and the units given
    /// ([`Take::units_given`](crate::Take::units_given)).
    ///
    /// ```
    /// use bvhview::OpenOptions;
    /// use bvhview::model::{pose::Up, stance::Units};
    /// use bvhview::retarget::Target;
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let walk = OpenOptions::new()
    ///     .up(Up::Y)
    ///     .units(Units::named("m").unwrap())
    ///     .open("tests/data/bvh/makehuman_walk1.bvh")?;
    /// let target = Target::of_take("walk", &walk);
    /// assert_eq!((target.up, target.units.unwrap().name), (Up::Y, "metres"));
    /// // Guessed, the MakeHuman walk stands along z.
    /// assert_eq!(Target::load("tests/data/bvh/makehuman_walk1.bvh", u64::MAX)?.up, Up::Z);
    /// # Ok(())
    /// # }
    /// ```
    pub fn of_take(name: impl Into<String>, take: &crate::Take) -> Target {
        let mut target = Target::new(name.into(), take.skeleton.clone(), &take.motion);
        if let Some(up) = take.stated_up {
            target.up = up;
            target.up_given = true;
        }
        target.units = take.stated_units.filter(|_| take.units_given);
        target.warnings = take.warnings.clone();
        target
    }

    /// The up axis the user gave for it, if any.
    pub fn stated_up(&self) -> Option<Up> {
        self.up_given.then_some(self.up)
    }

    /// `take`, put on this target, with what the user said of the target: its up axis and
    /// units (none said: both guessed from the take again).
    pub fn state_on(&self, take: &mut crate::Take) {
        take.stated_up = self.stated_up();
        take.stated_units = self.units;
        take.units_given = self.units.is_some();
    }

    /// [`Target::load`] with what the caller says of it: `options`' units and up axis (a take
    /// said to stand along x, −x, −y or −z is turned to stand along y as it is read, as any
    /// take is) and its file-size limit. Without units or an up axis, [`Target::load`].
    pub fn open(onto: &str, options: &crate::take::OpenOptions) -> Result<Target, Error> {
        let max_size = options.max_size_or_default();
        if options.units.is_none() && options.up.is_none() {
            return Target::load(onto, max_size);
        }
        let take = options.open(onto)?;
        Ok(Target::of_take(onto, &take))
    }

    /// A take on this skeleton by the guessed map (`pairs` override it), on up to `threads`
    /// threads, with what it measures against its source ([`check`](fn@crate::retarget::check));
    /// refused with the reason when the map cannot stand, when the bodies differ
    /// ([`Target::check_body`]: a quadruped rigged with 3ds Max Biped's human names onto a person,
    /// a person's walk onto a fox) unless `insist.any_body`, and when the output's check finds a
    /// side crossed or a width collapsed ([`Check::refusal`](crate::retarget::Check::refusal))
    /// unless `insist.force` (then [`Retargeted::forced`] holds the reason, for the caller to say).
    /// `source_name` names the take in messages. The one way every command puts a take on another
    /// skeleton (`retarget`, `dataset --onto`, `--character`; Python's `retarget`, `dress`,
    /// `compile_dataset`).
    pub fn apply(
        &self,
        source_name: &str,
        skeleton: &Skeleton,
        motion: &Motion,
        pairs: &[(String, String)],
        insist: Insist,
        threads: usize,
    ) -> Result<Retargeted, Error> {
        self.apply_up(source_name, skeleton, motion, None, pairs, insist, threads)
    }

    /// [`Target::apply`] with the axis the take stands along given (`--up`, `up=`), over the
    /// guess from its motion.
    #[allow(clippy::too_many_arguments)]
    pub fn apply_up(
        &self,
        source_name: &str,
        skeleton: &Skeleton,
        motion: &Motion,
        source_up: Option<Up>,
        pairs: &[(String, String)],
        insist: Insist,
        threads: usize,
    ) -> Result<Retargeted, Error> {
        if !insist.any_body {
            self.check_body(source_name, skeleton, motion)?;
        }
        crate::limits::retarget_values(
            &format!("{source_name} onto {}", self.name),
            motion.frame_count(),
            skeleton.channel_count(),
            self.skeleton.joints.len(),
            self.skeleton.channel_count(),
        )?;
        let map = self.map(source_name, skeleton, pairs)?;
        let ups = self.ups(skeleton, motion, source_up);
        let (out_skeleton, out) = crate::retarget::run::retarget_posed(
            skeleton,
            motion,
            &self.skeleton,
            Some(&self.poses),
            &map,
            ups,
            threads,
        )?;
        // The answer checks itself against its source before anyone writes it.
        let check = crate::retarget::check::check(
            skeleton,
            motion,
            &out_skeleton,
            &out,
            &map,
            ups,
            Some(&self.poses),
        );
        // A body let on by `any_body` is not a person's, and not held to a person's widths.
        let forced = check.refusal().filter(|_| !insist.any_body);
        if let Some(why) = &forced
            && !insist.force
        {
            return Err(Error::usage(
                Message::from(format!(
                    "{source_name} onto {}: not written: {why} ({}); ",
                    crate::limits::quoted(&self.name),
                    check.line()
                ))
                .then(force_goes_ahead()),
            ));
        }
        Ok(Retargeted {
            skeleton: out_skeleton,
            motion: out,
            check,
            forced,
            uncarried: self.uncarried_translations(skeleton, motion, &map),
        })
    }

    /// What `output` (a take on this skeleton, as [`Target::apply`] made it and an edit such as
    /// [`crate::retarget::lock_feet_from_source`] changed it after) measures against its source
    /// (`skeleton`, `motion`), by the same map and up axes: the answer checked again once it
    /// is what will be written.
    pub fn measure(
        &self,
        source_name: &str,
        skeleton: &Skeleton,
        motion: &Motion,
        source_up: Option<Up>,
        pairs: &[(String, String)],
        output: &Motion,
    ) -> Result<crate::retarget::check::Check, Error> {
        let map = self.map(source_name, skeleton, pairs)?;
        let ups = self.ups(skeleton, motion, source_up);
        Ok(crate::retarget::check::check(
            skeleton,
            motion,
            &self.skeleton,
            output,
            &map,
            ups,
            Some(&self.poses),
        ))
    }

    /// The guessed map from `skeleton` onto this target with `pairs` over it, refused when it
    /// cannot stand ([`Map::check`]).
    pub fn map(
        &self,
        source_name: &str,
        skeleton: &Skeleton,
        pairs: &[(String, String)],
    ) -> Result<Map, Error> {
        let mut map = Map::guess(skeleton, &self.skeleton);
        map.apply(pairs, skeleton, &self.skeleton)?;
        map.check(source_name, &self.name)?;
        Ok(map)
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
            (Some(Doubt::NotBiped(why)), None) => Err(Error::usage(
                Message::from(format!(
                    "{source_name}: not a two-legged body ({why}), and {} is one: its limbs \
                     would be carried over as a person's; ",
                    crate::limits::quoted(&self.name)
                ))
                .then(any_body_goes_ahead()),
            )),
            (None, Some(Doubt::NotBiped(why))) => Err(Error::usage(
                Message::from(format!(
                    "{source_name}: a two-legged body, and {} is not ({why}): a person's limbs \
                     would be carried onto it as if it were one; ",
                    crate::limits::quoted(&self.name)
                ))
                .then(any_body_goes_ahead()),
            )),
            _ => Ok(()),
        }
    }

    /// What retargeting the take onto this target by `map` cannot carry, said in words
    /// ([`Retargeted::uncarried`]).
    fn uncarried_translations(
        &self,
        skeleton: &Skeleton,
        motion: &Motion,
        map: &Map,
    ) -> Vec<String> {
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
            return Vec::new();
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
        candidates
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
            .collect()
    }

    /// The take's up axis (guessed, or stated by its file) and this target's.
    fn ups(&self, skeleton: &Skeleton, motion: &Motion, given: Option<Up>) -> Ups {
        let guess =
            || crate::model::stance::Stance::guess(skeleton, motion, OffsetMode::Replace, None).up;
        Ups {
            source: given.unwrap_or_else(guess),
            target: self.up,
        }
    }
}

/// A take's motion on another skeleton, one call from a [`Take`]: `onto` is a file (.bvh, .fbx,
/// .gltf, .glb, .asf; its skeleton only) or a built-in skeleton's name (`smpl22`). Joints are
/// matched by role from their names, as `bvhview retarget` matches them.
///
/// ```
/// use bvhview::Take;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?.trim(0..30);
/// let smpl = bvhview::retarget::onto(&take, "smpl22")?;
/// assert_eq!(smpl.frame_count(), 30);
/// assert!(smpl.point_names().iter().any(|n| n == "left_knee"));
/// # Ok(())
/// # }
/// ```
pub fn onto(take: &Take, onto: &str) -> Result<Take, Error> {
    let target = Target::load(onto, crate::take::DEFAULT_MAX_SIZE)?;
    let put = target.apply(
        &take.name,
        &take.skeleton,
        &take.motion,
        &[],
        Insist::default(),
        crate::io::parallel::cores(),
    )?;
    let name = format!("{} on {}", take.name, target.name);
    Ok(Take::new(put.skeleton, put.motion, name))
}
