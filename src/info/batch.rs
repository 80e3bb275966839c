//! `bvhview info DIR`: every BVH file and ASF/AMC pair under a folder, loaded on every core.

use crate::io::error::Error;
use crate::take::{self, extension};
use std::path::{Path, PathBuf};

/// One thing to load: a BVH file, an ASF with its AMC, an ASF alone, or an AMC without an ASF.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// // tests/data/asf_amc holds CMU's heiden_12.asf and its motion heiden_12_02_01.amc: one take.
/// let walk = bvhview::info::batch::collect_takes(std::path::Path::new("tests/data/asf_amc"))?;
/// let item = &walk.items[0];
/// assert!(item.path.ends_with("heiden_12.asf"));
/// assert!(item.motion.as_ref().is_some_and(|m| m.ends_with("heiden_12_02_01.amc")));
/// assert!(!item.is_unpaired_motion());
/// assert!(walk.skipped.is_empty());
/// # Ok(())
/// # }
/// ```
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
        if let Some(number) = subject_number(&stem) {
            return format!("{number}.asf");
        }
        match take_key(&stem) {
            Some(key) if !key.rest.starts_with('_') => {
                format!("{}{}{}.asf", key.prefix, key.number, key.rest)
            }
            _ => format!("{stem}.asf"),
        }
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

/// A name cut as CMU's downloads name takes and skeletons: `cmu_` (any text without digits),
/// the subject number `07`, for a take `_05`, and the rest `-walk`.
struct Key<'a> {
    prefix: &'a str,
    number: &'a str,
    rest: &'a str,
}

/// `prefix`, `number` and the rest of a skeleton's name (`cmu_07-walk`).
fn subject_key(stem: &str) -> Option<Key<'_>> {
    let start = stem.find(|c: char| c.is_ascii_digit())?;
    let end = stem[start..]
        .find(|c: char| !c.is_ascii_digit())
        .map_or(stem.len(), |k| start + k);
    Some(Key {
        prefix: &stem[..start],
        number: &stem[start..end],
        rest: &stem[end..],
    })
}

/// The same for a take's name (`cmu_07_05-walk`), its take number (`_05`) left out.
fn take_key(stem: &str) -> Option<Key<'_>> {
    let key = subject_key(stem)?;
    let take = key.rest.strip_prefix('_')?;
    let digits = take
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(take.len());
    (digits > 0).then(|| Key {
        rest: &take[digits..],
        ..key
    })
}

/// Whether a take's key and a skeleton's are the same but for the subject number.
fn same_scheme(take: &Key, skeleton: &Key) -> bool {
    take.prefix.eq_ignore_ascii_case(skeleton.prefix)
        && take.rest.eq_ignore_ascii_case(skeleton.rest)
}

/// Whether two subject numbers are the same number (`7` and `07`).
fn same_number(a: &str, b: &str) -> bool {
    a.trim_start_matches('0') == b.trim_start_matches('0')
}

/// The skeleton among `asfs` (one folder's) that an AMC named `amc_stem` goes with: the ASF of
/// the same name; else, as CMU names them, the ASF of its subject number (`07.asf` for
/// `07_05.amc`); else the ASF whose name is the longest start of the AMC's (`heiden_12.asf` for
/// `heiden_12_02_01.amc`); else the ASF named as CMU's downloads name it, the take number left
/// out (`cmu_07-walk.asf` for `cmu_07_05-walk.amc`); else the folder's only ASF, unless both are
/// numbered for different subjects.
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
    let amc_key = take_key(amc_stem);
    let cmu_named = || {
        let take = amc_key.as_ref()?;
        (0..stems.len()).find(|&k| {
            subject_key(&stems[k])
                .is_some_and(|asf| same_scheme(take, &asf) && same_number(take.number, asf.number))
        })
    };
    let only = || {
        // Only a folder's one ASF pairs so; with none, `numbered(0)` would look past the list.
        if stems.len() != 1 {
            return None;
        }
        let other_subject = (amc_subject.is_some() && numbered(0))
            || amc_key
                .as_ref()
                .zip(stems.first().and_then(|s| subject_key(s)))
                .is_some_and(|(take, asf)| same_scheme(take, &asf));
        (!other_subject).then_some(0)
    };
    same_name
        .or_else(same_subject)
        .or_else(by_prefix)
        .or_else(cmu_named)
        .or_else(only)
}

/// What a folder walk left out, and why: a loop, a folder or file reached again, a link out of
/// the folder, something that is not a regular file, an entry that cannot be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Skip {
    pub path: PathBuf,
    pub reason: String,
}

impl std::fmt::Display for Skip {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.reason)
    }
}

/// A folder's takes ([`collect`]): the items in path order, and what the walk left out.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Walk {
    pub items: Vec<Item>,
    pub skipped: Vec<Skip>,
}

/// Skipped entries said one a line; past these, the rest are counted.
pub const SKIPS_SAID: usize = 20;

impl Walk {
    /// What the walk skipped as the CLI says it on stderr: `skipped PATH: why`, one a line for
    /// the first [`SKIPS_SAID`], then how many more.
    pub fn skipped_lines(&self) -> Vec<String> {
        let mut lines: Vec<String> = self
            .skipped
            .iter()
            .take(SKIPS_SAID)
            .map(|skip| format!("skipped {skip}"))
            .collect();
        if self.skipped.len() > SKIPS_SAID {
            lines.push(format!(
                "skipped {} more in the folder walk",
                self.skipped.len() - SKIPS_SAID
            ));
        }
        lines
    }
}

/// A file's or folder's identity: its device and inode.
fn identity(metadata: &std::fs::Metadata) -> (u64, u64) {
    use std::os::unix::fs::MetadataExt;
    (metadata.dev(), metadata.ino())
}

/// Whether a name is one of a take's (`.bvh`, `.fbx`, `.gltf`, `.glb`, `.asf`, `.amc`, any case).
fn is_take_name(path: &Path) -> bool {
    crate::take::Format::from_path(path).is_some()
}

/// Why an entry cannot be read, as a skipped line says it.
fn unreadable(error: &std::io::Error) -> String {
    match error.kind() {
        std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
        std::io::ErrorKind::NotFound => "no such file".to_string(),
        _ => {
            let text = error.to_string();
            match text.find(" (os error") {
                Some(cut) => text[..cut].to_lowercase(),
                None => text,
            }
        }
    }
}

fn walk_error(error: &walkdir::Error) -> String {
    error
        .io_error()
        .map_or_else(|| error.to_string(), unreadable)
}

/// Why a link met in the walk of `dir` (whose real path is `root`) is not followed: it leads
/// out of `dir` (to a folder or a file: walking all of `/` would not end, and a private file must
/// not end up in a dataset or a message), or it cannot be resolved. `None`: it stays inside.
fn link_refused(path: &Path, root: &Path, dir: &Path) -> Option<String> {
    match std::fs::canonicalize(path) {
        Ok(target) if !target.starts_with(root) => Some(format!(
            "a link to {}, outside {}: not followed",
            target.display(),
            dir.display()
        )),
        Ok(_) => None,
        Err(e) => Some(format!("cannot be read: {}", unreadable(&e))),
    }
}

/// Every item under `dir` (subfolders too), in path order, and what was skipped. An AMC pairs
/// with an ASF in its folder as `skeleton_for` says; an AMC with none is listed unpaired; an
/// ASF no AMC uses is listed alone (its rest pose).
///
/// The walk is `walkdir`'s, in name order, with symbolic links followed as a careful tool
/// follows them: a folder (by device and inode) is walked once, at its first path in path order,
/// so a link back up (`ln -s . a`) or two links to one folder neither loop nor list a take
/// twice; a link to a folder outside `dir` (`ln -s / root`) is not followed, as walking all of
/// it would not end in any useful time, nor is a link to a file outside `dir` (a private file
/// must not end up in a dataset or its manifest); a file reached under two names (links) is listed once,
/// at its first path; only regular files are takes (a FIFO would wait for a writer for good).
/// Each of these, and every entry that cannot be read, is in [`Walk::skipped`]. A `dir` that
/// cannot be read is an error.
pub fn collect(dir: &Path) -> Result<Walk, Error> {
    std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    let root = std::fs::canonicalize(dir).map_err(|e| Error::io(dir, e))?;
    let mut found = Found::new(dir, root);
    let mut walk = walkdir::WalkDir::new(dir)
        .follow_links(true)
        .sort_by_file_name()
        .into_iter();
    while let Some(next) = walk.next() {
        match next {
            Err(error) => found.failed(error)?,
            Ok(entry) if entry.file_type().is_dir() => {
                if !found.folder(&entry) {
                    walk.skip_current_dir();
                }
            }
            Ok(entry) => found.file(&entry),
        }
    }
    let mut items = pair(&found.folders, &found.repeated_asfs);
    items.sort_by(|a, b| {
        (a.motion.as_ref().unwrap_or(&a.path)).cmp(b.motion.as_ref().unwrap_or(&b.path))
    });
    Ok(Walk {
        items,
        skipped: found.skipped,
    })
}

/// What the walk of [`collect`] has met so far: each folder's take files in name order
/// (regular files, each once), for the pairing; what it skipped; and the folders and files
/// already seen, by identity.
struct Found<'a> {
    /// The folder walked, and its real path.
    dir: &'a Path,
    root: PathBuf,
    skipped: Vec<Skip>,
    folders: std::collections::BTreeMap<PathBuf, Vec<PathBuf>>,
    folders_seen: std::collections::HashMap<(u64, u64), PathBuf>,
    files_seen: std::collections::HashMap<(u64, u64), PathBuf>,
    /// The ASFs met again under another name: still their folder's skeleton, never listed
    /// alone twice.
    repeated_asfs: Vec<PathBuf>,
}

impl<'a> Found<'a> {
    /// Nothing met yet in the walk of `dir`, whose real path is `root`.
    fn new(dir: &'a Path, root: PathBuf) -> Found<'a> {
        Found {
            dir,
            root,
            skipped: Vec::new(),
            folders: Default::default(),
            folders_seen: Default::default(),
            files_seen: Default::default(),
            repeated_asfs: Vec::new(),
        }
    }

    /// Notes `path` as skipped, and why.
    fn skip(&mut self, path: &Path, reason: String) {
        self.skipped.push(Skip {
            path: path.to_path_buf(),
            reason,
        })
    }

    /// An entry the walk could not give: a link back up (a loop), a broken link with a take's
    /// name, or what cannot be read, each skipped. `dir` itself unreadable is the error.
    fn failed(&mut self, error: walkdir::Error) -> Result<(), Error> {
        let dir = self.dir;
        let path = error.path().unwrap_or(dir).to_path_buf();
        if let Some(ancestor) = error.loop_ancestor() {
            let reason = format!(
                "a link back to {}, which holds it (a loop): not followed",
                ancestor.display()
            );
            self.skip(&path, reason);
            return Ok(());
        }
        if error.path() == Some(dir) {
            let source = error
                .into_io_error()
                .unwrap_or_else(|| std::io::Error::other("cannot be walked"));
            return Err(Error::io(dir, source));
        }
        let broken = std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink())
            && !path.exists();
        if broken {
            // A broken link that no take's name has is not worth a line.
            if is_take_name(&path) {
                let reason = match std::fs::read_link(&path) {
                    Ok(to) => format!("a link to {}, which does not exist", to.display()),
                    Err(_) => "a link to nothing".to_string(),
                };
                self.skip(&path, reason);
            }
        } else {
            let reason = match error.io_error() {
                Some(io) => unreadable(io),
                None => error.to_string(),
            };
            self.skip(&path, format!("cannot be read: {reason}"));
        }
        Ok(())
    }

    /// A folder met in the walk: whether to walk into it. Not a link out of `dir`, not one
    /// that cannot be read, not one walked already under another path.
    fn folder(&mut self, entry: &walkdir::DirEntry) -> bool {
        let path = entry.path();
        if entry.depth() > 0
            && entry.path_is_symlink()
            && let Some(reason) = link_refused(path, &self.root, self.dir)
        {
            self.skip(path, reason);
            return false;
        }
        let id = match entry.metadata() {
            Ok(metadata) => identity(&metadata),
            Err(e) => {
                self.skip(path, format!("cannot be read: {}", walk_error(&e)));
                return false;
            }
        };
        if let Some(first) = self.folders_seen.get(&id) {
            let reason = format!("the folder {} again: walked once", first.display());
            self.skip(path, reason);
            return false;
        }
        self.folders_seen.insert(id, path.to_path_buf());
        true
    }

    /// A file met in the walk: kept in its folder's list when it has a take's name, is a
    /// regular file inside `dir`, and was not met before under another name (an ASF always is:
    /// it is the skeleton of its folder's AMCs).
    fn file(&mut self, entry: &walkdir::DirEntry) {
        let path = entry.path();
        if !is_take_name(path) {
            return;
        }
        // A link to a file outside `dir` is not followed either: what it points at is not
        // the user's to show.
        if entry.path_is_symlink()
            && let Some(reason) = link_refused(path, &self.root, self.dir)
        {
            self.skip(path, reason);
            return;
        }
        if !entry.file_type().is_file() {
            let kind = crate::io::read::kind_of(&entry.file_type());
            self.skip(path, format!("{kind}, not a take"));
            return;
        }
        let id = match entry.metadata() {
            Ok(metadata) => identity(&metadata),
            Err(e) => {
                self.skip(path, format!("cannot be read: {}", walk_error(&e)));
                return;
            }
        };
        let folder = path.parent().unwrap_or(self.dir).to_path_buf();
        match self.files_seen.get(&id) {
            // An ASF is every AMC's in its folder, whatever other name it has elsewhere.
            Some(_) if extension(path) == "asf" => self.repeated_asfs.push(path.to_path_buf()),
            Some(first) => {
                let reason = format!("the file {} again: listed once", first.display());
                self.skip(path, reason);
                return;
            }
            None => {
                self.files_seen.insert(id, path.to_path_buf());
            }
        }
        self.folders
            .entry(folder)
            .or_default()
            .push(path.to_path_buf());
    }
}

/// The items of each folder's take files: a take that stands alone as it is, an AMC with the
/// ASF `skeleton_for` gives it (or unpaired), then each ASF no AMC used and not met before
/// under another name (`repeated_asfs`), alone.
fn pair(
    folders: &std::collections::BTreeMap<PathBuf, Vec<PathBuf>>,
    repeated_asfs: &[PathBuf],
) -> Vec<Item> {
    let mut items = Vec::new();
    for entries in folders.values() {
        let asfs: Vec<&PathBuf> = entries.iter().filter(|p| extension(p) == "asf").collect();
        let mut used = vec![false; asfs.len()];
        for path in entries {
            let format = crate::take::Format::from_path(path);
            match extension(path).as_str() {
                _ if format.is_some_and(|f| f.stands_alone()) => items.push(Item {
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
            if !used && !repeated_asfs.contains(asf) {
                items.push(Item {
                    path: (*asf).clone(),
                    motion: None,
                });
            }
        }
    }
    items
}

/// [`collect`] for a command that makes something of the takes (`dataset`, `convert DIR`): `dir`
/// must be a folder, and one without any take is refused, as there is nothing to make of it.
/// What the walk skipped (loops, folders and files reached again, links out of `dir`, what is
/// not a regular file or cannot be read) is in [`Walk::skipped`].
pub fn collect_takes(dir: &Path) -> Result<Walk, Error> {
    // A missing folder is an I/O error (Python's FileNotFoundError), a file a usage one.
    match std::fs::metadata(dir) {
        Err(e) => return Err(Error::io(dir, e)),
        Ok(m) if !m.is_dir() => {
            return Err(Error::usage(format!("{}: not a folder", dir.display())));
        }
        Ok(_) => {}
    }
    let walk = collect(dir)?;
    if walk.items.is_empty() {
        // What the walk left out is why there is none to make anything of (a take that is a
        // link out of the folder): the first of it said, the rest counted.
        let why = match &walk.skipped[..] {
            [] => String::new(),
            [only] => format!(": skipped {only}"),
            [first, rest @ ..] => format!(": skipped {first}, and {} more", rest.len()),
        };
        return Err(Error::usage(format!(
            "{}: no takes (.bvh, .asf, .amc, .fbx, .gltf, .glb or .npz files){why}",
            dir.display()
        )));
    }
    Ok(walk)
}

/// What every item is loaded with: the options `info` takes for one file.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Seconds per frame, overriding each file's.
    pub frame_time: Option<f64>,
    /// Files larger than this are refused.
    pub max_size: u64,
    /// The convention the offset-mode warning is judged against.
    pub offset_mode: crate::model::pose::OffsetMode,
    /// The units every take's lengths are in, over the guess (`--units`).
    pub units: Option<crate::model::stance::Units>,
    /// The axis every take stands along, over the guess (`--up`).
    pub up: Option<crate::model::pose::UpAxis>,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            frame_time: None,
            max_size: take::DEFAULT_MAX_SIZE,
            offset_mode: crate::model::pose::OffsetMode::default(),
            units: None,
            up: None,
        }
    }
}

/// The line printed for a loaded item; its warnings are those `info FILE` lists.
fn describe(loaded: &take::Take, offset_mode: crate::model::pose::OffsetMode) -> String {
    let joints = loaded
        .skeleton
        .joints
        .iter()
        .filter(|j| !j.end_site)
        .count();
    let frames = loaded.motion.frame_count();
    let mut line = format!(
        "{}, {}, {} s",
        crate::io::error::counted(joints, "joint"),
        crate::io::error::counted(frames, "frame"),
        crate::info::readable(loaded.motion.duration(), 1)
    );
    let warnings = crate::info::warnings(loaded, offset_mode);
    if !warnings.is_empty() {
        line.push_str(&format!(
            " ({})",
            crate::io::error::counted(warnings.len(), "warning")
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
    crate::io::parallel::map_in_order(
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
                let options = take::OpenOptions {
                    motion: item.motion.clone(),
                    frame_time: settings.frame_time,
                    max_size: Some(settings.max_size),
                    threads: Some(1),
                    units: settings.units,
                    up: settings.up,
                    ..Default::default()
                };
                take::load_take(&item.path, &options)
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
        // A numbered take in a folder without any ASF (a panic before: the check for a numbered
        // only ASF looked at the first of none).
        assert_eq!(paired("07_01", &[]), None);
        assert_eq!(paired("cmu_07_05-walk", &[]), None);
    }

    /// CMU's downloads name a subject's skeleton `cmu_07-walk.asf` and its takes
    /// `cmu_07_05-walk.amc` (`NN-x.asf` with `NN_MM-x.amc`, with or without a prefix).
    #[test]
    fn an_amc_pairs_with_the_asf_named_as_cmu_downloads_name_them() {
        let asfs = ["cmu_07-walk", "cmu_08-walk"];
        assert_eq!(
            paired("cmu_07_05-walk", &asfs).as_deref(),
            Some("cmu_07-walk")
        );
        assert_eq!(
            paired("cmu_08_01-walk", &asfs).as_deref(),
            Some("cmu_08-walk")
        );
        assert_eq!(
            paired("CMU_7_05-Walk", &asfs).as_deref(),
            Some("cmu_07-walk")
        );
        assert_eq!(
            paired("07_05-walk", &["07-walk", "08-walk"]).as_deref(),
            Some("07-walk")
        );
        assert_eq!(paired("07_05-x", &["run", "07-x"]).as_deref(), Some("07-x"));
        // Another subject named the same way is not this take's skeleton, even alone.
        assert_eq!(paired("cmu_09_01-walk", &["cmu_07-walk"]), None);
        assert_eq!(paired("cmu_09_01-walk", &asfs), None);
        // A skeleton named otherwise, alone in the folder, is still the take's.
        assert_eq!(
            paired("cmu_09_01-walk", &["skeleton"]).as_deref(),
            Some("skeleton")
        );
        let item = Item {
            path: PathBuf::from("d/cmu_07_05-walk.amc"),
            motion: None,
        };
        assert_eq!(item.wanted_skeleton(), "cmu_07-walk.asf");
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
