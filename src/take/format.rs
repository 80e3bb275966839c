//! The formats takes are read from, and how a file or its bytes tell theirs.

use std::path::Path;

/// A format takes are read from: which files hold it (by extension or by their first bytes)
/// and what they hold. The one list of formats: the readers, the folder walks and the messages
/// all ask it.
///
/// ```
/// use bvhview::take::{Format, Take};
/// use std::path::Path;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// assert_eq!(Format::from_path(Path::new("WALK.GLB")), Some(Format::Gltf));
/// assert_eq!(Format::of_extension("amc"), Some(Format::AsfAmc));
/// assert_eq!(Format::sniff(b"\xEF\xBB\xBFHIERARCHY\nROOT Hips"), Some(Format::Bvh));
/// assert_eq!(Format::Gltf.extensions(), ["gltf", "glb"]);
/// assert!(Format::Fbx.holds_several_takes() && !Format::AsfAmc.stands_alone());
/// let take = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// assert_eq!(take.format, Some(Format::Bvh));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Format {
    /// BVH (Biovision Hierarchy): `.bvh`.
    Bvh,
    /// An ASF skeleton with its AMC motion (CMU's Acclaim format).
    AsfAmc,
    /// Autodesk FBX, binary or ASCII: `.fbx`.
    Fbx,
    /// glTF 2.0, `.gltf` or `.glb`.
    Gltf,
    /// AMASS's `.npz`: SMPL, SMPL-H or SMPL-X parameters (see [`crate::smpl`]).
    Amass,
}

impl Format {
    /// Every format, in the order messages list them.
    pub const ALL: [Format; 5] = [
        Format::Bvh,
        Format::Fbx,
        Format::Gltf,
        Format::AsfAmc,
        Format::Amass,
    ];

    /// The (lower-case) extensions of its files.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            Format::Bvh => &["bvh"],
            Format::AsfAmc => &["asf", "amc"],
            Format::Fbx => &["fbx"],
            Format::Gltf => &["gltf", "glb"],
            Format::Amass => &["npz"],
        }
    }

    /// The format a file of this extension holds (case aside).
    pub fn of_extension(extension: &str) -> Option<Format> {
        let extension = extension.to_ascii_lowercase();
        Format::ALL
            .into_iter()
            .find(|format| format.extensions().contains(&extension.as_str()))
    }

    /// The format a file holds by its extension.
    pub fn from_path(path: &Path) -> Option<Format> {
        Format::of_extension(&extension(path))
    }

    /// The format of a take's bytes by how they begin, for standard input, which has no
    /// extension: `HIERARCHY` (after a byte-order mark or blanks) is BVH, `glTF` (binary GLB)
    /// or `{` (its JSON) glTF, FBX's binary magic or an ASCII FBX's `; FBX` comment FBX, a zip's
    /// `PK\x03\x04` an AMASS `.npz`. An ASF is never told so: it needs its AMC beside it.
    pub fn sniff(bytes: &[u8]) -> Option<Format> {
        let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        let start = text
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .unwrap_or(text.len());
        let text = &text[start..];
        if text.len() >= 9 && text[..9].eq_ignore_ascii_case(b"HIERARCHY") {
            Some(Format::Bvh)
        } else if bytes.starts_with(b"glTF") || text.starts_with(b"{") {
            Some(Format::Gltf)
        } else if bytes.starts_with(b"Kaydara FBX Binary") || text.starts_with(b"; FBX") {
            Some(Format::Fbx)
        } else if bytes.starts_with(b"PK\x03\x04") {
            Some(Format::Amass)
        } else {
            None
        }
    }

    /// Whether one file holds takes to pick among (FBX animation stacks, glTF animations:
    /// [`OpenOptions::take`](crate::take::OpenOptions::take)).
    pub fn holds_several_takes(self) -> bool {
        matches!(self, Format::Fbx | Format::Gltf)
    }

    /// Whether a file of it is a take on its own (an ASF skeleton needs its AMC motion).
    pub fn stands_alone(self) -> bool {
        self != Format::AsfAmc
    }
}

/// A path's extension in lower case (`TAKE.BVH` → `bvh`), empty when it has none.
pub(crate) fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}
