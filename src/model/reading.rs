//! What every format's reader hands over: the take with what it says once, and the list of
//! takes a file holds, one picked by name or index.

use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;

/// One take of a file: its name, frames and seconds per frame.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// # #[cfg(feature = "gltf")]
/// # {
/// let path = std::path::Path::new("tests/data/gltf/bvh11_131_01.glb");
/// let takes = bvhview::gltf::takes(path, 1 << 30)?;
/// assert_eq!(takes.len(), 1);
/// assert_eq!((takes[0].name.as_str(), takes[0].frames), ("bvh11_131_01", 60));
/// # }
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TakeInfo {
    /// The take's name in the file (an FBX animation stack, a glTF animation).
    pub name: String,
    /// How many frames it holds.
    pub frames: usize,
    /// Seconds per frame.
    pub frame_time: f64,
}

/// What a reader gives [`crate::take`]: the take and what it says once.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// # #[cfg(feature = "gltf")]
/// # {
/// let path = std::path::Path::new("tests/data/gltf/bvh11_131_01.glb");
/// let read = bvhview::gltf::load(path, &bvhview::take::OpenOptions::new())?;
/// assert_eq!(read.motion.frame_count(), 60);
/// assert_eq!(read.take.as_deref(), Some("bvh11_131_01"));
/// # }
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct Read {
    /// The skeleton, joints in pre-order.
    pub skeleton: Skeleton,
    /// The take's frames, one column per channel of `skeleton`.
    pub motion: Motion,
    /// Things that were accepted but deserve a word, each said once.
    pub warnings: Vec<Message>,
    /// The take read, by name, when the file holds takes (none: its rest pose).
    pub take: Option<String>,
    /// The units the lengths are in, where the file states them and the reader keeps them (a
    /// plain FBX take, read in its file's units); `None`: guessed from the figure.
    pub stated_units: Option<crate::model::stance::Units>,
}

/// Picks a take by name, or by its index in `info`'s list.
pub fn pick_take(names: &[String], take: Option<&str>, file: &str) -> Result<usize, Error> {
    let Some(take) = take else { return Ok(0) };
    if let Some(i) = names.iter().position(|n| n == take) {
        return Ok(i);
    }
    if let Ok(i) = take.trim().parse::<usize>()
        && i < names.len()
    {
        return Ok(i);
    }
    let list = if names.is_empty() {
        "it has none".to_string()
    } else {
        let quoted: Vec<String> = names
            .iter()
            .enumerate()
            .map(|(i, n)| format!("{i} '{n}'"))
            .collect();
        format!("it has {}", quoted.join(", "))
    };
    Err(Error::usage(format!("{file}: no take '{take}' ({list})")))
}

/// [`pick_take`] for a file whose takes are `names` (at least one): the index and name of the
/// take read, and, when none was asked for and there are several, a warning naming the first
/// and how to pick another.
pub fn choose_take(
    names: &[String],
    take: Option<&str>,
    file: &str,
    warnings: &mut Vec<Message>,
) -> Result<(usize, String), Error> {
    let index = pick_take(names, take, file)?;
    if take.is_none() && names.len() > 1 {
        warnings.push(
            Message::from(format!(
                "{} takes; reading take 0 '{}' (",
                names.len(),
                names[0]
            ))
            .argument("take", Some("NAME|INDEX"))
            .text(" picks another; `bvhview info` lists them)"),
        );
    }
    Ok((index, names[index].clone()))
}
