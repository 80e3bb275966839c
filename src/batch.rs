//! `bvhview info DIR`: every BVH file and ASF/AMC pair under a folder, loaded on every core.

use crate::error::Error;
use crate::input::{self, extension};
use std::path::{Path, PathBuf};

/// One thing to load: a BVH file, an ASF with its AMC, an ASF alone, or an AMC without an ASF.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Item {
    pub path: PathBuf,
    pub motion: Option<PathBuf>,
}

impl Item {
    /// An AMC no skeleton in its folder pairs with: listed, not loaded (motion alone has no
    /// joints to move).
    pub fn is_unpaired_motion(&self) -> bool {
        self.motion.is_none() && extension(&self.path) == "amc"
    }

    /// The skeleton an unpaired AMC would have paired with by its name, for the note.
    pub fn wanted_skeleton(&self) -> String {
        let stem = stem(&self.path);
        format!("{}.asf", subject_number(&stem).unwrap_or(&stem))
    }
}

/// How one item went.
#[derive(Debug)]
pub struct Outcome {
    pub item: Item,
    /// The line describing a loaded item; `Ok(None)` for an unpaired AMC, which is not loaded.
    pub result: Result<Option<String>, Error>,
    pub bytes: u64,
}

/// A file name without its extension.
fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// CMU's subject number: `07` in `07_05` (a take) or in `07` (the skeleton).
fn subject_number(stem: &str) -> Option<&str> {
    let number = stem.split('_').next().unwrap_or(stem);
    (!number.is_empty() && number.bytes().all(|b| b.is_ascii_digit())).then_some(number)
}

/// Whether two subject numbers are the same number (`7` and `07`).
fn same_number(a: &str, b: &str) -> bool {
    a.trim_start_matches('0') == b.trim_start_matches('0')
}

/// The skeleton among `asfs` (one folder's) that an AMC named `amc_stem` goes with: the ASF of
/// the same name; else, as CMU names them, the ASF of its subject number (`07.asf` for
/// `07_05.amc`); else the ASF whose name is the longest start of the AMC's (`heiden_12.asf` for
/// `heiden_12_02_01.amc`); else the folder's only ASF, unless both are numbered for different
/// subjects.
fn skeleton_for(amc_stem: &str, asfs: &[&PathBuf]) -> Option<usize> {
    let stems: Vec<String> = asfs.iter().map(|asf| stem(asf)).collect();
    let amc_subject = subject_number(amc_stem);
    let numbered = |k: usize| subject_number(&stems[k]) == Some(stems[k].as_str());
    let same_name = (0..stems.len()).find(|&k| stems[k].eq_ignore_ascii_case(amc_stem));
    let same_subject = || {
        let subject = amc_subject?;
        (0..stems.len()).find(|&k| numbered(k) && same_number(&stems[k], subject))
    };
    // A numbered ASF goes only with its own subject: `1.asf` is not the skeleton of `12_02.amc`.
    let by_prefix = || {
        (0..stems.len())
            .filter(|&k| !numbered(k) && amc_stem.starts_with(stems[k].as_str()))
            .max_by_key(|&k| stems[k].len())
    };
    let only = || {
        let other_subject = amc_subject.is_some() && numbered(0);
        (stems.len() == 1 && !other_subject).then_some(0)
    };
    same_name
        .or_else(same_subject)
        .or_else(by_prefix)
        .or_else(only)
}

/// Every item under `dir` (subfolders too), in path order. An AMC pairs with an ASF in its
/// folder as `skeleton_for` says; an AMC with none is listed unpaired; an ASF no AMC uses is
/// listed alone (its rest pose).
pub fn collect(dir: &Path) -> Result<Vec<Item>, Error> {
    let mut items = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(&folder)
            .map_err(|e| Error::io(&folder, e))?
            .filter_map(|entry| entry.ok().map(|e| e.path()))
            .collect();
        entries.sort();
        let asfs: Vec<&PathBuf> = entries
            .iter()
            .filter(|p| extension(p) == "asf" && p.is_file())
            .collect();
        let mut used = vec![false; asfs.len()];
        for path in &entries {
            if path.is_dir() {
                folders.push(path.clone());
                continue;
            }
            // A FIFO or a device named like a take would wait for a writer for good, or read
            // without end: a folder's takes are its regular files (links to them included).
            if !path.is_file() {
                continue;
            }
            match extension(path).as_str() {
                "bvh" => items.push(Item {
                    path: path.clone(),
                    motion: None,
                }),
                "amc" => match skeleton_for(&stem(path), &asfs) {
                    Some(k) => {
                        used[k] = true;
                        items.push(Item {
                            path: asfs[k].clone(),
                            motion: Some(path.clone()),
                        });
                    }
                    None => items.push(Item {
                        path: path.clone(),
                        motion: None,
                    }),
                },
                _ => {}
            }
        }
        for (asf, used) in asfs.iter().zip(used) {
            if !used {
                items.push(Item {
                    path: (*asf).clone(),
                    motion: None,
                });
            }
        }
    }
    items.sort_by(|a, b| {
        (a.motion.as_ref().unwrap_or(&a.path)).cmp(b.motion.as_ref().unwrap_or(&b.path))
    });
    Ok(items)
}

/// What every item is loaded with: the options `info` takes for one file.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Seconds per frame, overriding each file's.
    pub frame_time: Option<f64>,
    /// Files larger than this are refused.
    pub max_size: u64,
    /// The convention the offset-mode warning is judged against.
    pub offset_mode: crate::pose::OffsetMode,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            frame_time: None,
            max_size: input::DEFAULT_MAX_SIZE,
            offset_mode: crate::pose::OffsetMode::default(),
        }
    }
}

/// The line printed for a loaded item; its warnings are those `info FILE` lists.
fn describe(loaded: &input::Loaded, offset_mode: crate::pose::OffsetMode) -> String {
    let joints = loaded
        .skeleton
        .joints
        .iter()
        .filter(|j| !j.end_site)
        .count();
    let frames = loaded.motion.frame_count();
    let mut line = format!(
        "{}, {}, {} s",
        crate::error::counted(joints, "joint"),
        crate::error::counted(frames, "frame"),
        crate::info::readable(loaded.motion.duration(), 1)
    );
    let warnings = crate::info::warnings(loaded, offset_mode);
    if !warnings.is_empty() {
        line.push_str(&format!(
            " ({})",
            crate::error::counted(warnings.len(), "warning")
        ));
    }
    line
}

/// Loads every item on `threads` threads; `done(outcome, finished, total)` is called for each
/// outcome in item order (so output is the same from run to run).
pub fn run(
    items: Vec<Item>,
    threads: usize,
    settings: Settings,
    mut done: impl FnMut(&Outcome, usize, usize) + Send,
) -> Vec<Outcome> {
    let total = items.len();
    let mut outcomes = Vec::with_capacity(total);
    crate::parallel::map_in_order(
        total,
        threads,
        4 * threads.max(1),
        |index| {
            let item = &items[index];
            let size = |p: &Path| std::fs::metadata(p).map_or(0, |m| m.len());
            let bytes = size(&item.path) + item.motion.as_deref().map_or(0, size);
            let result = if item.is_unpaired_motion() {
                Ok(None)
            } else {
                input::load_checked(
                    &item.path,
                    item.motion.as_deref(),
                    settings.frame_time,
                    1,
                    settings.max_size,
                )
                .map(|loaded| Some(describe(&loaded, settings.offset_mode)))
            };
            Outcome {
                item: item.clone(),
                result,
                bytes,
            }
        },
        |index, outcome| {
            done(&outcome, index + 1, total);
            outcomes.push(outcome);
            true
        },
    );
    outcomes
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ASF (by name) that [`skeleton_for`] pairs `amc` with among `asfs`.
    fn paired(amc: &str, asfs: &[&str]) -> Option<String> {
        let paths: Vec<PathBuf> = asfs
            .iter()
            .map(|a| PathBuf::from(format!("{a}.asf")))
            .collect();
        let refs: Vec<&PathBuf> = paths.iter().collect();
        skeleton_for(amc, &refs).map(|k| asfs[k].to_string())
    }

    #[test]
    fn an_amc_pairs_by_name_then_cmu_subject_then_prefix_then_the_only_asf() {
        assert_eq!(paired("walk", &["run", "walk"]).as_deref(), Some("walk"));
        assert_eq!(paired("07_05", &["07", "08"]).as_deref(), Some("07"));
        assert_eq!(paired("7_05", &["07", "08"]).as_deref(), Some("07"));
        assert_eq!(paired("12_02", &["1", "12"]).as_deref(), Some("12"));
        assert_eq!(
            paired("heiden_12_02_01", &["heiden", "heiden_12", "other"]).as_deref(),
            Some("heiden_12")
        );
        assert_eq!(paired("take", &["skeleton"]).as_deref(), Some("skeleton"));
        // A numbered skeleton is another subject's: not the skeleton of this take.
        assert_eq!(paired("12_02", &["1"]), None);
        assert_eq!(paired("08_01", &["07"]), None);
        assert_eq!(paired("12_02", &["07", "walk"]), None);
        assert_eq!(paired("walk", &[]), None);
    }

    #[test]
    fn an_unpaired_amc_names_the_skeleton_it_looked_for() {
        let item = |name: &str| Item {
            path: PathBuf::from(name),
            motion: None,
        };
        assert!(item("d/12_01.amc").is_unpaired_motion());
        assert!(!item("d/12.asf").is_unpaired_motion());
        assert_eq!(item("d/12_01.amc").wanted_skeleton(), "12.asf");
        assert_eq!(item("d/walk.amc").wanted_skeleton(), "walk.asf");
    }
}
