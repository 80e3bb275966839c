//! Helpers shared by the integration tests. Real-world files are read from ../shared/data.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

pub fn shared() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared")
}

pub fn data(relative: &str) -> PathBuf {
    shared().join("data").join(relative)
}

/// Every file with extension `ext` in a folder, sorted; fails if there is none.
pub fn files_in(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no .{ext} files in {}", dir.display());
    files
}

pub fn load(relative: &str) -> bvhview::bvh::Bvh {
    let path = data(relative);
    bvhview::bvh::load_file(&path).unwrap_or_else(|e| panic!("{e}"))
}

pub fn load_text(text: &str) -> Result<bvhview::bvh::Bvh, bvhview::Error> {
    bvhview::bvh::load_bytes(text.as_bytes(), "t.bvh")
}

pub fn error_text(text: &str) -> String {
    match load_text(text) {
        Ok(_) => panic!("loaded, expected an error:\n{text}"),
        Err(e) => e.to_string(),
    }
}
