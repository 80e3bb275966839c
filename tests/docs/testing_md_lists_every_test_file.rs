//! docs/TESTING.md names every Rust file under tests/, and only files that exist: a newcomer
//! finds each test file there with a line of what it tests, and the list cannot fall behind a
//! file added, moved or removed.

use std::collections::BTreeSet;
use std::path::Path;

/// Every `.rs` file under tests/, as `tests/FOLDER/FILE.rs`.
fn rust_files_under_tests(root: &Path) -> BTreeSet<String> {
    let mut files = BTreeSet::new();
    for entry in walkdir::WalkDir::new(root.join("tests")) {
        let entry = entry.unwrap();
        let path = entry.path();
        if entry.file_type().is_file() && path.extension().is_some_and(|e| e == "rs") {
            let relative = path.strip_prefix(root).unwrap();
            files.insert(relative.to_str().unwrap().to_string());
        }
    }
    files
}

/// Every `tests/….rs` path the text names: a path that starts at `tests/` (not inside a longer
/// path such as `python/tests/`, and not a `src/…` file) and ends in `.rs`.
fn test_files_named_in(text: &str) -> BTreeSet<String> {
    let bytes = text.as_bytes();
    let mut named = BTreeSet::new();
    let mut from = 0;
    while let Some(found) = text[from..].find("tests/") {
        let start = from + found;
        from = start + "tests/".len();
        let before = start.checked_sub(1).map(|i| bytes[i]);
        if before.is_some_and(|b| b.is_ascii_alphanumeric() || b == b'/' || b == b'_' || b == b'.')
        {
            continue;
        }
        let end = text[start..]
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '/' || c == '.'))
            .map_or(text.len(), |n| start + n);
        let path = text[start..end].trim_end_matches('.');
        if path.ends_with(".rs") {
            named.insert(path.to_string());
        }
    }
    named
}

#[test]
fn testing_md_names_every_test_file_and_no_other() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let testing = std::fs::read_to_string(root.join("docs/TESTING.md")).unwrap();
    let named = test_files_named_in(&testing);
    let files = rust_files_under_tests(root);
    let unnamed: Vec<&String> = files.difference(&named).collect();
    let missing: Vec<&String> = named.difference(&files).collect();
    assert!(
        unnamed.is_empty(),
        "docs/TESTING.md does not name these test files (add a line of what each tests): {unnamed:?}"
    );
    assert!(
        missing.is_empty(),
        "docs/TESTING.md names test files that do not exist (moved or removed?): {missing:?}"
    );
}

#[test]
fn a_path_is_read_only_where_it_starts_at_tests() {
    let text = "`tests/cli/main.rs` and tests/motion/retarget.rs, not python/tests/x.rs nor \
                src/tests/y.rs nor `tests/data/SOURCES.md`; tests/render/golden_pictures.rs.";
    let named: Vec<String> = test_files_named_in(text).into_iter().collect();
    assert_eq!(
        named,
        [
            "tests/cli/main.rs",
            "tests/motion/retarget.rs",
            "tests/render/golden_pictures.rs"
        ]
    );
}
