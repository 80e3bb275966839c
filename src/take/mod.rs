//! The front door: a take (a skeleton, its motion, its rate and where it came from) opened from
//! any format by its extension, saved as BVH or glTF, and the operations on it one call away.
//!
//! ```
//! use bvhview::take::Take;
//!
//! # fn main() -> Result<(), bvhview::Error> {
//! let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
//! assert_eq!(take.frame_count(), 344);
//! // Every joint and End Site, named as the exports name them (`Head_End`).
//! let names = take.point_names();
//! let at = |name: &str| names.iter().position(|n| n == name).unwrap();
//! let points = take.positions(10).unwrap();
//! assert!(points[at("Head_End")].y > points[at("Hips")].y, "the head is above the hips");
//! assert!(take.positions(344).is_none(), "frames past the end are None");
//! # Ok(())
//! # }
//! ```

use crate::acclaim;
use crate::bvh;
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::motion::Motion;
use crate::model::pose::OffsetMode;
use crate::model::skeleton::Skeleton;
use std::path::Path;

pub(crate) mod bundled;
pub(crate) mod format;
pub(crate) mod options;

use bundled::{DEFAULT_MOTION, DEFAULT_MOTION_NAME};
pub use format::Format;
pub(crate) use format::extension;
pub use options::{DEFAULT_MAX_SIZE, OpenOptions};

/// A skeleton and its motion, from whichever format, with what the file said once and where it
/// came from. Python's `bvhview.Motion` is this type; its methods have the same names.
///
/// ```
/// use bvhview::Take;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// assert_eq!(walk.fps().round(), 120.0);
/// let short = walk.trim(0..12).mirror()?;
/// assert_eq!(short.frame_count(), 12);
/// assert_eq!(short.frame(0).map(|values| values.len()), walk.frame(0).map(|v| v.len()));
/// let path = std::env::temp_dir().join("bvhview-take-example.bvh");
/// short.save(&path)?;
/// assert_eq!(Take::open(&path)?.frame_count(), 12);
/// # std::fs::remove_file(&path).ok();
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Take {
    /// The joints, in pre-order.
    pub skeleton: Skeleton,
    /// The frames, one column per channel of `skeleton`.
    pub motion: Motion,
    /// What the file said once: things accepted that deserve a word (a warning may name an
    /// argument, as [`Error`]'s messages do).
    pub warnings: Vec<Message>,
    /// The units the file states (an ASF's `:units length`, the `UnitScaleFactor` of an FBX
    /// take read in its own units), if any.
    pub stated_units: Option<crate::model::stance::Units>,
    /// Whether `stated_units` were given by the caller ([`OpenOptions::units`]) rather than
    /// stated by the file.
    pub units_given: bool,
    /// The up axis the caller gave ([`OpenOptions::up`]), over the guess.
    pub stated_up: Option<crate::model::pose::Up>,
    /// What messages call it: its path, or "the bundled walk".
    pub name: String,
    /// The format it was read from; `None` for a take made in memory.
    pub format: Option<Format>,
    /// The name of the take chosen in a file that holds several (an FBX animation stack, a
    /// glTF animation).
    pub take_name: Option<String>,
    /// How position channels meet the OFFSET in [`Take::positions`], [`Take::ground`] and a
    /// glTF save: replace it (the article's reading, the default) or add to it.
    pub offset_mode: OffsetMode,
    /// The SMPL-family body an AMASS file said (its betas and gender), kept while the skeleton
    /// and its lengths are the file's, for an AMASS file written from the take.
    pub body: Option<crate::smpl::Body>,
}

impl Take {
    /// A take made in memory, called `name`: no format, no warnings, no stated units, the
    /// article's offset mode.
    pub fn new(skeleton: Skeleton, motion: Motion, name: impl Into<String>) -> Take {
        Take {
            skeleton,
            motion,
            warnings: Vec::new(),
            stated_units: None,
            units_given: false,
            stated_up: None,
            name: name.into(),
            format: None,
            take_name: None,
            offset_mode: OffsetMode::Replace,
            body: None,
        }
    }

    /// A take read from a file of `format`, with what the file said once.
    fn read(
        skeleton: Skeleton,
        motion: Motion,
        warnings: impl IntoIterator<Item = impl Into<Message>>,
        format: Format,
        name: String,
    ) -> Take {
        Take {
            warnings: warnings.into_iter().map(Into::into).collect(),
            format: Some(format),
            ..Take::new(skeleton, motion, name)
        }
    }

    /// A reader's take, its frame time overridden by `frame_time` when given.
    fn of_read(
        read: crate::model::reading::Read,
        format: Format,
        frame_time: Option<f64>,
        name: String,
    ) -> Take {
        let mut motion = read.motion;
        if let Some(time) = frame_time {
            motion.frame_time = time;
        }
        Take {
            take_name: read.take,
            stated_units: read.stated_units,
            ..Take::read(read.skeleton, motion, read.warnings, format, name)
        }
    }

    /// The bundled walk: the take the window and `snapshot` show when given no file.
    ///
    /// ```
    /// let walk = bvhview::Take::bundled()?;
    /// assert_eq!(walk.skeleton.joints[0].name, "Hips");
    /// # Ok::<(), bvhview::Error>(())
    /// ```
    pub fn bundled() -> Result<Take, Error> {
        let file = bvh::load_bytes(DEFAULT_MOTION, DEFAULT_MOTION_NAME)?;
        Ok(Take::read(
            file.skeleton,
            file.motion,
            file.warnings,
            Format::Bvh,
            DEFAULT_MOTION_NAME.to_string(),
        ))
    }

    /// How the take stands (up axis, units, height), guessed from its motion in `mode`.
    pub fn stance(&self, mode: OffsetMode) -> crate::model::stance::Stance {
        use crate::model::stance::UnitsBasis;
        let basis = if self.units_given {
            UnitsBasis::Given
        } else if self.format == Some(Format::Fbx) {
            UnitsBasis::Fbx
        } else if self.format == Some(Format::Amass) {
            UnitsBasis::Amass
        } else {
            UnitsBasis::Asf
        };
        let stated = self.stated_units.map(|units| (units, basis));
        let stance =
            crate::model::stance::Stance::guess_stated(&self.skeleton, &self.motion, mode, stated);
        match self.stated_up {
            Some(up) => stance.with_up(up),
            None => stance,
        }
    }

    /// Opens a take by its file's extension: `.bvh`, `.fbx`, `.gltf`, `.glb`, or an `.asf`
    /// skeleton in its rest pose (its motion through [`OpenOptions::motion`]). An FBX or glTF
    /// file's first take; [`OpenOptions::take`] picks another.
    pub fn open(path: impl AsRef<Path>) -> Result<Take, Error> {
        OpenOptions::new().open(path)
    }

    /// Opens a take with options.
    ///
    /// ```
    /// use bvhview::take::{OpenOptions, Take};
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let options = OpenOptions::new().motion("tests/data/asf_amc/heiden_12_02_01.amc");
    /// let take = Take::open_with("tests/data/asf_amc/heiden_12.asf", &options)?;
    /// assert_eq!(take.format, Some(bvhview::take::Format::AsfAmc));
    /// assert!(take.frame_count() > 0);
    /// # Ok(())
    /// # }
    /// ```
    pub fn open_with(path: impl AsRef<Path>, options: &OpenOptions) -> Result<Take, Error> {
        options.open(path)
    }

    /// Writes the take by the extension of `path`: `.bvh`, glTF as `.glb` (binary) or `.gltf`
    /// (text, data inline), `.fbx` (FBX 7.4 binary, in centimetres), or `.npz` (AMASS's layout,
    /// for a take on a SMPL-family skeleton: [`Take::amass`]). The file is written whole or not
    /// at all.
    ///
    /// ```
    /// use bvhview::take::Take;
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let folder = tempfile::tempdir().unwrap();
    /// let take = Take::open("tests/data/bvh/bvhparser_simple.bvh")?;
    /// let copy = folder.path().join("copy.bvh");
    /// take.save(&copy)?;
    /// assert_eq!(Take::open(&copy)?.motion, take.motion);
    /// # Ok(())
    /// # }
    /// ```
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), Error> {
        let path = path.as_ref();
        let bytes = match extension(path).as_str() {
            "bvh" => self.bvh_text()?.into_bytes(),
            "glb" => self.gltf(crate::gltf::Container::Glb)?,
            "gltf" => self.gltf(crate::gltf::Container::Gltf)?,
            "fbx" => self.fbx_bytes(None, &path.display().to_string())?,
            "npz" => self.amass()?.0,
            other => {
                return Err(Error::usage(format!(
                    "{}: save writes .bvh, .glb, .gltf, .fbx or .npz files, not '{other}'",
                    path.display()
                )));
            }
        };
        crate::io::output::AtomicFile::write_whole(path, &bytes)
    }

    /// The take as AMASS's `.npz` (SMPL, SMPL-H or SMPL-X parameters, by the joints its
    /// skeleton has), and what is said of it: the take must be on a SMPL-family skeleton (the
    /// built-in `smpl22`, `smpl24`, `smplh52`, `smplx55`, an AMASS file read, a take retargeted
    /// onto one). See [`crate::smpl::amass::of_take`].
    ///
    /// ```
    /// use bvhview::Take;
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let walk = Take::open("tests/data/smpl/amass_smplh_walk.npz")?;
    /// let (bytes, said) = walk.amass()?;
    /// assert!(bytes.starts_with(b"PK") && said.is_empty());
    /// let back = bvhview::OpenOptions::new()
    ///     .format(bvhview::take::Format::Amass)
    ///     .open_bytes(&bytes, "back.npz")?;
    /// assert_eq!(back.frame_count(), walk.frame_count());
    /// # Ok(())
    /// # }
    /// ```
    pub fn amass(&self) -> Result<(Vec<u8>, Vec<Message>), Error> {
        let stance = self.stance(self.offset_mode);
        let params = crate::smpl::amass::of_take(
            &self.skeleton,
            &self.motion,
            self.offset_mode,
            f64::from(stance.units.metres),
            stance.up,
            self.body.as_ref(),
            &self.name,
        )?;
        Ok((crate::smpl::amass::to_npz(&params)?, params.warnings))
    }

    /// The take as BVH text. A skeleton with fixed bone axes (ASF) has them baked into its
    /// rotations first: BVH has none.
    pub fn bvh_text(&self) -> Result<String, Error> {
        let baked = crate::edit::baked_for_bvh(&self.skeleton, &self.motion)?;
        let (skeleton, motion) = baked
            .as_ref()
            .map_or((&self.skeleton, &self.motion), |(s, m)| (s, m));
        crate::bvh::writer::to_string(skeleton, motion)
    }

    /// The take as the bytes of a glTF file (no skin).
    pub fn gltf(&self, container: crate::gltf::Container) -> Result<Vec<u8>, Error> {
        crate::gltf::to_gltf(
            &self.skeleton,
            &self.motion,
            self.offset_mode,
            container,
            false,
        )
    }

    /// The take as an FBX 7.4 binary file in centimetres, its units and up axis as
    /// [`Take::stance`] reads them; the animation stack is named after the take.
    #[cfg(feature = "fbx")]
    pub fn fbx(&self) -> Result<crate::fbx::write::Written, Error> {
        crate::fbx::write::to_bytes(&self.skeleton, &self.motion, &self.fbx_settings(0.01))
    }

    /// [`Take::fbx`] written in `units` instead of centimetres (`UnitScaleFactor` says them).
    ///
    /// ```
    /// use bvhview::{Take, model::stance::Units};
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let take = Take::open("tests/data/bvh/bvhparser_simple.bvh")?;
    /// let metres = take.fbx_in(Units::named("m").unwrap())?;
    /// assert!(metres.bytes.starts_with(b"Kaydara FBX Binary"));
    /// # Ok(())
    /// # }
    /// ```
    #[cfg(feature = "fbx")]
    pub fn fbx_in(
        &self,
        units: crate::model::stance::Units,
    ) -> Result<crate::fbx::write::Written, Error> {
        let settings = self.fbx_settings(f64::from(units.metres));
        crate::fbx::write::to_bytes(&self.skeleton, &self.motion, &settings)
    }

    /// [`Take::fbx`] with a character's mesh bound to the joints (`mesh` bound to this take's
    /// skeleton, as [`crate::character::Character::dress`] gives it): an animated skinned
    /// character in one file.
    ///
    /// ```
    /// # fn main() -> Result<(), bvhview::Error> {
    /// use bvhview::character::Character;
    ///
    /// let kenney = Character::open("tests/data/characters/maya_kenney_character_7700_binary.fbx")?;
    /// let written = kenney.take.fbx_character(&kenney.mesh)?;
    /// assert!(written.bytes.starts_with(b"Kaydara FBX Binary"));
    /// # Ok(())
    /// # }
    /// ```
    #[cfg(feature = "fbx")]
    pub fn fbx_character(
        &self,
        mesh: &crate::model::mesh::Mesh,
    ) -> Result<crate::fbx::write::Written, Error> {
        self.fbx_character_in(mesh, crate::model::stance::Units::of_metres(0.01))
    }

    /// [`Take::fbx_character`] written in `units` instead of centimetres.
    #[cfg(feature = "fbx")]
    pub fn fbx_character_in(
        &self,
        mesh: &crate::model::mesh::Mesh,
        units: crate::model::stance::Units,
    ) -> Result<crate::fbx::write::Written, Error> {
        // The mesh is bound to joints whose OFFSETs position channels replace, as glTF's
        // character is written.
        let settings = crate::fbx::write::Settings {
            offset_mode: crate::model::pose::OffsetMode::Replace,
            ..self.fbx_settings(f64::from(units.metres))
        };
        crate::fbx::write::character_to_bytes(&self.skeleton, &self.motion, mesh, &settings)
    }

    /// What an FBX file of this take states: its name, units and up axis as
    /// [`Take::stance`] reads them, written in `out_metres_per_unit` (0.01: centimetres).
    #[cfg(feature = "fbx")]
    fn fbx_settings(&self, out_metres_per_unit: f64) -> crate::fbx::write::Settings {
        let stance = self.stance(self.offset_mode);
        crate::fbx::write::Settings {
            take_name: self.take_label(),
            offset_mode: self.offset_mode,
            metres_per_unit: f64::from(stance.units.metres),
            up: stance.up,
            out_metres_per_unit,
        }
    }

    /// [`Take::fbx`]'s bytes (with `mesh`: [`Take::fbx_character`]'s), or what this build
    /// lacks to make them; `output` names the file.
    pub(crate) fn fbx_bytes(
        &self,
        mesh: Option<&crate::model::mesh::Mesh>,
        output: &str,
    ) -> Result<Vec<u8>, Error> {
        #[cfg(feature = "fbx")]
        {
            let _ = output;
            Ok(match mesh {
                Some(mesh) => self.fbx_character(mesh)?.bytes,
                None => self.fbx()?.bytes,
            })
        }
        #[cfg(not(feature = "fbx"))]
        {
            let _ = mesh;
            Err(crate::io::absent::without("fbx", "FBX", output))
        }
    }

    /// What a take is called inside a file that names takes: the take chosen in the file it
    /// came from, else its file's name without the extension.
    pub fn take_label(&self) -> String {
        if let Some(name) = &self.take_name {
            return name.clone();
        }
        let stem = Path::new(&self.name)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned());
        stem.filter(|s| !s.is_empty())
            .unwrap_or_else(|| "Take".to_string())
    }

    /// Frames in the take.
    pub fn frame_count(&self) -> usize {
        self.motion.frame_count()
    }

    /// Seconds per frame.
    pub fn frame_time(&self) -> f64 {
        self.motion.frame_time
    }

    /// Frames per second (1 / frame time).
    pub fn fps(&self) -> f64 {
        1.0 / self.motion.frame_time
    }

    /// The channel values of frame `index`, in file order; `None` past the last frame.
    pub fn frame(&self, index: usize) -> Option<&[f32]> {
        self.motion.get(index)
    }

    /// The names of the points [`Take::positions`] gives, as every export names them: each
    /// joint, and each End Site as `<parent>_End` (ASF: the root, then each bone's end).
    pub fn point_names(&self) -> Vec<String> {
        crate::positions::export_points(&self.skeleton)
            .into_iter()
            .map(|(name, _)| name)
            .collect()
    }

    /// Every joint's world position at frame `index` (the last frame past the end, the rest
    /// pose with none), in 64-bit floats, in the take's own units, axes and offset mode: one a
    /// joint, End Sites too, by joint index (an ASF's [`Take::positions`] are its exported
    /// points, which are not one a joint).
    ///
    /// ```
    /// let walk = bvhview::Take::open("tests/data/bvh/bvh11_131_01.bvh")?;
    /// let places = walk.joint_places(10);
    /// assert_eq!(places.len(), walk.skeleton.joints.len());
    /// # Ok::<(), bvhview::Error>(())
    /// ```
    pub fn joint_places(&self, index: usize) -> Vec<glam::DVec3> {
        let last = self.frame_count().saturating_sub(1);
        let row = self.motion.frame(index.min(last));
        let mut world = Vec::new();
        crate::model::pose::world_transforms_f64(&self.skeleton, row, self.offset_mode, &mut world);
        world.into_iter().map(|(_, place)| place).collect()
    }

    /// The world position of every point at frame `index` (forward kinematics, in the
    /// take's own units and axes), in [`Take::point_names`]' order; `None` past the last frame.
    pub fn positions(&self, index: usize) -> Option<Vec<glam::Vec3>> {
        let frame = self.frame(index)?;
        let joints = crate::model::pose::world_positions(&self.skeleton, frame, self.offset_mode);
        Some(
            crate::positions::export_points(&self.skeleton)
                .into_iter()
                .map(|(_, joint)| joints[joint])
                .collect(),
        )
    }

    /// What the caller says the take is, over the guess: its units (`--units`, `units=`; then
    /// [`Take::units_given`]) and the axis it stands along ([`Take::stand_along`]). The one way
    /// every reader, command and Python loader takes them.
    ///
    /// ```
    /// use bvhview::Take;
    /// use bvhview::model::{pose::{OffsetMode, Up, UpAxis}, stance::Units};
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let mut walk = Take::open("tests/data/bvh/makehuman_walk1.bvh")?;
    /// walk.given(Units::named("cm"), Some(UpAxis::Y))?;
    /// let stance = walk.stance(OffsetMode::Replace);
    /// assert!(walk.units_given && stance.up_given && stance.up == Up::Y);
    /// assert_eq!(stance.units.name, "centimetres");
    /// # Ok(())
    /// # }
    /// ```
    pub fn given(
        &mut self,
        units: Option<crate::model::stance::Units>,
        up: Option<crate::model::pose::UpAxis>,
    ) -> Result<(), Error> {
        if let Some(units) = units {
            self.stated_units = Some(units);
            self.units_given = true;
        }
        match up {
            Some(axis) => self.stand_along(axis),
            None => Ok(()),
        }
    }

    /// The caller's word on the axis the take stands along, over the guess (`--up`, `up=`):
    /// along +y or +z it is kept as stated ([`Take::stated_up`]); along x, −x, −y or −z the
    /// take is turned exactly to stand along +y ([`crate::edit::reorient`]: every OFFSET and
    /// position moved to the turned axes, every rotation Q·R·Q⁻¹ in its joint's order) and a
    /// warning says so, for bvhview's stances stand along y or z. An ASF bone turns by its
    /// axis and a hinge (one or two rotations) is given one; a joint of one or two position
    /// channels cannot turn and refuses it by name.
    ///
    /// ```
    /// use bvhview::{OpenOptions, Take};
    /// use bvhview::model::pose::{OffsetMode, Up, UpAxis};
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let walk = Take::open("tests/data/bvh/makehuman_walk1.bvh")?; // stands along +z
    /// let mut upside_down = walk.clone();
    /// upside_down.stand_along(UpAxis::NegZ)?;
    /// let stance = upside_down.stance(OffsetMode::Replace);
    /// assert!(stance.up_given && stance.up == Up::Y);
    /// // Stood on its head: the feet are now above the hips.
    /// let joint = |name: &str| upside_down.skeleton.joints.iter().position(|j| j.name == name);
    /// let p = upside_down.positions(0).unwrap();
    /// assert!(p[joint("Foot_L").unwrap()].y > p[joint("Root").unwrap()].y);
    /// assert!(upside_down.warnings.iter().any(|w| w.to_string().contains("turned")));
    /// # Ok(())
    /// # }
    /// ```
    pub fn stand_along(&mut self, axis: crate::model::pose::UpAxis) -> Result<(), Error> {
        use crate::model::pose::{Up, UpAxis};
        if let Some(up) = axis.standing() {
            self.stated_up = Some(up);
            return Ok(());
        }
        let (skeleton, motion) =
            crate::edit::reorient(&self.skeleton, &self.motion, axis, UpAxis::Y)?;
        self.skeleton = skeleton;
        self.motion = motion;
        self.stated_up = Some(Up::Y);
        self.warnings.push(
            Message::of_argument("up", Some(&axis.to_string())).text(format!(
                ": turned to stand along +y as it was read ({} about {}), every position and \
                 rotation with it: bvhview stands takes along y or z",
                if axis == UpAxis::NegY {
                    "a half turn"
                } else {
                    "a quarter turn"
                },
                if matches!(axis, UpAxis::X | UpAxis::NegX) {
                    "z"
                } else {
                    "x"
                },
            )),
        );
        Ok(())
    }

    /// The take with `skeleton` and `motion` from an edit: the same name, format and warnings;
    /// the units a file stated kept only when the edit kept every length.
    pub fn edited(&self, skeleton: Skeleton, motion: Motion, same_lengths: bool) -> Take {
        Take {
            motion,
            warnings: self.warnings.clone(),
            stated_units: self.stated_units.filter(|_| same_lengths),
            units_given: self.units_given && same_lengths,
            // An edit keeps the axes (one that turns the take says its new up axis itself).
            stated_up: self.stated_up,
            name: self.name.clone(),
            format: self.format,
            take_name: self.take_name.clone(),
            offset_mode: self.offset_mode,
            body: self
                .body
                .clone()
                .filter(|_| same_lengths && skeleton == self.skeleton),
            skeleton,
        }
    }

    /// Frames `range` of the take (clamped to the frames there are).
    pub fn trim(&self, range: std::ops::Range<usize>) -> Take {
        let count = self.frame_count();
        let range = range.start.min(count)..range.end.clamp(range.start.min(count), count);
        self.edited(
            self.skeleton.clone(),
            crate::edit::trim(&self.motion, range),
            true,
        )
    }

    /// Every length (offsets and translations) times `factor`.
    pub fn scale(&self, factor: f32) -> Result<Take, Error> {
        let (skeleton, motion) = crate::edit::scale(&self.skeleton, &self.motion, factor)?;
        Ok(self.edited(skeleton, motion, factor == 1.0))
    }

    /// The take at `fps` frames per second (rotations interpolated on the sphere).
    pub fn resample(&self, fps: f64) -> Result<Take, Error> {
        let motion = crate::edit::resample(&self.skeleton, &self.motion, fps)?;
        Ok(self.edited(self.skeleton.clone(), motion, true))
    }

    /// Left and right swapped: each side's joints move as the other side's did, reflected.
    pub fn mirror(&self) -> Result<Take, Error> {
        let options = crate::edit::MirrorOptions::default();
        let (skeleton, motion) = crate::edit::mirror(&self.skeleton, &self.motion, &options)?;
        Ok(self.edited(skeleton, motion, true))
    }

    /// The root's travel over the floor taken out (its height kept).
    pub fn in_place(&self) -> Take {
        let up = self.stance(self.offset_mode).up;
        let motion = crate::edit::in_place(&self.skeleton, &self.motion, up);
        self.edited(self.skeleton.clone(), motion, true)
    }

    /// The take moved up or down so that its lowest point over all frames is on the floor.
    pub fn ground(&self) -> Result<Take, Error> {
        let up = self.stance(self.offset_mode).up;
        let (skeleton, motion) =
            crate::edit::ground(&self.skeleton, &self.motion, self.offset_mode, up)?;
        Ok(self.edited(skeleton, motion, true))
    }
}

/// The door itself: opening with these options, by the reader of the format.
impl OpenOptions {
    /// Opens the take at `path` with these options, in the format its extension names.
    pub fn open(&self, path: impl AsRef<Path>) -> Result<Take, Error> {
        let mut take = load_take(path.as_ref(), self)?;
        take.offset_mode = self.offset_mode.unwrap_or(OffsetMode::Replace);
        Ok(take)
    }

    /// Opens a take from bytes in memory (standard input, a download) with these options:
    /// in [`OpenOptions::format`], or the one its first bytes tell. `name` is what messages
    /// call it. A glTF read so has no folder, so its buffers must be inside it (GLB or data
    /// URIs); an ASF needs its AMC and is read from files only.
    ///
    /// ```
    /// use bvhview::take::{Format, OpenOptions};
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let bytes = std::fs::read("tests/oracle/inputs/tiny_crlf.bvh").unwrap();
    /// let take = OpenOptions::new().open_bytes(&bytes, "tiny")?;
    /// assert_eq!((take.format, take.name.as_str()), (Some(Format::Bvh), "tiny"));
    /// assert!(OpenOptions::new().format(Format::Fbx).open_bytes(&bytes, "tiny").is_err());
    /// # Ok(())
    /// # }
    /// ```
    pub fn open_bytes(&self, bytes: &[u8], name: &str) -> Result<Take, Error> {
        let mut take = give_units(self, load_bytes(bytes, name, self)?)?;
        take.offset_mode = self.offset_mode.unwrap_or(OffsetMode::Replace);
        Ok(take)
    }
}

/// The unit tests' shorthand for [`OpenOptions::open`] with an AMC and a frame time.
#[cfg(test)]
pub(crate) fn load(
    path: &Path,
    motion: Option<&Path>,
    frame_time: Option<f64>,
) -> Result<Take, Error> {
    let mut options = OpenOptions::new();
    options.motion = motion.map(Path::to_path_buf);
    options.frame_time = frame_time;
    options.open(path)
}

/// Fails unless `path` is a readable regular file of at most `max_size` bytes. A FIFO, a device
/// or a socket is refused by its type before any read (a FIFO would wait for a writer for good,
/// /dev/zero never ends); standard input is read as `-`.
pub(crate) fn check_file(path: &Path, max_size: u64) -> Result<(), Error> {
    let metadata = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if metadata.is_dir() {
        return Err(Error::usage(format!(
            "{}: is a folder, not a file (`bvhview info FOLDER` reads every file in one)",
            path.display()
        )));
    }
    if !metadata.is_file() {
        let what = crate::io::read::kind_of(&metadata.file_type());
        return Err(Error::usage(format!(
            "{}: {what}, not a regular file; bvhview reads takes from files (`-` reads standard \
             input)",
            path.display()
        )));
    }
    if metadata.len() > max_size {
        return Err(Error::too_big(
            &path.display().to_string(),
            metadata.len(),
            max_size,
        ));
    }
    Ok(())
}

/// The takes of an FBX or glTF file (name, frames, frame time), in file order; empty for the
/// formats that hold one take.
pub fn takes(path: &Path, max_size: u64) -> Result<Vec<crate::model::reading::TakeInfo>, Error> {
    check_file(path, max_size)?;
    match Format::from_path(path) {
        Some(Format::Fbx) => crate::fbx::takes(path, max_size),
        Some(Format::Gltf) => crate::gltf::takes(path, max_size),
        _ => Ok(Vec::new()),
    }
}

/// [`OpenOptions::open`]: the reader of the format `path`'s extension names.
pub(crate) fn load_take(path: &Path, options: &OpenOptions) -> Result<Take, Error> {
    give_units(options, load_take_as_written(path, options)?)
}

/// `take` with the units and up axis `options` give, if any, over its own.
fn give_units(options: &OpenOptions, mut take: Take) -> Result<Take, Error> {
    take.given(options.units, options.up)?;
    Ok(take)
}

/// [`load_take`] before the units the options give.
fn load_take_as_written(path: &Path, options: &OpenOptions) -> Result<Take, Error> {
    let max_size = options.max_size_or_default();
    let (motion, frame_time, take) = (
        options.motion.as_deref(),
        options.frame_time,
        options.take.as_deref(),
    );
    if let Some(built_in) = built_in_name(path) {
        return load_built_in(path, built_in, options);
    }
    check_file(path, max_size)?;
    if let Some(motion) = motion {
        check_file(motion, max_size)?;
    }
    crate::limits::frame_time_option(frame_time)?;
    let Some(format) = Format::from_path(path) else {
        return Err(Error::UnknownFormat {
            input: path.display().to_string(),
            extension: extension(path),
        });
    };
    if take.is_some() && !format.holds_several_takes() {
        return Err(Error::invalid(
            "take",
            "",
            format!(
                "{} holds one take (only FBX and glTF files hold several)",
                path.display()
            ),
        ));
    }
    if let Some(amc) = motion.filter(|_| format != Format::AsfAmc) {
        return Err(Error::invalid(
            "motion",
            amc.display().to_string(),
            "only an ASF skeleton takes a motion file",
        ));
    }
    let name = path.display().to_string();
    let read = match format {
        Format::AsfAmc if extension(path) == "amc" => {
            let shown = path.display().to_string();
            return Err(Error::usage(
                Message::from(format!(
                    "{shown}: an AMC file holds motion only; give its skeleton: "
                ))
                .opening("SKELETON.asf", "motion", &shown),
            ));
        }
        Format::AsfAmc => return load_asf_amc(path, options),
        Format::Fbx => crate::fbx::load(path, options)?,
        Format::Gltf => crate::gltf::load(path, options)?,
        Format::Amass => {
            let bytes = crate::io::whole::read_binary_file(path, max_size)?;
            return load_amass(&bytes, name, options);
        }
        Format::Bvh => {
            let settings = bvh::loader::Settings {
                threads: options.threads_or_cores(),
                max_size,
                ..Default::default()
            };
            let file = bvh::load_file(path, settings)?;
            crate::model::reading::Read {
                skeleton: file.skeleton,
                motion: file.motion,
                warnings: file.warnings.into_iter().map(Message::from).collect(),
                take: None,
                stated_units: None,
            }
        }
    };
    // FBX and glTF readers give metres (ufbx converts the FBX's UnitScaleFactor; glTF is metres
    // by definition); the stance's guess from the figure's size says so.
    Ok(Take::of_read(read, format, frame_time, name))
}

/// The take of an AMASS file's `bytes`, with the body it holds.
fn load_amass(bytes: &[u8], name: String, options: &OpenOptions) -> Result<Take, Error> {
    let (read, body) = crate::smpl::load_bytes(
        bytes,
        &name,
        options.frame_time,
        options.body_model.as_deref(),
        options.max_size_or_default(),
    )?;
    let mut take = Take::of_read(read, Format::Amass, options.frame_time, name);
    take.body = Some(body);
    Ok(take)
}

/// The built-in skeleton `path` names: a bare name without an extension or a folder, such as
/// `smpl22` (see [`crate::bvh::built_in::BUILT_IN`]).
fn built_in_name(path: &Path) -> Option<&'static str> {
    let name = path.to_str()?;
    if path.components().count() != 1 || !extension(path).is_empty() {
        return None;
    }
    crate::bvh::built_in::name_of(name)
}

/// A built-in skeleton as a take: its rest pose, one frame (its units guessed as a file's are:
/// every built-in stands a person's height in centimetres). A file of
/// that name in the current folder wins, read by its first bytes, and a warning says so.
fn load_built_in(path: &Path, name: &str, options: &OpenOptions) -> Result<Take, Error> {
    // Only a regular file of that name wins (a folder called smpl22 does not hide the built-in).
    if std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        let max_size = options.max_size_or_default();
        check_file(path, max_size)?;
        let bytes = crate::io::read::read_file(path, max_size)?;
        let mut take = load_bytes(&bytes, &path.display().to_string(), options)?;
        take.warnings.push(Message::from(format!(
            "the file '{}' in this folder was read, not the built-in skeleton {name} (give \
             another path to the file, or move it, to read the built-in one)",
            path.display()
        )));
        return Ok(take);
    }
    if options.motion.is_some() || options.take.is_some() {
        return Err(Error::usage(format!(
            "{name} is a built-in skeleton: its rest pose is its one take (no motion file, no \
             take to choose)"
        )));
    }
    let (skeleton, motion) = crate::bvh::built_in::built_in(name)
        .ok_or_else(|| Error::usage(format!("the built-in skeleton {name} does not load")))?;
    Ok(Take::read(
        skeleton,
        motion,
        Vec::<Message>::new(),
        Format::Bvh,
        name.to_string(),
    ))
}

/// An ASF skeleton at `path` with the AMC motion `options` names (none: its rest pose alone).
fn load_asf_amc(path: &Path, options: &OpenOptions) -> Result<Take, Error> {
    let max_size = options.max_size_or_default();
    let asf = acclaim::load_asf(path, max_size)?;
    let (skeleton, maps) = asf.to_skeleton();
    let frame_time = options.frame_time.unwrap_or(acclaim::DEFAULT_FRAME_TIME);
    let channels = skeleton.channel_count();
    let motion = match options.motion.as_deref() {
        Some(amc) => {
            if extension(amc) != "amc" {
                return Err(Error::invalid(
                    "motion",
                    amc.display().to_string(),
                    "expected an .amc file",
                ));
            }
            acclaim::load_amc(
                amc,
                max_size,
                &maps,
                channels,
                asf.units.degrees,
                frame_time,
            )?
        }
        None => Motion::new(frame_time, channels, 0, Vec::new()),
    };
    let mut warnings = asf.warnings;
    let motion = match acclaim::absolute::made_relative(&skeleton, &motion) {
        Some((relative, word)) => {
            warnings.push(word);
            relative
        }
        None => motion,
    };
    Ok(Take {
        stated_units: crate::model::stance::asf_units(asf.units.length),
        ..Take::read(
            skeleton,
            motion,
            warnings,
            Format::AsfAmc,
            path.display().to_string(),
        )
    })
}

/// [`OpenOptions::open_bytes`].
fn load_bytes(bytes: &[u8], name: &str, options: &OpenOptions) -> Result<Take, Error> {
    let (frame_time, take) = (options.frame_time, options.take.as_deref());
    crate::limits::frame_time_option(frame_time)?;
    if bytes.is_empty() {
        return Err(Error::usage(format!("{name}: empty: no take to read")));
    }
    let Some(format) = options.format.or_else(|| Format::sniff(bytes)) else {
        return Err(Error::usage(
            Message::from(format!(
                "{name}: not a take bvhview can tell by its first bytes; name its format with "
            ))
            .argument("format", Some("bvh, fbx, gltf or glb")),
        ));
    };
    if take.is_some() && !format.holds_several_takes() {
        return Err(Error::invalid(
            "take",
            "",
            format!("{name} is a BVH, which holds one take"),
        ));
    }
    let read = match format {
        Format::Bvh => {
            let file = bvh::load_bytes(bytes, name)?;
            crate::model::reading::Read {
                skeleton: file.skeleton,
                motion: file.motion,
                warnings: file.warnings.into_iter().map(Message::from).collect(),
                take: None,
                stated_units: None,
            }
        }
        Format::Fbx => crate::fbx::load_bytes(bytes, name, options)?,
        Format::Gltf => crate::gltf::load_bytes(bytes, name, options)?,
        Format::Amass => return load_amass(bytes, name.to_string(), options),
        Format::AsfAmc => {
            return Err(Error::usage(format!(
                "{name}: an ASF skeleton is read from a file, beside its AMC motion; bvhview \
                 reads bvh, fbx, gltf or glb from bytes"
            )));
        }
    };
    Ok(Take::of_read(read, format, frame_time, name.to_string()))
}
