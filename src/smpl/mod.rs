//! The SMPL family's motion (AMASS's `.npz` files of SMPL, SMPL-H and SMPL-X parameters) as
//! takes: [`layout`] (the model types' joints and trees), [`npz`] (the archive, read as hostile),
//! [`amass`] (the parameters, and the take they make).

pub mod amass;
pub mod body;
pub mod fit;
pub mod layout;
pub mod model;
pub mod npz;

pub use body::Body;
pub use layout::ModelType;

use crate::io::error::Error;
use crate::model::reading::Read;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The take of `bytes`, an AMASS-layout `.npz` named `shown`, and the body it holds;
/// `frame_time` stands in for a file that states no rate; `body_model` is the user's model file
/// (or a folder of them) for the joints' offsets.
pub fn load_bytes(
    bytes: &[u8],
    shown: &str,
    frame_time: Option<f64>,
    body_model: Option<&Path>,
    max_size: u64,
) -> Result<(Read, Body), Error> {
    let npz = npz::read(bytes, shown)?;
    let amass = amass::read(&npz, shown, frame_time)?;
    // A model of another type than the motion's (given for a target: `convert walk_smplh.npz
    // --onto smplx --body-model SMPLX_NEUTRAL.npz`) does not read it: said, and the built-in
    // figure reads it.
    let mut other_type = None;
    let model = match body_model {
        Some(path) if path.is_dir() => {
            match open_model(path, amass.gender.as_deref(), Some(amass.model), max_size) {
                Ok(model) => Some(model),
                Err(why) => {
                    other_type = Some(why.to_string());
                    None
                }
            }
        }
        Some(path) => {
            let model = open_model(path, amass.gender.as_deref(), None, max_size)?;
            if model.model == amass.model {
                Some(model)
            } else {
                other_type = Some(format!(
                    "{}: a {} model, and the motion is {} parameters",
                    model.name,
                    model.model.label(),
                    amass.model.label()
                ));
                None
            }
        }
        None => None,
    };
    let amass::OnFigure {
        skeleton,
        motion,
        said: mut warnings,
        rest_pelvis,
    } = amass::to_take(&amass, model.as_deref())?;
    if let Some(why) = other_type {
        warnings.push(format!("the body model does not read this take ({why})").into());
    }
    let body = Body {
        model: amass.model,
        betas: amass.betas.clone(),
        gender: amass.gender.clone(),
        rest_pelvis,
    };
    let read = Read {
        skeleton,
        motion,
        warnings,
        take: None,
        stated_units: Some(crate::model::stance::Units::of_metres(1.0)),
    };
    Ok((read, body))
}

/// Model files read in this process, by path and gender: a folder of AMASS files read with one
/// model reads it once.
type ModelCache = Vec<(
    PathBuf,
    Option<String>,
    Option<ModelType>,
    Arc<model::BodyModel>,
)>;

/// The body model at `path` (a file, or a folder holding one per gender) for `gender` and of
/// type `wanted` (any, for `None`), of at most `max_size` bytes, read once per process.
pub fn open_model(
    path: &Path,
    gender: Option<&str>,
    wanted: Option<ModelType>,
    max_size: u64,
) -> Result<Arc<model::BodyModel>, Error> {
    static CACHE: Mutex<ModelCache> = Mutex::new(Vec::new());
    let gender = gender.map(|g| g.trim().to_ascii_lowercase());
    let key = (path.to_path_buf(), gender.clone(), wanted);
    if let Ok(cache) = CACHE.lock()
        && let Some((.., model)) = cache
            .iter()
            .find(|(p, g, t, _)| (p, g, *t) == (&key.0, &key.1, key.2))
    {
        return Ok(model.clone());
    }
    let model = Arc::new(model::BodyModel::open(
        path,
        gender.as_deref(),
        wanted,
        max_size,
    )?);
    if let Some(wanted) = wanted.filter(|&w| w != model.model) {
        return Err(Error::usage(format!(
            "{}: a {} model; the motion is {} parameters (give a {} model file)",
            model.name,
            model.model.label(),
            wanted.label(),
            wanted.label()
        )));
    }
    if let Ok(mut cache) = CACHE.lock() {
        // A few models at most: each holds its blend shapes (100 MB for SMPL-X).
        if cache.len() >= 3 {
            cache.remove(0);
        }
        cache.push((key.0, key.1, key.2, model.clone()));
    }
    Ok(model)
}
