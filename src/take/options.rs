//! How a take is opened: the options every reader is given ([`OpenOptions`]), apart from the
//! readers themselves so that they can take them without depending on the front door.

use super::format::Format;
use crate::model::pose::OffsetMode;
use std::path::Path;

/// Files larger than this are refused unless `--max-size` says otherwise (8 GiB).
pub const DEFAULT_MAX_SIZE: u64 = 8 << 30;

/// How to open a take: options for [`Take::open_with`](crate::take::Take::open_with), each with a default, set in a chain.
///
/// ```
/// use bvhview::{OpenOptions, model::pose::OffsetMode};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let options = OpenOptions::new().frame_time(0.5).threads(1).offset_mode(OffsetMode::Add);
/// let take = options.open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// assert_eq!((take.fps(), take.offset_mode), (2.0, OffsetMode::Add));
/// // Files larger than `max_size` are refused before they are read.
/// assert!(OpenOptions::new().max_size(100).open("tests/oracle/inputs/tiny_crlf.bvh").is_err());
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default)]
pub struct OpenOptions {
    pub(crate) motion: Option<std::path::PathBuf>,
    pub(crate) take: Option<String>,
    pub(crate) frame_time: Option<f64>,
    pub(crate) max_size: Option<u64>,
    pub(crate) threads: Option<usize>,
    pub(crate) offset_mode: Option<OffsetMode>,
    pub(crate) format: Option<Format>,
    pub(crate) units: Option<crate::model::stance::Units>,
    pub(crate) up: Option<crate::model::pose::UpAxis>,
    pub(crate) body_model: Option<std::path::PathBuf>,
    pub(crate) betas: Option<Vec<f64>>,
}

impl OpenOptions {
    /// The defaults: an FBX or glTF file's first take, the file's own rate, files up to
    /// [`DEFAULT_MAX_SIZE`], every core, the article's offset mode, the format told by the
    /// path's extension (or by the first bytes, for [`OpenOptions::open_bytes`]).
    pub fn new() -> OpenOptions {
        OpenOptions::default()
    }

    /// The AMC motion of an ASF skeleton.
    pub fn motion(mut self, amc: impl AsRef<Path>) -> OpenOptions {
        self.motion = Some(amc.as_ref().to_path_buf());
        self
    }

    /// The take of an FBX or glTF file that holds several: its name, or its index in
    /// [`takes`](crate::take::takes).
    pub fn take(mut self, take: impl Into<String>) -> OpenOptions {
        self.take = Some(take.into());
        self
    }

    /// The user's SMPL-family model file (an `.npz`, or a folder with one per gender): an
    /// AMASS file's joints are then that body's, of the file's betas, not bvhview's built-in
    /// figure's.
    pub fn body_model(mut self, path: impl AsRef<Path>) -> OpenOptions {
        self.body_model = Some(path.as_ref().to_path_buf());
        self
    }

    /// The shape of a body model opened as a character ([`crate::character::Character`]):
    /// its first betas (the rest zero). Without them, the mean shape, or an AMASS take's own.
    pub fn betas(mut self, betas: &[f64]) -> OpenOptions {
        self.betas = Some(betas.to_vec());
        self
    }

    /// Seconds per frame, over the file's (AMC files state none: 1/120 by default).
    pub fn frame_time(mut self, seconds: f64) -> OpenOptions {
        self.frame_time = Some(seconds);
        self
    }

    /// Refuse files larger than this many bytes, before reading them.
    pub fn max_size(mut self, bytes: u64) -> OpenOptions {
        self.max_size = Some(bytes);
        self
    }

    /// Threads to read with (a BVH's rows, an FBX's frames).
    pub fn threads(mut self, threads: usize) -> OpenOptions {
        self.threads = Some(threads);
        self
    }

    /// How position channels meet the OFFSET: replace it (the default) or add to it.
    pub fn offset_mode(mut self, mode: OffsetMode) -> OpenOptions {
        self.offset_mode = Some(mode);
        self
    }

    /// The format of the bytes [`OpenOptions::open_bytes`] reads, rather than the one their
    /// first bytes tell ([`Format::sniff`]).
    pub fn format(mut self, format: Format) -> OpenOptions {
        self.format = Some(format);
        self
    }

    /// The units the take's lengths are in, over the guess (and over what the file states):
    /// every measure in metres (floor, framing, heights, retarget scale) takes them.
    ///
    /// ```
    /// use bvhview::{OpenOptions, model::stance::Units};
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// // A 61 cm figure in centimetres, which the guess would read as inches.
    /// let take = OpenOptions::new()
    ///     .units(Units::named("cm").unwrap())
    ///     .open("tests/data/bvh/bvhparser_simple.bvh")?;
    /// assert_eq!(take.stance(take.offset_mode).units.name, "centimetres");
    /// # Ok(())
    /// # }
    /// ```
    pub fn units(mut self, units: crate::model::stance::Units) -> OpenOptions {
        self.units = Some(units);
        self
    }

    /// The axis the take stands along, over the guess: every measure that needs it (floor,
    /// heights, retarget, datasets) takes it, and `info` says it was given.
    ///
    /// ```
    /// use bvhview::OpenOptions;
    /// use bvhview::model::pose::Up;
    ///
    /// # fn main() -> Result<(), bvhview::Error> {
    /// let take = OpenOptions::new().up(Up::Z).open("tests/data/bvh/makehuman_walk1.bvh")?;
    /// assert!(take.stance(take.offset_mode).up_given);
    /// # Ok(())
    /// # }
    /// ```
    ///
    /// Any signed axis may be given ([`UpAxis`](crate::model::pose::UpAxis)): a take stated
    /// to stand along x, −x, −y or −z is turned to stand along +y as it is read
    /// ([`Take::stand_along`](crate::Take::stand_along)).
    pub fn up(mut self, up: impl Into<crate::model::pose::UpAxis>) -> OpenOptions {
        self.up = Some(up.into());
        self
    }

    pub(crate) fn threads_or_cores(&self) -> usize {
        self.threads.unwrap_or_else(crate::io::parallel::cores)
    }

    pub(crate) fn max_size_or_default(&self) -> u64 {
        self.max_size.unwrap_or(DEFAULT_MAX_SIZE)
    }
}
