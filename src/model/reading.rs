//! What every format's reader hands over: the take with what it says once, and the list of
//! takes a file holds, one picked by name or index.

use crate::io::error::Error;
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;

/// One take of a file: its name, frames and seconds per frame.
#[derive(Clone, Debug, PartialEq)]
pub struct TakeInfo {
    pub name: String,
    pub frames: usize,
    pub frame_time: f64,
}

/// What a reader gives [`crate::take`]: the take and what it says once.
#[derive(Debug)]
pub struct Read {
    pub skeleton: Skeleton,
    pub motion: Motion,
    pub warnings: Vec<String>,
    /// The take read, by name, when the file holds takes (none: its rest pose).
    pub take: Option<String>,
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
    Err(Error::Usage(format!("{file}: no take '{take}' ({list})")))
}

/// [`pick_take`] for a file whose takes are `names` (at least one): the index and name of the
/// take read, and, when none was asked for and there are several, a warning naming the first
/// and how to pick another.
pub fn choose_take(
    names: &[String],
    take: Option<&str>,
    file: &str,
    warnings: &mut Vec<String>,
) -> Result<(usize, String), Error> {
    let index = pick_take(names, take, file)?;
    if take.is_none() && names.len() > 1 {
        warnings.push(format!(
            "{} takes; reading take 0 '{}' (--take NAME|INDEX picks another; `bvhview info` \
             lists them)",
            names.len(),
            names[0]
        ));
    }
    Ok((index, names[index].clone()))
}
