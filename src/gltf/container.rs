//! The two containers glTF is written in, in a file of its own so that the writer (and the
//! refusals of a build without glTF) take it from a sibling rather than from the module above.

/// Which container: a binary `.glb`, or a `.gltf` text file with its buffer inline (base64).
///
/// ```
/// use bvhview::{Take, gltf::{Container, to_gltf}, model::pose::OffsetMode};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// # #[cfg(feature = "gltf")]
/// # {
/// let take = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let (skeleton, motion) = (&take.skeleton, &take.motion);
/// let glb = to_gltf(skeleton, motion, OffsetMode::Replace, Container::Glb, false)?;
/// assert!(glb.starts_with(b"glTF"));
/// let text = to_gltf(skeleton, motion, OffsetMode::Replace, Container::Gltf, false)?;
/// assert!(text.starts_with(b"{"));
/// # }
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Container {
    /// Binary glTF: a JSON chunk and a binary chunk in one file.
    Glb,
    /// A JSON text file with its buffer inline as a base64 data URI.
    Gltf,
}
