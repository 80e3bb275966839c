//! `--character` (the viewer, `snapshot`, `convert`, `positions`): the characters takes are put
//! on, loaded once each.

use super::{Source, note};
use crate::character::Character;
use crate::io::error::Error;
use crate::retarget::Insist;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// How far `--character` goes against the refusals of putting a take on a character.
#[derive(clap::Args, Clone, Copy, Debug, Default)]
pub(crate) struct Insisting {
    /// With --character: put the take on a character whose body is not two-legged like the
    /// take's (a person's walk on a four-legged character, or the reverse), which is refused
    /// otherwise: the limbs are carried over as a person's.
    #[arg(long, requires = "character")]
    pub any_body: bool,
    /// With --character: keep a take whose retarget onto the character's skeleton finds a side
    /// crossed or a width collapsed (legs crossing at the pelvis, both thighs from one point),
    /// which is refused otherwise; said as a warning.
    #[arg(long, requires = "character")]
    pub force: bool,
}

impl Insisting {
    pub(crate) fn insist(self) -> Insist {
        Insist {
            any_body: self.any_body,
            force: self.force,
        }
    }
}

/// `take` (read from `path`) on `character` ([`Character::dress_file`]; a body model shaped
/// by an AMASS take's betas first, [`Character::for_take`]), with what the retarget measured
/// said: its warnings always, its check line unless `-q`. The character it went on comes back
/// beside it.
pub(crate) fn dress(
    character: &Arc<Character>,
    take: &crate::Take,
    path: &Path,
    insist: Insist,
) -> Result<(crate::Take, Arc<Character>), Error> {
    let character = character.for_take(take)?;
    let (dressed, said) = character.dress_file(take, path, insist, crate::io::parallel::cores())?;
    let (take_name, character_name) = (path.display().to_string(), &character.take.name);
    for warning in said.warnings(&take_name, character_name) {
        eprintln!("bvhview: {}", warning.spelled(&super::Flags));
    }
    if let Some(check) = &said.check {
        note(format_args!(
            "{take_name} onto {character_name}: {}",
            check.line()
        ));
    }
    Ok((dressed, character))
}

/// The character each of `count` takes is put on: none without `--character`, one for all when
/// given once, else one per take in order. A file named twice is read once. Each character's
/// warnings are said once.
pub(crate) fn load_all(
    paths: &[PathBuf],
    count: usize,
    source: &Source,
) -> Result<Vec<Option<Arc<Character>>>, Error> {
    if paths.is_empty() {
        return Ok(vec![None; count]);
    }
    if paths.len() != 1 && paths.len() != count {
        return Err(Error::usage(format!(
            "--character: give one for every take, or one per take in their order ({} given \
             for {})",
            paths.len(),
            crate::io::error::counted(count, "take")
        )));
    }
    let mut read: Vec<(PathBuf, Arc<Character>)> = Vec::new();
    let mut out = Vec::with_capacity(count);
    for k in 0..count {
        let path = &paths[k.min(paths.len() - 1)];
        if path.as_os_str() == "-" {
            // It said "-: no such file".
            return Err(Error::usage(
                "--character -: a character is read from a file, not standard input (a glTF's \
                 buffers and textures are found beside it); give its .fbx, .glb or .gltf path",
            ));
        }
        if let Some((_, character)) = read.iter().find(|(p, _)| p == path) {
            out.push(Some(character.clone()));
            continue;
        }
        let mut options = crate::take::OpenOptions::new().max_size(source.max_size);
        if let Some(betas) = &source.betas {
            options = options.betas(betas);
        }
        let character = Arc::new(Character::open_with(path, &options)?);
        for warning in &character.take.warnings {
            eprintln!(
                "bvhview: {}: warning: {}",
                path.display(),
                warning.spelled(&super::Flags)
            );
        }
        read.push((path.clone(), character.clone()));
        out.push(Some(character));
    }
    Ok(out)
}
