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

/// How one item went.
#[derive(Debug)]
pub struct Outcome {
    pub item: Item,
    pub result: Result<String, Error>,
    pub bytes: u64,
}

/// Every item under `dir` (subfolders too), in path order. An AMC pairs with the ASF in its folder
/// whose name is the longest prefix of the AMC's (`12.asf` with `12_02.amc`), or with the
/// folder's only ASF; an ASF no AMC uses is listed alone (its rest pose).
pub fn collect(dir: &Path) -> Result<Vec<Item>, Error> {
    let mut items = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(&folder)
            .map_err(|e| Error::io(&folder, e))?
            .filter_map(|entry| entry.ok().map(|e| e.path()))
            .collect();
        entries.sort();
        let asfs: Vec<&PathBuf> = entries.iter().filter(|p| extension(p) == "asf").collect();
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
                "amc" => {
                    let stem = path
                        .file_stem()
                        .map(|s| s.to_string_lossy().into_owned())
                        .unwrap_or_default();
                    let by_prefix = asfs
                        .iter()
                        .enumerate()
                        .filter(|(_, asf)| {
                            let asf_stem = asf
                                .file_stem()
                                .map(|s| s.to_string_lossy().into_owned())
                                .unwrap_or_default();
                            stem.starts_with(&asf_stem)
                        })
                        .max_by_key(|(_, asf)| asf.as_os_str().len());
                    let chosen = by_prefix.or(if asfs.len() == 1 {
                        Some((0, &asfs[0]))
                    } else {
                        None
                    });
                    match chosen {
                        Some((k, asf)) => {
                            used[k] = true;
                            items.push(Item {
                                path: (*asf).clone(),
                                motion: Some(path.clone()),
                            });
                        }
                        None => items.push(Item {
                            path: path.clone(),
                            motion: None,
                        }),
                    }
                }
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
        "{joints} joints, {frames} frames, {} s",
        crate::info::readable(loaded.motion.duration(), 1)
    );
    let warnings = crate::info::warnings(loaded, offset_mode);
    if !warnings.is_empty() {
        line.push_str(&format!(
            " ({} warning{})",
            warnings.len(),
            if warnings.len() == 1 { "" } else { "s" }
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
            let result = input::load_checked(
                &item.path,
                item.motion.as_deref(),
                settings.frame_time,
                1,
                settings.max_size,
            )
            .map(|loaded| describe(&loaded, settings.offset_mode));
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
