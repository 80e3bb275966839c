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
#[derive(Clone, Debug, Default)]
pub struct Npz {
    arrays: Vec<(String, NpyArray)>,
}

impl Npz {
    /// The array named `name`, if the file holds it.
    pub(crate) fn get(&self, name: &str) -> Option<&NpyArray> {
        self.arrays.iter().find(|(n, _)| n == name).map(|(_, a)| a)
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
