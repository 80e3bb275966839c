//! How a take stands: which axis is up, what unit its lengths are written in and how tall the
//! figure is, guessed from its motion (the joints' spread and the root's path over a sample of
//! its frames), or from its rest pose when it has no frames. A rest pose alone misleads: some
//! exporters lay it along x (LaFAN1, Rokoko), others stand it along y and turn the root to z.
//!
//! Nothing here changes the article's picture, which draws every file as written; the studio
//! look, `--fit`, `info` and the edits use the guess, and `--up` overrides it.

use crate::model::body::Body;
use crate::model::motion::Motion;
use crate::model::pose::{FkPlan, FkScratch, OffsetMode, Up, world_positions};
use crate::model::skeleton::Skeleton;
use glam::Vec3;

/// At most this many frames, evenly spread over the take, are looked at.
const SAMPLED_POSES: usize = 64;

/// The spread along one axis must be this many times the other's for the guess to be likely,
/// and [`SURE`] times for it to be sure.
const LIKELY: f32 = 1.25;
const SURE: f32 = 2.0;

/// How much a guess is worth.
///
/// ```
/// use bvhview::model::stance::{Sureness, Units};
///
/// let (units, sureness) = Units::guess_with_sureness(175.0); // a person, in centimetres
/// assert_eq!((units.name, sureness.word()), ("centimetres", "sure"));
/// assert_eq!(Units::guess_with_sureness(6.0).1, Sureness::Unsure); // 6 what?
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sureness {
    /// The file says so (an ASF's `:units`, a glTF's or FBX's axes), or the skeleton is one
    /// whose units are known.
    Stated,
    /// The evidence is clear: one answer well ahead of the others.
    Sure,
    /// The evidence leans one way, not by much.
    Likely,
    /// A convention rather than evidence (BVH's Y up when the figure tells nothing).
    Unsure,
}

impl Sureness {
    /// How messages and `info` say it: `stated`, `sure`, `likely` or `unsure`.
    pub fn word(self) -> &'static str {
        match self {
            Sureness::Stated => "stated",
            Sureness::Sure => "sure",
            Sureness::Likely => "likely",
            Sureness::Unsure => "unsure",
        }
    }
}

/// What the units guess rests on.
///
/// ```
/// use bvhview::{Take, model::{pose::OffsetMode, stance::{Sureness, UnitsBasis}}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let asf = Take::open("tests/data/asf_amc/heiden_12.asf")?.stance(OffsetMode::Replace);
/// assert_eq!((asf.units_basis, asf.units_sureness), (UnitsBasis::Asf, Sureness::Stated));
/// let bvh = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?.stance(OffsetMode::Replace);
/// assert_eq!(bvh.units_basis, UnitsBasis::Size);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitsBasis {
    /// The ASF's `:units length` (CMU's 0.45: lengths in 1/0.45 inch).
    Asf,
    /// The FBX's `UnitScaleFactor`: a plain FBX take is read in its file's own units.
    Fbx,
    /// AMASS's metres (the SMPL family's models and their `trans` are in metres).
    Amass,
    /// A skeleton known by its joints' names (CMU's, as cgspeed converted it to BVH).
    CmuSkeleton,
    /// The figure's size, nearest a person's 1.7 m.
    Size,
    /// Given by the caller (`--units`, `units=`), not guessed.
    Given,
}

/// The units a file's lengths look written in, guessed from how tall its skeleton stands.
///
/// ```
/// use bvhview::model::stance::Units;
///
/// assert_eq!(Units::guess(1.8).name, "metres");
/// assert_eq!(Units::guess(72.0).name, "inches"); // a Second Life avatar
/// assert_eq!(Units::guess(1700.0).metres, 0.001);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Units {
    /// What messages call them (`centimetres`).
    pub name: &'static str,
    /// Metres per unit of the file.
    pub metres: f32,
}

impl Units {
    /// The units of `metres` metres per unit, by name where they have one (`centimetres`,
    /// CMU's), else as a length given.
    ///
    /// ```
    /// use bvhview::model::stance::Units;
    ///
    /// assert_eq!(Units::of_metres(0.0254).name, "inches");
    /// assert_eq!(Units::of_metres(0.5).name, "units of the length given");
    /// ```
    pub fn of_metres(metres: f32) -> Units {
        if metres == CMU_UNITS.metres {
            return CMU_UNITS;
        }
        ["mm", "cm", "dm", "m", "in", "ft"]
            .into_iter()
            .filter_map(Units::named)
            .find(|units| units.metres == metres)
            .unwrap_or(Units {
                name: "units of the length given",
                metres,
            })
    }

    /// The units a user names: `mm`, `cm`, `m`, `in`, `ft` (or their long names), or a number
    /// of metres per unit (`0.0254`); `None` for anything else.
    ///
    /// ```
    /// use bvhview::model::stance::Units;
    ///
    /// assert_eq!(Units::named("cm").unwrap().metres, 0.01);
    /// assert_eq!(Units::named("feet").unwrap().name, "feet");
    /// assert_eq!(Units::named("0.5").unwrap().metres, 0.5);
    /// assert!(Units::named("-1").is_none() && Units::named("parsecs").is_none());
    /// ```
    pub fn named(text: &str) -> Option<Units> {
        let (name, metres) = match text.trim().to_ascii_lowercase().as_str() {
            "mm" | "millimetres" | "millimeters" => ("millimetres", 0.001),
            "cm" | "centimetres" | "centimeters" => ("centimetres", 0.01),
            "dm" | "decimetres" | "decimeters" => ("decimetres", 0.1),
            "m" | "metres" | "meters" => ("metres", 1.0),
            "in" | "inches" => ("inches", 0.0254),
            "ft" | "feet" => ("feet", 0.3048),
            number => {
                // A length a take's unit could be: a nanometre to a kilometre.
                let metres: f32 = number.parse().ok()?;
                return (1e-9..=1e3)
                    .contains(&metres)
                    .then(|| Units::of_metres(metres));
            }
        };
        Some(Units { name, metres })
    }

    /// The units in which a figure of size `height` (its largest spread, see [`Stance::size`])
    /// comes nearest to a person's 1.7 m, by ratio: metres, decimetres (MakeHuman's),
    /// centimetres, millimetres or inches.
    /// Tiny rigs in metres read as metres, Second Life's (about 72 tall) as inches.
    pub fn guess(height: f32) -> Units {
        Units::guess_with_sureness(height).0
    }

    /// [`Units::guess`], and how sure it is: sure when the size is within a third of 1.7 m in
    /// those units and clearly nearer than in any other, likely within ×1.8, else unsure.
    pub fn guess_with_sureness(height: f32) -> (Units, Sureness) {
        const CANDIDATES: [Units; 5] = [
            Units {
                name: "metres",
                metres: 1.0,
            },
            Units {
                name: "decimetres",
                metres: 0.1,
            },
            Units {
                name: "centimetres",
                metres: 0.01,
            },
            Units {
                name: "millimetres",
                metres: 0.001,
            },
            Units {
                name: "inches",
                metres: 0.0254,
            },
        ];
        let off = |units: &Units| (height.max(1e-6) * units.metres / 1.7).ln().abs();
        let mut ranked = CANDIDATES;
        ranked.sort_by(|a, b| off(a).total_cmp(&off(b)));
        let (best, next) = (off(&ranked[0]), off(&ranked[1]));
        let sureness = if best < 1.35f32.ln() && next - best > 0.5 {
            Sureness::Sure
        } else if best < 1.8f32.ln() {
            Sureness::Likely
        } else {
            Sureness::Unsure
        };
        (ranked[0], sureness)
    }
}

/// CMU's lengths: 1/0.45 inch, about 5.64 cm (their ASF files say `length 0.45`; cgspeed's BVH
/// conversions keep the lengths).
pub const CMU_UNITS: Units = Units {
    name: "CMU units (1/0.45 inch)",
    metres: 0.0254 / 0.45,
};

/// The guess for one take.
///
/// ```
/// use bvhview::{Take, model::{pose::{OffsetMode, Up}, stance::Stance}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// let stance: Stance = take.stance(OffsetMode::Replace);
/// assert_eq!(stance.up, Up::Y);
/// assert_eq!(stance.units.name, "CMU units (1/0.45 inch)"); // CMU's skeleton, known by name
/// assert_eq!(stance.poses, 64); // frames looked at
/// assert!(stance.height > 0.0 && stance.height <= stance.size);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stance {
    /// The axis the figure stands along.
    pub up: Up,
    /// How sure the up axis is.
    pub up_sureness: Sureness,
    /// Whether the root's path decided the up axis (the figure's spread did not).
    pub up_by_path: bool,
    /// Whether the up axis was given by the caller (`--up`, `up=`), not guessed.
    pub up_given: bool,
    /// `Some(legs)` when the body has no legs (a hand alone) or more than two (a crab): its
    /// spread says nothing of which way a person would stand, so the file's Y is kept.
    pub legs_not_two: Option<usize>,
    /// The figure's spread along x, y and z (the median over the poses looked at), in the file's
    /// units, as the file is written.
    pub spread: Vec3,
    /// How far the root travels along x, y and z over the poses looked at.
    pub root_travel: Vec3,
    /// The units the lengths look written in.
    pub units: Units,
    /// How sure the units are.
    pub units_sureness: Sureness,
    /// What the units guess rests on.
    pub units_basis: UnitsBasis,
    /// How tall the figure stands along its up axis (the median over the poses), in file units.
    pub height: f32,
    /// The figure's size the units come from: its largest spread, in motion or at rest.
    pub size: f32,
    /// Frames looked at (0: the rest pose).
    pub poses: usize,
    /// The offset mode the poses were computed in: the one asked for, or the other when the
    /// file clearly looks written for it (otherwise its bones collapse and say nothing).
    pub mode: OffsetMode,
}

/// The spread of `points` along each axis (max − min), and the box's low corner.
fn spread(points: impl Iterator<Item = Vec3>) -> Option<(Vec3, Vec3)> {
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for p in points {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    (lo.x <= hi.x).then(|| (hi - lo, lo))
}

fn median(values: &mut [f32]) -> f32 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f32::total_cmp);
    values[values.len() / 2]
}

/// Whether the skeleton is CMU's (its hip joints are named as CMU's ASF files name them, which
/// cgspeed's BVH conversions keep).
fn is_cmu_skeleton(skeleton: &Skeleton) -> bool {
    let has = |name: &str| {
        skeleton
            .joints
            .iter()
            .any(|j| j.name.eq_ignore_ascii_case(name))
    };
    (has("LHipJoint") && has("RHipJoint")) || (has("lhipjoint") && has("lfemur"))
}

/// The points the figure's spread is measured on: every point but the roots (a root may stand
/// far from the figure, as Bandai's joint_Root does on the floor), unless that leaves nothing.
fn body_points(skeleton: &Skeleton) -> Vec<usize> {
    let children: Vec<usize> = (0..skeleton.joints.len())
        .filter(|&i| skeleton.joints[i].parent.is_some())
        .collect();
    if children.len() > 1 {
        children
    } else {
        (0..skeleton.joints.len()).collect()
    }
}

/// The frames looked at: every one of `frames`, or [`SAMPLED_POSES`] spread evenly from the
/// first to the last.
fn sampled_frames(frames: usize) -> Vec<usize> {
    if frames <= SAMPLED_POSES {
        (0..frames).collect()
    } else {
        (0..SAMPLED_POSES)
            .map(|i| i * (frames - 1) / (SAMPLED_POSES - 1))
            .collect()
    }
}

/// The figure's spread in each pose looked at, and how far its root travels.
struct Spreads {
    spreads: Vec<Vec3>,
    root_travel: Vec3,
}

impl Spreads {
    /// The spreads of `body` in the `sampled` frames (the rest pose's, `rest_spread`, without
    /// frames), and the box of the root's path.
    fn measure(
        skeleton: &Skeleton,
        motion: &Motion,
        mode: OffsetMode,
        body: &[usize],
        sampled: &[usize],
        rest_spread: Vec3,
    ) -> Spreads {
        let root = skeleton.roots().next();
        let mut spreads: Vec<Vec3> = Vec::with_capacity(sampled.len().max(1));
        let (mut path_lo, mut path_hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        if sampled.is_empty() {
            spreads.push(rest_spread);
        } else {
            let plan = FkPlan::new(skeleton, mode);
            let (mut batch, mut scratch) = (Vec::new(), FkScratch::default());
            let joints = skeleton.joints.len();
            // Eight sampled poses side by side, as the FK plan computes them.
            for frames in sampled.chunks(crate::model::pose::LANES) {
                let rows: Vec<&[f32]> = frames.iter().map(|&f| motion.frame(f)).collect();
                plan.positions_of_frames(&rows, &mut batch, &mut scratch);
                pose_spreads(
                    &batch,
                    joints,
                    body,
                    root,
                    &mut spreads,
                    &mut path_lo,
                    &mut path_hi,
                );
            }
        }
        let root_travel = if path_lo.x <= path_hi.x {
            path_hi - path_lo
        } else {
            Vec3::ZERO
        };
        Spreads {
            spreads,
            root_travel,
        }
    }
}

/// Which way the figure stands, and what says so.
struct Upright {
    up: Up,
    sureness: Sureness,
    /// The root's path decided (the spread did not).
    by_path: bool,
    legs_not_two: Option<usize>,
}

impl Upright {
    /// Up: the axis the figure spreads along most of y and z; when neither clearly wins, the
    /// one the root travels along least, if it travels; else BVH's Y.
    fn guess(skeleton: &Skeleton, spread: Vec3, root_travel: Vec3, size: f32) -> Upright {
        let (y, z) = (spread.y, spread.z);
        let (mut up, mut up_sureness, mut up_by_path) = (Up::Y, Sureness::Unsure, false);
        let legs_not_two = Body::of(skeleton).legs_not_two(skeleton);
        if skeleton.y_up_stated {
            up_sureness = Sureness::Stated;
        } else if legs_not_two.is_some() {
            // A hand or a crab lies as flat as it stands: no body to stand it up by.
        } else if y.max(z) > 1e-6 {
            let ratio = y.max(z) / y.min(z).max(1e-6);
            if ratio >= LIKELY {
                up = if z > y { Up::Z } else { Up::Y };
                up_sureness = if ratio >= SURE {
                    Sureness::Sure
                } else {
                    Sureness::Likely
                };
            } else {
                let (ty, tz) = (root_travel.y, root_travel.z);
                if ty.max(tz) >= 0.5 * size && ty.max(tz) >= SURE * ty.min(tz) {
                    up = if ty > tz { Up::Z } else { Up::Y };
                    up_sureness = Sureness::Likely;
                    up_by_path = true;
                }
            }
        }
        Upright {
            up,
            sureness: up_sureness,
            by_path: up_by_path,
            legs_not_two,
        }
    }
}

/// The units: those the file states, CMU's for CMU's skeleton of a person's size in them, else
/// the guess from the figure's `size`.
fn units_of(
    skeleton: &Skeleton,
    stated: Option<(Units, UnitsBasis)>,
    size: f32,
) -> (Units, Sureness, UnitsBasis) {
    match stated {
        Some((units, basis)) => (units, Sureness::Stated, basis),
        None if is_cmu_skeleton(skeleton) && (1.0..=2.4).contains(&(size * CMU_UNITS.metres)) => {
            (CMU_UNITS, Sureness::Stated, UnitsBasis::CmuSkeleton)
        }
        None => {
            let (units, sureness) = Units::guess_with_sureness(size);
            (units, sureness, UnitsBasis::Size)
        }
    }
}

impl Stance {
    /// The guess for `skeleton` with `motion`, its poses computed in `mode` (or the other mode
    /// when the file looks written for it). `stated`: units the file states (an ASF's).
    pub fn guess(
        skeleton: &Skeleton,
        motion: &Motion,
        mode: OffsetMode,
        stated: Option<Units>,
    ) -> Stance {
        Stance::guess_stated(skeleton, motion, mode, stated.map(|u| (u, UnitsBasis::Asf)))
    }

    /// [`Stance::guess`] with the units stated and what states them (the file's ASF
    /// `:units`, or the caller: [`UnitsBasis::Given`]).
    pub fn guess_stated(
        skeleton: &Skeleton,
        motion: &Motion,
        mode: OffsetMode,
        stated: Option<(Units, UnitsBasis)>,
    ) -> Stance {
        let mode = crate::model::pose::guessed_mode(skeleton, motion, mode);
        let body = body_points(skeleton);
        let rest = world_positions(skeleton, &[], mode);
        let rest_spread = spread(body.iter().map(|&i| rest[i])).map_or(Vec3::ZERO, |(s, _)| s);
        let sampled = sampled_frames(motion.frame_count());
        let Spreads {
            spreads,
            root_travel,
        } = Spreads::measure(skeleton, motion, mode, &body, &sampled, rest_spread);
        let axis_median =
            |axis: usize| median(&mut spreads.iter().map(|s| s[axis]).collect::<Vec<_>>());
        let spread = Vec3::new(axis_median(0), axis_median(1), axis_median(2));
        let largest = median(&mut spreads.iter().map(|s| s.max_element()).collect::<Vec<_>>());
        let size = largest.max(rest_spread.max_element());

        let upright = Upright::guess(skeleton, spread, root_travel, size);
        let height = median(
            &mut spreads
                .iter()
                .map(|s| match upright.up {
                    Up::Y => s.y,
                    Up::Z => s.z,
                })
                .collect::<Vec<_>>(),
        );
        let (units, units_sureness, units_basis) = units_of(skeleton, stated, size);
        Stance {
            up: upright.up,
            up_sureness: upright.sureness,
            up_given: false,
            up_by_path: upright.by_path,
            legs_not_two: upright.legs_not_two,
            spread,
            root_travel,
            units,
            units_sureness,
            units_basis,
            height,
            size,
            poses: sampled.len(),
            mode,
        }
    }

    /// The guess from the rest pose alone (what a take without frames gets from [`Stance::guess`]).
    pub fn at_rest(skeleton: &Skeleton, mode: OffsetMode) -> Stance {
        let channels = skeleton.channel_count();
        Stance::guess(
            skeleton,
            &Motion::new(0.0, channels, 0, Vec::new()),
            mode,
            None,
        )
    }

    /// This stance with the up axis the caller gives (`--up`, `up=`) over the guess: the height
    /// measured along it, said as given.
    ///
    /// ```
    /// use bvhview::Take;
    /// use bvhview::model::pose::{OffsetMode, Up};
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let walk = Take::open("tests/data/bvh/makehuman_walk1.bvh")?.stance(OffsetMode::Replace);
    /// assert_eq!(walk.up, Up::Z);
    /// let given = walk.with_up(Up::Y);
    /// assert!(given.up_given && given.up == Up::Y && given.height < walk.height);
    /// # Ok(())
    /// # }
    /// ```
    pub fn with_up(mut self, up: Up) -> Stance {
        self.height = self.height_along(up);
        self.up = up;
        self.up_sureness = Sureness::Stated;
        self.up_by_path = false;
        self.up_given = true;
        self
    }

    /// The figure's height standing, in the file's units: the guess's, or, when `--up` asks for
    /// the other axis, the figure's spread along it (the median over the frames looked at).
    pub fn height_along(&self, up: Up) -> f32 {
        if up == self.up {
            self.height
        } else {
            match up {
                Up::Y => self.spread.y,
                Up::Z => self.spread.z,
            }
        }
    }

    /// `info`'s line on the up axis: the guess and what it rests on.
    pub fn up_text(&self) -> String {
        let axis = match self.up {
            Up::Y => "y",
            Up::Z => "z",
        };
        let poses = self.poses_text();
        let why = if self.up_given {
            "given, not guessed".to_string()
        } else if self.up_sureness == Sureness::Stated {
            "the file states its axes".to_string()
        } else if let Some(legs) = self.legs_not_two {
            let what = match legs {
                0 => "no legs, a hand or part of a body".to_string(),
                n => format!(
                    "{} legs, not a two-legged body",
                    crate::model::body::count_word(n)
                ),
            };
            format!("{what}: no body to guess it from, the file's own y")
        } else if self.up_by_path {
            format!(
                "the root travels {} along y and {} along z over {poses}",
                short(self.root_travel.y),
                short(self.root_travel.z)
            )
        } else if self.up_sureness == Sureness::Unsure {
            format!(
                "the figure spreads {} along y and {} along z over {poses}: BVH's usual y",
                short(self.spread.y),
                short(self.spread.z)
            )
        } else {
            format!(
                "the figure spreads {} along y and {} along z over {poses}",
                short(self.spread.y),
                short(self.spread.z)
            )
        };
        format!("{axis} ({}: {why})", self.up_sureness.word())
    }

    /// `info`'s line on the units: the guess, what it rests on and the height it gives.
    pub fn units_text(&self) -> String {
        let why = match self.units_basis {
            UnitsBasis::Asf => "the ASF's :units".to_string(),
            UnitsBasis::Fbx => "the FBX's UnitScaleFactor".to_string(),
            UnitsBasis::Amass => "AMASS's metres".to_string(),
            UnitsBasis::CmuSkeleton => "CMU's skeleton (LHipJoint, RHipJoint)".to_string(),
            UnitsBasis::Size => format!("the figure spans {}", short(self.size)),
            UnitsBasis::Given => "given, not guessed".to_string(),
        };
        format!(
            "{} ({}: {why}; it stands {} tall, {} m)",
            self.units.name,
            self.units_sureness.word(),
            short(self.height),
            short(self.height * self.units.metres)
        )
    }

    fn poses_text(&self) -> String {
        match self.poses {
            0 => "the rest pose".to_string(),
            1 => "1 frame".to_string(),
            n => format!("{n} frames"),
        }
    }
}

/// A length with three significant digits.
fn short(value: f32) -> String {
    let value = f64::from(value);
    if value == 0.0 || !value.is_finite() {
        return format!("{value}");
    }
    let digits = (2 - value.abs().log10().floor() as i32).max(0) as usize;
    format!("{value:.digits$}")
}

/// Units an ASF's `:units length` states: CMU's 0.45 (lengths in 1/0.45 inch). Other values
/// are left to the size guess: the Acclaim format does not say what a length of 1 is.
pub fn asf_units(length: f64) -> Option<Units> {
    ((length - 0.45).abs() < 1e-9).then_some(CMU_UNITS)
}

/// The spread of the body points and the root's place in each pose of `batch` (poses of
/// `joints` points one after the other), added to the lists; points that are not finite are
/// left out.
fn pose_spreads(
    batch: &[Vec3],
    joints: usize,
    body: &[usize],
    root: Option<usize>,
    spreads: &mut Vec<Vec3>,
    path_lo: &mut Vec3,
    path_hi: &mut Vec3,
) {
    for points in batch.chunks(joints.max(1)) {
        let finite = |p: &Vec3| p.is_finite();
        if let Some((s, _)) = spread(body.iter().map(|&i| points[i]).filter(finite)) {
            spreads.push(s);
        }
        if let Some(root) = root.filter(|&r| points[r].is_finite()) {
            *path_lo = path_lo.min(points[root]);
            *path_hi = path_hi.max(points[root]);
        }
    }
}
