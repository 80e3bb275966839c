//! What the window is given: how it starts, and its takes, each with where it was loaded from.

use crate::io::error::Error;
use crate::io::message::Spelling;
use crate::model::pose::OffsetMode;
use crate::render::draw::Style;
use crate::render::options::Look;
use crate::take::Take;
use std::path::PathBuf;

/// How the window starts.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    pub offset_mode: OffsetMode,
    pub style: Style,
    /// Start with the generated skin (K toggles it).
    pub skin: bool,
    /// The article's look or the studio's (V switches).
    pub look: Look,
    /// Say nothing on stderr about pictures written (P).
    pub quiet: bool,
    /// Several takes at their true sizes instead of the first one's height (`--true-scale`).
    pub true_scale: bool,
    /// Whether `style` was asked for (`--style`, or B since): V then leaves it as it is.
    pub style_chosen: bool,
    /// Record what the window shows into this MP4 from the start (`--record`; M stops).
    pub record: Option<PathBuf>,
    /// How messages on stderr and in the window write an argument (the command line's flags).
    pub spelling: &'static dyn Spelling,
}

/// Where a take was loaded from, to load it again (R).
#[derive(Clone, Debug)]
pub struct TakeSource {
    pub path: PathBuf,
    /// The AMC of an ASF skeleton.
    pub motion: Option<PathBuf>,
    pub frame_time: Option<f64>,
    pub max_size: u64,
    /// The take of an FBX or glTF file (`--take`).
    pub take: Option<String>,
    /// How far putting it on a character goes against the refusals (`--any-body`, `--force`).
    pub insist: crate::retarget::Insist,
    /// The SMPL-family model file an AMASS take's body is read with (`--body-model`).
    pub body_model: Option<PathBuf>,
    /// The units its lengths are in, over the guess (`--units`).
    pub units: Option<crate::model::stance::Units>,
    /// The axis it stands along, over the guess (`--up`): x, -x, -y and -z turn it to y as it
    /// is read.
    pub up: Option<crate::model::pose::UpAxis>,
}

impl TakeSource {
    pub(super) fn load(&self) -> Result<Take, Error> {
        let options = crate::take::OpenOptions {
            motion: self.motion.clone(),
            take: self.take.clone(),
            frame_time: self.frame_time,
            max_size: Some(self.max_size),
            body_model: self.body_model.clone(),
            units: self.units,
            up: self.up,
            ..Default::default()
        };
        crate::take::load_take(&self.path, &options)
    }
}

/// One take in the window.
#[derive(Clone, Debug)]
pub struct ViewerTake {
    /// Its file's name, for the title and the HUD.
    pub name: String,
    /// Where it came from; `None` for the bundled walk, which R leaves as it is.
    pub source: Option<TakeSource>,
    pub loaded: Take,
    /// Its up axis, asked for or guessed from the motion: a Z-up take is stood up in a view
    /// that frames it (see `Viewer::drawn_up`); the article's view draws it as written.
    pub up: crate::model::pose::Up,
    /// How it stands, guessed from its motion (its height and units size the studio).
    pub stance: crate::model::stance::Stance,
    /// The up axis `--up` asked for; without it, R guesses again from what it reads.
    pub up_asked: Option<crate::model::pose::Up>,
    /// The character the take is put on (`--character`): `loaded` is then the take retargeted
    /// onto its skeleton, and its mesh is drawn.
    pub character: Option<std::sync::Arc<crate::character::Character>>,
}

impl ViewerTake {
    /// The offset mode its bones are drawn in ([`OffsetMode::for_take`]).
    pub fn offset_mode(&self, asked: OffsetMode) -> OffsetMode {
        asked.for_take(self.character.is_some())
    }

    /// A take loaded from `source`, its up axis guessed, its warnings said on stderr.
    /// Arguments in the warnings are written as `spelling` writes them.
    pub fn from_source(
        source: TakeSource,
        mode: OffsetMode,
        spelling: &dyn Spelling,
    ) -> Result<ViewerTake, Error> {
        let loaded = source.load()?;
        for warning in &loaded.warnings {
            eprintln!(
                "bvhview: {}: warning: {}",
                source.path.display(),
                warning.spelled(spelling)
            );
        }
        let name = source.path.file_name().map_or_else(
            || source.path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let stance = loaded.stance(mode);
        Ok(ViewerTake {
            name,
            up: stance.up,
            stance,
            up_asked: None,
            source: Some(source),
            loaded,
            character: None,
        })
    }

    /// Puts the take on `character` (its take from the file retargeted onto the character's
    /// skeleton), its stance and up axis guessed again.
    pub fn put_on(
        &mut self,
        character: std::sync::Arc<crate::character::Character>,
        mode: OffsetMode,
        spelling: &dyn Spelling,
    ) -> Result<(), Error> {
        let threads = crate::io::parallel::cores();
        let (dressed, said) = match &self.source {
            Some(source) => {
                character.dress_file(&self.loaded, &source.path, source.insist, threads)?
            }
            None => character.dress(&self.loaded, &[], Default::default(), threads)?,
        };
        for warning in said.warnings(&self.name, &character.take.name) {
            eprintln!("bvhview: {}", warning.spelled(spelling));
        }
        if let Some(check) = &said.check {
            eprintln!(
                "{} onto {}: {}",
                self.name,
                character.take.name,
                check.line()
            );
        }
        self.loaded = dressed;
        self.character = Some(character);
        self.stance = self.loaded.stance(self.offset_mode(mode));
        self.up = self.up_asked.unwrap_or(self.stance.up);
        Ok(())
    }
}
