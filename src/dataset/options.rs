//! What every take is turned into: the compile's options, checked before any take is read.

use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::pose::RotationKind;

/// What every take is turned into.
///
/// ```
/// use bvhview::dataset::{self, Options};
/// use bvhview::model::pose::RotationKind;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// # let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// // `folder` holds walk.bvh, a copy of tests/data/bvh/bvhparser_walk_01.bvh.
/// let takes = dataset::takes(folder.path())?;
/// let options = Options { fps: 60.0, rotations: RotationKind::Quat, ..Options::default() };
/// options.check()?;
/// let clip = dataset::compile_take(folder.path(), &takes[0], &options)?;
/// assert_eq!(clip.frames, 172);
/// assert_eq!(clip.rotations.len(), clip.frames * clip.topology.rotated.len() * 4);
/// assert!(Options { fps: 0.0, ..Options::default() }.check().is_err());
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// The one frame rate every clip is resampled to.
    pub fps: f64,
    /// How rotations are written.
    pub rotations: RotationKind,
    /// Positions relative to the root's place on the floor (x and z) in each frame.
    pub root_relative: bool,
    /// The points foot contacts are given for, by name; `None`: the ankle and toe of each leg as
    /// the reading of the body finds them ([`crate::model::body::Body::foot_points`]), or, for a
    /// body without two feet, guessed from the rest pose
    /// ([`guess_feet`](crate::dataset::guess_feet)) with a warning.
    pub feet: Option<Vec<String>>,
    /// A foot point is in contact when it is at most this high (metres) above its own floor
    /// (the lowest it comes within a second each way: the reading of the body's contacts,
    /// [`crate::model::body::contact`])…
    pub contact_height: f32,
    /// …and moves slower than this (metres per second).
    pub contact_speed: f32,
    /// Files larger than this are skipped.
    pub max_size: u64,
    /// Every take retargeted onto this skeleton first (`--onto`), so a folder of mixed
    /// skeletons makes one group; a take whose map misses a required role is skipped.
    pub onto: Option<crate::retarget::Target>,
    /// With `onto`: put on it a take whose body is not two-legged like the target's (refused
    /// otherwise, [`crate::retarget::Target::check_body`]; `--any-body`).
    pub any_body: bool,
    /// With `onto`: keep a take whose output's check finds a side crossed or a width collapsed
    /// (skipped otherwise, [`crate::retarget::Check::refusal`]; `--force`), with a warning.
    pub force: bool,
    /// With `onto`: `SRC = DST` pairs over every take's guessed map (`--map`), as `retarget
    /// --map` gives them (`SRC =` with an empty target leaves a source joint out); pairs for one
    /// skeleton apply to the takes of that skeleton only. A take that has no joint a pair for
    /// it names is skipped with the reason.
    pub map: crate::retarget::MapPairs,
    /// Each clip moved up or down so that its lowest foot point over the whole clip is on
    /// y = 0 (`--ground`); positions, root translations and the roots' translations alike.
    pub ground: bool,
    /// With `rotations` quaternions: each frame's sign chosen against the previous frame's
    /// (`q` or `-q`, whichever is nearer), so that a joint's quaternions run continuously along
    /// time (`--quat-continuous`). Off: each has w ≥ 0, frame by frame, and may flip sign
    /// between neighbouring frames where w crosses 0.
    pub quat_continuous: bool,
    /// Each take's planted feet held where they landed first (`--lock-feet`, as `convert
    /// --lock-feet` holds them).
    pub lock_feet: bool,
    /// What each take is written as (`--features`).
    pub features: FeatureSet,
    /// The units every take's lengths are in, over the guess (`--units`); the manifest says
    /// each clip's units were given.
    pub units: Option<crate::model::stance::Units>,
    /// The axis every take stands along, over the guess (`--up`); the manifest says each
    /// clip's up axis was given.
    pub up: Option<crate::model::pose::UpAxis>,
    /// The units every length is written in (`--out-units`): positions, translations,
    /// velocities, OFFSETs and each group's `skeleton.bvh`; `None`: metres. The contact
    /// thresholds and the clips' metrics stay in metres. HumanML3D's vectors are metres by
    /// their definition.
    pub out_units: Option<crate::model::stance::Units>,
}

/// What each take of a dataset is written as (`--features`).
///
/// ```
/// use bvhview::dataset::FeatureSet;
///
/// assert_eq!(FeatureSet::parse("humanml3d"), Some(FeatureSet::HumanMl3d));
/// assert_eq!(FeatureSet::default().name(), "arrays");
/// assert_eq!(FeatureSet::parse("smpl"), None);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FeatureSet {
    /// bvhview's arrays, clips grouped by skeleton topology (`group_K/*.npy`).
    #[default]
    Arrays,
    /// HumanML3D's representation ([`crate::humanml3d`]) in its folder layout: per take
    /// `new_joint_vecs/ID.npy` (its 263-value vectors) and `new_joints/ID.npy` (the positions
    /// they stand for), with `Mean.npy` and `Std.npy` over the set and `all.txt` listing the
    /// IDs: the take's place in the folder's list of takes, six digits (`000042`).
    HumanMl3d,
}

impl FeatureSet {
    /// The name `--features` and the manifest give it.
    pub fn name(self) -> &'static str {
        match self {
            FeatureSet::Arrays => "arrays",
            FeatureSet::HumanMl3d => "humanml3d",
        }
    }

    /// The set named `name`.
    pub fn parse(name: &str) -> Option<FeatureSet> {
        [FeatureSet::Arrays, FeatureSet::HumanMl3d]
            .into_iter()
            .find(|set| set.name() == name)
    }
}

impl Default for Options {
    fn default() -> Options {
        Options {
            fps: 30.0,
            rotations: RotationKind::SixD,
            root_relative: false,
            feet: None,
            contact_height: 0.05,
            contact_speed: 0.5,
            ground: false,
            quat_continuous: false,
            lock_feet: false,
            features: FeatureSet::Arrays,
            map: crate::retarget::MapPairs::default(),
            max_size: crate::take::DEFAULT_MAX_SIZE,
            onto: None,
            any_body: false,
            force: false,
            units: None,
            up: None,
            out_units: None,
        }
    }
}

impl Options {
    /// Refuses rates and thresholds no dataset can be made with.
    pub fn check(&self) -> Result<(), Error> {
        crate::limits::fps(self.fps, false)?;
        let positive = |name: &'static str, value: f32| {
            if value.is_finite() && value >= 0.0 {
                Ok(())
            } else {
                Err(Error::invalid(
                    name,
                    value.to_string(),
                    "expected a finite number of at least 0",
                ))
            }
        };
        if let Some(units) = self.out_units
            && units.metres != 1.0
            && self.features == FeatureSet::HumanMl3d
        {
            return Err(Error::usage(
                Message::from("`")
                    .argument("out_units", Some(units.name))
                    .text("`: HumanML3D's vectors are in metres by their definition"),
            ));
        }
        positive("contact_height", self.contact_height)?;
        positive("contact_speed", self.contact_speed)?;
        if !self.map.is_empty() && self.onto.is_none() {
            return Err(Error::usage(
                Message::from("`")
                    .argument("map", None)
                    .text("` needs `")
                    .argument("onto", None)
                    .text("`: its pairs name joints of the skeleton every take is put on"),
            ));
        }
        if self.quat_continuous && self.rotations != RotationKind::Quat {
            return Err(Error::invalid(
                "quat_continuous",
                "",
                Message::from("only quaternions have a sign to choose (")
                    .argument("rotations", Some("quat"))
                    .text(format!("), not {}", self.rotations.name())),
            ));
        }
        if let Some(feet) = &self.feet
            && (feet.is_empty() || feet.iter().any(|name| name.is_empty()))
        {
            return Err(Error::invalid(
                "feet",
                "",
                "expected point names separated by commas (as the dataset names them)",
            ));
        }
        if self.features == FeatureSet::HumanMl3d {
            self.check_humanml3d()?;
        }
        Ok(())
    }

    /// HumanML3D's vectors are of SMPL's 22 joints at 20 fps, placed by its own processing.
    fn check_humanml3d(&self) -> Result<(), Error> {
        let refuse = |why: Message| Err(Error::invalid("features", "humanml3d", why));
        let Some(target) = &self.onto else {
            return refuse(
                Message::from("needs ")
                    .argument("onto", Some("smpl22"))
                    .text(
                        " (or a skeleton with SMPL's 22 joint names): HumanML3D's vectors are \
                         of SMPL's 22 joints",
                    ),
            );
        };
        let missing: Vec<&str> = crate::solve::SMPL22_ORDER
            .iter()
            .filter(|name| !target.skeleton.joints.iter().any(|j| j.name == **name))
            .copied()
            .collect();
        if !missing.is_empty() {
            return refuse(
                format!(
                    "{} has no joint named {} (HumanML3D's vectors are of SMPL's 22 joints, by \
                     the names of the built-in smpl22)",
                    target.name,
                    missing.join(", ")
                )
                .into(),
            );
        }
        if self.fps != crate::humanml3d::FPS {
            return refuse(
                format!(
                    "HumanML3D's vectors are made at 20 fps (its contact threshold is a step per \
                     frame), not {}",
                    crate::limits::show(self.fps)
                )
                .into(),
            );
        }
        let placed = [
            ("root_relative", self.root_relative),
            ("ground", self.ground),
            ("quat_continuous", self.quat_continuous),
            ("feet", self.feet.is_some()),
        ];
        if let Some(&(option, _)) = placed.iter().find(|(_, on)| *on) {
            return refuse(Message::of_argument(option, None).text(
                " has no part in HumanML3D's vectors (its processing grounds and centres each \
                 take itself, and its contacts are of its own foot joints)",
            ));
        }
        Ok(())
    }
}
