//! The SMPL family's motion (AMASS's `.npz` files of SMPL, SMPL-H and SMPL-X parameters) as
//! takes: [`layout`] (the model types' joints and trees), [`npz`] (the archive, read as hostile),
//! [`amass`] (the parameters, and the take they make).

pub mod amass;
pub mod layout;
pub mod model;
pub mod npz;

pub use layout::ModelType;

use crate::io::error::Error;
use crate::model::reading::Read;

/// The take of `bytes`, an AMASS-layout `.npz` named `shown`; `frame_time` stands in for a file
/// that states no rate.
pub fn load_bytes(bytes: &[u8], shown: &str, frame_time: Option<f64>) -> Result<Read, Error> {
    let npz = npz::read(bytes, shown)?;
    let amass = amass::read(&npz, shown, frame_time)?;
    let (skeleton, motion, warnings) = amass::to_take(&amass)?;
    Ok(Read {
        skeleton,
        motion,
        warnings,
        take: None,
        stated_units: Some(crate::model::stance::Units::of_metres(1.0)),
    })
}
