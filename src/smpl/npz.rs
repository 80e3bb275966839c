//! `.npz` files read as the dataset reader reads a folder: hostile until checked.
//!
//! An `.npz` is a zip archive of `.npy` arrays (numpy's `savez`, stored, or `savez_compressed`,
//! deflated). Every member must be a plain `.npy` at the archive's top (no folder, link or
//! other compression); the sizes its directory states are held to a budget per byte of the file
//! before anything is inflated, and each member is read only that far; every array's header and
//! size are checked against its bytes; object arrays (pickles) are never loaded.

use crate::io::error::Error;
use crate::solve::input::{NpyArray, npy_array};
use std::io::Read;

/// The most members an `.npz` bvhview reads may hold.
pub const MAX_MEMBERS: usize = 1024;

/// What an `.npz`'s members may inflate to: this many bytes for each byte of the file, plus
/// [`INFLATED_FLOOR`] (numbers of AMASS files deflate to about a third; a bomb to a thousandth).
pub const INFLATED_PER_BYTE: u64 = 64;

/// The inflated bytes every `.npz` may reach, whatever its size.
pub const INFLATED_FLOOR: u64 = 16 << 20;

/// An `.npz`'s arrays, by name (`poses` for the member `poses.npy`), in archive order.
///
/// ```
/// use bvhview::smpl::npz;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let bytes = std::fs::read("tests/data/smpl/amass_smplh_walk.npz").unwrap();
/// let arrays = npz::read(&bytes, "walk.npz")?;
/// assert!(arrays.names().any(|name| name == "poses"));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default)]
pub struct Npz {
    arrays: Vec<(String, NpyArray)>,
}

impl Npz {
    /// The array named `name`, if the file holds it.
    pub(crate) fn get(&self, name: &str) -> Option<&NpyArray> {
        self.arrays.iter().find(|(n, _)| n == name).map(|(_, a)| a)
    }

    /// The numbers of the array named `name` (its shape, and its values in C order), if the
    /// file holds it and it holds numbers.
    pub fn numbers(&self, name: &str) -> Option<(&[usize], &[f64])> {
        match self.get(name)? {
            NpyArray::Numbers { shape, values } => Some((shape, values)),
            _ => None,
        }
    }

    /// The numbers of the array named `name`, moved out of the archive (a model's blend shapes
    /// are not held twice).
    pub(crate) fn take_numbers(&mut self, name: &str) -> Option<(Vec<usize>, Vec<f64>)> {
        let at = self
            .arrays
            .iter()
            .position(|(n, a)| n == name && matches!(a, NpyArray::Numbers { .. }))?;
        match self.arrays.remove(at).1 {
            NpyArray::Numbers { shape, values } => Some((shape, values)),
            _ => None,
        }
    }

    /// The arrays' names, in archive order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.arrays.iter().map(|(n, _)| n.as_str())
    }
}

/// The arrays of `bytes`, an `.npz`, named `shown` in errors.
pub fn read(bytes: &[u8], shown: &str) -> Result<Npz, Error> {
    let refuse = |why: String| Error::decoding(shown, why);
    if !bytes.starts_with(b"PK") {
        return Err(refuse(
            "not an .npz (a zip archive of .npy arrays): it does not begin with a zip's `PK`"
                .into(),
        ));
    }
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes))
        .map_err(|e| refuse(format!("not a zip archive bvhview reads ({e})")))?;
    if archive.len() > MAX_MEMBERS {
        return Err(Error::limit(
            "members",
            MAX_MEMBERS as u64,
            archive.len() as u64,
            format!(
                "{shown}: {} members, more than the {MAX_MEMBERS} an .npz bvhview reads holds",
                archive.len()
            ),
        ));
    }
    let budget =
        INFLATED_FLOOR.saturating_add((bytes.len() as u64).saturating_mul(INFLATED_PER_BYTE));
    let mut stated = 0u64;
    for i in 0..archive.len() {
        let member = archive
            .by_index_raw(i)
            .map_err(|e| refuse(format!("member {i}: {e}")))?;
        stated = stated.saturating_add(member.size());
    }
    if stated > budget {
        return Err(Error::limit(
            "bytes",
            budget,
            stated,
            format!(
                "{shown}: its members inflate to {stated} bytes, more than a file of {} bytes \
                 is read for ({INFLATED_PER_BYTE} a byte and {INFLATED_FLOOR}); refused as \
                 damaged or hostile",
                bytes.len()
            ),
        ));
    }
    let mut arrays = Vec::with_capacity(archive.len());
    for i in 0..archive.len() {
        let mut member = archive
            .by_index(i)
            .map_err(|e| refuse(format!("member {i}: {e}")))?;
        let name = member
            .name()
            .map_err(|e| refuse(format!("member {i}: a name bvhview cannot read ({e})")))?
            .to_string();
        let quoted = crate::limits::quoted(&name);
        let member_refused = |why: &str| refuse(format!("member '{quoted}': {why}"));
        let Some(array_name) = name.strip_suffix(".npy") else {
            return Err(member_refused(
                "not an .npy array (an .npz holds only those)",
            ));
        };
        if member.is_dir() || member.is_symlink() || name.contains(['/', '\\']) {
            return Err(member_refused(
                "a folder, a link or a path, not an .npy array at the archive's top",
            ));
        }
        if member.encrypted() {
            return Err(member_refused("encrypted"));
        }
        match member.compression() {
            zip::CompressionMethod::Stored | zip::CompressionMethod::Deflated => {}
            other => {
                return Err(member_refused(&format!(
                    "compressed with {other:?}; numpy writes stored or deflated members"
                )));
            }
        }
        let size = member.size();
        let mut data = Vec::with_capacity(size.min(budget) as usize);
        (&mut member)
            .take(size.saturating_add(1))
            .read_to_end(&mut data)
            .map_err(|e| member_refused(&format!("damaged ({e})")))?;
        if data.len() as u64 != size {
            return Err(member_refused(&format!(
                "its directory says {size} bytes, and it holds {}",
                data.len()
            )));
        }
        if arrays.iter().any(|(n, _)| n == array_name) {
            return Err(member_refused("a second member of that name"));
        }
        let array = npy_array(&data, &format!("{shown}: member '{quoted}'"))?;
        arrays.push((array_name.to_string(), array));
    }
    Ok(Npz { arrays })
}

/// An array's shape and its numbers (C order).
type Numbers<'a> = (&'a [usize], &'a [f64]);

/// The numbers of `key`, with its shape, or why not: missing (`None`), or not numbers.
pub(crate) fn numbers<'a>(
    npz: &'a Npz,
    key: &str,
    shown: &str,
) -> Result<Option<Numbers<'a>>, Error> {
    match npz.get(key) {
        None => Ok(None),
        Some(NpyArray::Numbers { shape, values }) => Ok(Some((shape, values))),
        Some(NpyArray::Text { .. }) => Err(Error::decoding(
            shown,
            format!("'{key}' holds text, not numbers"),
        )),
        Some(NpyArray::Other { dtype }) => Err(Error::decoding(
            shown,
            format!(
                "'{key}' is an array of dtype {dtype} (an object array is a pickle, which \
                 bvhview never loads); it must hold numbers"
            ),
        )),
    }
}

/// An `.npy` (version 1) of float64 values of `shape` (`[]`: one value, 0-d), C order.
pub(crate) fn npy_f64(shape: &[usize], values: &[f64]) -> Vec<u8> {
    let mut out = crate::io::npy::header("<f8", shape, 0);
    for v in values {
        out.extend(v.to_le_bytes());
    }
    out
}

/// A 0-d `.npy` of one unicode string, as numpy saves `np.array("male")` (`<U4`).
pub(crate) fn npy_text(text: &str) -> Vec<u8> {
    let count = text.chars().count().max(1);
    let mut out = crate::io::npy::header(&format!("<U{count}"), &[], 0);
    for c in text.chars() {
        out.extend((c as u32).to_le_bytes());
    }
    if text.is_empty() {
        out.extend([0u8; 4]);
    }
    out
}

/// An `.npz` of `members` (each an array's name, without `.npy`, and its bytes), stored as
/// numpy's `savez` stores them.
pub(crate) fn write(members: &[(String, Vec<u8>)]) -> Result<Vec<u8>, Error> {
    use std::io::Write;
    let failed = |e: &dyn std::fmt::Display| Error::usage(format!("cannot write the .npz: {e}"));
    let mut out = std::io::Cursor::new(Vec::new());
    let mut zip = zip::ZipWriter::new(&mut out);
    // A fixed time: the same take makes the same bytes.
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .last_modified_time(zip::DateTime::default())
        .large_file(
            members
                .iter()
                .any(|(_, b)| b.len() as u64 >= u32::MAX as u64),
        );
    for (name, bytes) in members {
        zip.start_file(format!("{name}.npy"), options)
            .map_err(|e| failed(&e))?;
        zip.write_all(bytes).map_err(|e| failed(&e))?;
    }
    zip.finish().map_err(|e| failed(&e))?;
    Ok(out.into_inner())
}
