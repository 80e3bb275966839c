//! A dataset folder is input from anyone: mutated manifests and `.npy` files fed to the reader
//! and to merge. Whatever the mutation, the answer is a dataset whose every range reads, or an
//! error; never a panic, a hang, or a merge that writes anything from a refused piece.

use bvhview::dataset::{self, Options, merge, read};
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// One small dataset of two clips in one group, compiled once.
fn template() -> &'static Path {
    static MADE: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();
    let (_, path) = MADE.get_or_init(|| {
        let temp = tempfile::tempdir().unwrap();
        let takes = temp.path().join("takes");
        std::fs::create_dir(&takes).unwrap();
        let walk = std::fs::read("tests/data/bvh/assimp_01_01.bvh").unwrap();
        std::fs::write(takes.join("a.bvh"), &walk).unwrap();
        std::fs::write(takes.join("b.bvh"), &walk).unwrap();
        let out = temp.path().join("ds");
        let items = dataset::takes(&takes).unwrap();
        let list = dataset::whole_list(&takes, &items);
        let options = Options {
            fps: 10.0,
            ..Options::default()
        };
        dataset::compile(&takes, items, &options, 1, &out, list, |_, _, _, _| true).unwrap();
        (temp, out)
    });
    path
}

fn copy_folder(from: &Path, to: &Path) {
    std::fs::create_dir(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_folder(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

/// The files a mutation may hit.
const FILES: [&str; 5] = [
    "manifest.json",
    "group_0/positions.npy",
    "group_0/offsets.npy",
    "group_0/rotations.npy",
    "group_0/rest_offsets.npy",
];

/// What a reader that accepted a dataset must be able to do: read every clip's rows of every
/// array, and merge it.
fn use_it(dataset: &read::Dataset, out: &Path) {
    for (k, group) in dataset.manifest.groups.iter().enumerate() {
        let files = &dataset.groups[k];
        for clip in dataset.manifest.clips.iter().filter(|c| c.group == k) {
            for array in &files.arrays[..6] {
                array
                    .read_rows(clip.start..clip.start + clip.frames)
                    .expect("a checked dataset reads its clips");
            }
        }
        assert_eq!(files.offsets.last().copied(), Some(group.frames));
    }
    let merged = merge::merge(
        std::slice::from_ref(&dataset.path),
        out,
        merge::Join::Folders,
    );
    assert!(
        merged.is_ok() || !out.exists(),
        "a refused merge writes nothing"
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Bytes of one file flipped, cut, or one number in the manifest replaced.
    #[test]
    fn mutated_datasets_are_read_or_refused_never_a_panic(
        file in 0..FILES.len(),
        at in any::<prop::sample::Index>(),
        byte in any::<u8>(),
        cut in any::<bool>(),
        number in prop_oneof![Just(0i128), Just(-1), Just(1 << 63), Just(u64::MAX as i128), 0..100_000i128],
        replace_number in any::<bool>(),
    ) {
        let temp = tempfile::tempdir().unwrap();
        let ds = temp.path().join("ds");
        copy_folder(template(), &ds);
        let path = ds.join(FILES[file]);
        let mut bytes = std::fs::read(&path).unwrap();
        if replace_number && file == 0 {
            // One of the manifest's numbers (a start, a frame count, a shape) replaced.
            let text = String::from_utf8(bytes.clone()).unwrap();
            let digits: Vec<usize> = text
                .char_indices()
                .filter(|&(i, c)| c.is_ascii_digit() && (i == 0 || !text.as_bytes()[i - 1].is_ascii_alphanumeric()))
                .map(|(i, _)| i)
                .collect();
            let start = digits[at.index(digits.len())];
            let end = start + text[start..].find(|c: char| !c.is_ascii_digit()).unwrap_or(0);
            bytes = format!("{}{number}{}", &text[..start], &text[end..]).into_bytes();
        } else if cut {
            bytes.truncate(at.index(bytes.len() + 1));
        } else {
            let i = at.index(bytes.len());
            bytes[i] ^= byte.max(1);
        }
        std::fs::write(&path, &bytes).unwrap();
        if let Ok(dataset) = read::open(&ds) {
            use_it(&dataset, &temp.path().join("merged"));
        }
    }
}

#[test]
fn the_template_itself_reads_and_merges() {
    let dataset = read::open(template()).unwrap();
    assert_eq!(dataset.manifest.clips.len(), 2);
    let temp = tempfile::tempdir().unwrap();
    use_it(&dataset, &temp.path().join("merged"));
    assert!(temp.path().join("merged/manifest.json").is_file());
}
