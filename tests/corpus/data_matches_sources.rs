//! The repository's own test data is what its README says: every corpus file listed in
//! tests/data/SOURCES.md with an existing licence file and no non-redistributable licence, and
//! every copy still byte for byte the shared corpus's (when ../shared is there).

use crate::common;
use common::*;
use std::collections::BTreeSet;
use std::path::Path;

/// The files and licence files the SOURCES tables name, above "## Left out".
fn listed() -> (BTreeSet<String>, BTreeSet<String>, String) {
    let text = std::fs::read_to_string(repo_data("SOURCES.md")).unwrap();
    let kept = &text[..text.find("## Left out").expect("a Left out section")];
    let mut files = BTreeSet::new();
    let mut licences = BTreeSet::new();
    let mut folder = "";
    for line in kept.lines() {
        if let Some(rest) = line.strip_prefix("## ") {
            let start = rest.find("(`").map(|i| i + 2).unwrap_or(rest.len());
            folder = rest[start..].trim_end_matches("`)");
        }
        let Some(row) = line.strip_prefix("| `") else {
            continue;
        };
        let name = &row[..row.find('`').unwrap()];
        files.insert(format!("{folder}{name}"));
        let mut ticks = line.split('`').skip(1).step_by(2);
        ticks.next();
        licences.extend(
            ticks
                .filter(|t| !t.contains(' ') && (t.ends_with(".txt") || t.ends_with(".md")))
                .map(str::to_string),
        );
    }
    (files, licences, kept.to_string())
}

fn corpus_files(root: &Path) -> BTreeSet<String> {
    let mut files = BTreeSet::new();
    for folder in ["bvh", "asf_amc", "bvh_malformed"] {
        for entry in std::fs::read_dir(root.join(folder)).unwrap() {
            let name = entry.unwrap().file_name().into_string().unwrap();
            files.insert(format!("{folder}/{name}"));
        }
    }
    files
}

#[test]
fn every_repository_file_is_listed_with_a_licence_that_allows_redistribution() {
    let (listed, licences, text) = listed();
    let present = corpus_files(&repo_data(""));
    assert_eq!(present.len(), 29, "{present:?}");
    assert_eq!(listed, present, "SOURCES.md and tests/data disagree");
    // The DALi licence is named in the section's text, not in a table row.
    assert!(text.contains("`dali-toolkit_LICENSE_Apache-2.0.txt`"));
    let mut named = licences.clone();
    named.insert("dali-toolkit_LICENSE_Apache-2.0.txt".to_string());
    let on_disk: BTreeSet<String> = std::fs::read_dir(repo_data("licenses"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(
        named, on_disk,
        "licence files named vs in tests/data/licenses"
    );
    for forbidden in ["NC", "GPL", "Non-Commercial", "NonCommercial"] {
        assert!(
            !text.contains(forbidden),
            "a kept file is listed under {forbidden}"
        );
    }
    for licence in &on_disk {
        let body = std::fs::read_to_string(repo_data("licenses").join(licence)).unwrap();
        assert!(
            !body.contains("NonCommercial") && !body.contains("GNU GENERAL PUBLIC"),
            "{licence}"
        );
    }
}

#[test]
fn every_edge_input_is_described_in_its_readme() {
    let readme = std::fs::read_to_string(edge("README.md")).unwrap();
    for path in files_in(&edge(""), "bvh") {
        let name = path.file_name().unwrap().to_str().unwrap();
        assert!(readme.contains(&format!("`{name}`")), "{name}");
    }
}

fn assert_same_bytes(ours: &Path, theirs: &Path) {
    let a = std::fs::read(ours).unwrap_or_else(|e| panic!("{}: {e}", ours.display()));
    let b = std::fs::read(theirs).unwrap_or_else(|e| panic!("{}: {e}", theirs.display()));
    assert!(
        a == b,
        "{} differs from {}",
        ours.display(),
        theirs.display()
    );
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn repository_copies_equal_the_shared_corpus_and_oracle() {
    for file in corpus_files(&repo_data("")) {
        assert_same_bytes(&repo_data(&file), &shared_data(&file));
    }
    for entry in std::fs::read_dir(repo_data("licenses")).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        let file = format!("licenses/{name}");
        assert_same_bytes(&repo_data(&file), &shared_data(&file));
    }
    let shared_oracle = shared_data("").join("../oracle");
    let mut compared = 0;
    for folder in ["inputs", "print", "refs", "trace", ""] {
        for entry in std::fs::read_dir(shared_oracle.join(folder)).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_str().unwrap();
            if path.is_file() && name != "README.md" && !name.starts_with('.') {
                let relative = path.strip_prefix(&shared_oracle).unwrap();
                assert_same_bytes(&oracle(relative.to_str().unwrap()), &path);
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 26, "files of ../shared/oracle");
}
