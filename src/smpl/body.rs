//! The SMPL-family body a take holds: what an AMASS file said of it, kept for the file written
//! from the take.

use super::layout::ModelType;

/// The SMPL-family body a take was read with: an AMASS file's `betas` and `gender`, and where
/// its model file put the pelvis at rest. An AMASS file written from the take keeps them.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = bvhview::Take::open("tests/data/smpl/amass_smplx_walk.npz")?;
/// let body = walk.body.as_ref().unwrap();
/// assert_eq!(body.gender.as_deref(), Some("female"));
/// assert!(body.rest_pelvis.is_none()); // no model file given: bvhview's own lengths
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// The model type of the parameters.
    pub model: ModelType,
    /// The shape parameters, as the file gave them.
    pub betas: Vec<f64>,
    /// `female`, `male` or `neutral`, as the file said.
    pub gender: Option<String>,
    /// The model's pelvis at rest for these betas (metres, the model's axes), when a model file
    /// gave the joints: the file's `trans` is where the pelvis is, less this.
    pub rest_pelvis: Option<[f64; 3]>,
}
