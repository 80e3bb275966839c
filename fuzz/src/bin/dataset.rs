//! A dataset folder as someone else made it: the first byte picks which of its files the rest
//! of the input replaces (the manifest, an array, the offsets, the skeleton), over a real
//! dataset compiled at start. The reader must refuse it or give a dataset whose every clip
//! reads; merge and the way back to a take must answer without a panic.
use bvhview::dataset::{self, Options, merge, read};
use std::path::Path;

const FILES: [&str; 5] = [
    "manifest.json",
    "group_0/positions.npy",
    "group_0/offsets.npy",
    "group_0/rest_offsets.npy",
    "group_0/skeleton.bvh",
];

fn copy_folder(from: &Path, to: &Path) {
    std::fs::create_dir(to).expect("a new folder");
    for entry in std::fs::read_dir(from).expect("the template") {
        let entry = entry.expect("an entry");
        let target = to.join(entry.file_name());
        if entry.file_type().expect("a type").is_dir() {
            copy_folder(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).expect("a copy");
        }
    }
}

fn main() {
    let work = tempfile::tempdir().expect("a temporary folder");
    let takes = work.path().join("takes");
    std::fs::create_dir(&takes).expect("a folder");
    let walk = include_bytes!("../../../tests/data/bvh/assimp_01_01.bvh");
    std::fs::write(takes.join("a.bvh"), walk).expect("a take");
    std::fs::write(takes.join("b.bvh"), walk).expect("a take");
    let template = work.path().join("template");
    let items = dataset::takes(&takes).expect("takes");
    let list = dataset::whole_list(&takes, &items);
    let options = Options {
        fps: 10.0,
        ..Options::default()
    };
    dataset::compile(&takes, items, &options, 1, &template, list, |_, _, _, _| {
        true
    })
    .expect("the template compiles");
    let mut round = 0u64;
    afl::fuzz!(|data: &[u8]| {
        round += 1;
        let (choice, bytes) = bvhview_fuzz::split(data);
        let ds = work.path().join(format!("case_{round}"));
        copy_folder(&template, &ds);
        let file = FILES[usize::from(choice) % FILES.len()];
        std::fs::write(ds.join(file), bytes).expect("the mutated file");
        if let Ok(opened) = read::open(&ds) {
            for (k, group) in opened.groups.iter().enumerate() {
                for clip in opened.manifest.clips.iter().filter(|c| c.group == k) {
                    for array in &group.arrays[..6] {
                        array
                            .read_rows(clip.start..clip.start + clip.frames)
                            .expect("a checked dataset reads its clips");
                    }
                }
                let _ = opened.skeleton(k);
            }
            let merged = ds.with_extension("merged");
            let _ = merge::merge(&[ds.clone()], &merged, merge::Join::Folders);
            let _ = std::fs::remove_dir_all(&merged);
        }
        let _ = std::fs::remove_dir_all(&ds);
    });
}
