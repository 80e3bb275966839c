//! `--character` (the viewer, `snapshot`, `convert`, `positions`): the characters takes are put
//! on, loaded once each.

use super::*;
use crate::character::Character;
use std::sync::Arc;

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
        return Err(Error::Usage(format!(
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
            return Err(Error::Usage(
                "--character -: a character is read from a file, not standard input (a glTF's \
                 buffers and textures are found beside it); give its .fbx, .glb or .gltf path"
                    .into(),
            ));
        }
        if let Some((_, character)) = read.iter().find(|(p, _)| p == path) {
            out.push(Some(character.clone()));
            continue;
        }
        let character = Arc::new(Character::open_with(
            path,
            source.max_size,
            None,
            crate::io::parallel::cores(),
        )?);
        for warning in &character.take.warnings {
            eprintln!("bvhview: {}: warning: {warning}", path.display());
        }
        read.push((path.clone(), character.clone()));
        out.push(Some(character));
    }
    Ok(out)
}
