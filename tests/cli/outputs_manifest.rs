//! The CLI's outputs on the repository's own files, byte for byte, against a manifest written
//! by the binary before a change (the house was rebuilt without changing what it does).
//!
//! `tests/cli_outputs.tsv` holds, per command, its exit code and the SHA-256 of its stdout, its
//! stderr and every file it wrote (paths of the scratch folder replaced by `$OUT`). To write the
//! manifest from another build of the binary (say, the last commit's):
//! `BVHVIEW_CLI_BIN=/path/to/bvhview BVHVIEW_CLI_WRITE=1 cargo test --test cli outputs_manifest`.
//! Pictures are left out: they are held by the golden tests, at the renderer's tolerance.

use crate::common;

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::process::Command;

const MANIFEST: &str = "tests/cli_outputs.tsv";

fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn binary() -> PathBuf {
    std::env::var_os("BVHVIEW_CLI_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_bvhview")))
}

fn hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Every take of the repository's own corpus and edge inputs, as paths relative to the repository.
fn takes() -> Vec<String> {
    let mut takes = Vec::new();
    // A build without a format's feature refuses its files; their lines are left out.
    let formats = [
        ("tests/data/bvh", &["bvh"][..], true),
        ("tests/data/fbx", &["fbx"][..], cfg!(feature = "fbx")),
        (
            "tests/data/gltf",
            &["glb", "gltf"][..],
            cfg!(feature = "gltf"),
        ),
        ("tests/edge", &["bvh"][..], true),
    ];
    for (dir, exts, _) in formats.into_iter().filter(|(_, _, built)| *built) {
        for ext in exts {
            for file in common::files_in(&repo().join(dir), ext) {
                takes.push(format!(
                    "{dir}/{}",
                    file.file_name().unwrap().to_str().unwrap()
                ));
            }
        }
    }
    takes.push(
        "tests/data/asf_amc/heiden_12.asf --motion tests/data/asf_amc/heiden_12_02_01.amc".into(),
    );
    takes
}

/// The commands, each a line of words; `$OUT` is a fresh scratch folder.
fn commands() -> Vec<String> {
    let mut commands = Vec::new();
    for take in takes() {
        commands.push(format!("info {take}"));
        commands.push(format!("positions {take} --frames 0..3 -o $OUT/p.csv"));
        commands.push(format!("convert {take} -o $OUT/c.bvh"));
        if cfg!(feature = "gltf") {
            commands.push(format!("convert {take} --frames 0..2 -o $OUT/c.glb"));
        }
        commands.push(format!("retarget {take} --onto smpl22 --show-map"));
        commands.push(format!("retarget {take} --onto smpl22 -o $OUT/r.bvh"));
        if take.ends_with(".bvh") {
            commands.push(format!("print {take}"));
            commands.push(format!("trace {take} --explain"));
        }
    }
    if cfg!(all(feature = "fbx", feature = "gltf")) {
        commands.push("info tests/data".into());
    }
    commands.push("dataset tests/data/bvh -o $OUT/ds".into());
    commands.push(
        "convert tests/data/bvh/bvh11_131_01.bvh --frames 0..10 --onto smplh -o $OUT/o.npz".into(),
    );
    commands.push("generate man".into());
    commands
}

/// Runs one command; its line of the manifest.
fn run(command: &str) -> String {
    let out = tempfile::tempdir().unwrap();
    let out_text = out.path().to_str().unwrap();
    let words: Vec<String> = command
        .split_whitespace()
        .map(|w| w.replace("$OUT", out_text))
        .collect();
    let result = Command::new(binary())
        .args(&words)
        .current_dir(repo())
        .env("LC_ALL", "C")
        .output()
        .unwrap();
    // The scratch folder's name, and the time a folder summary took, change from run to run.
    let scrub = |bytes: &[u8]| {
        let text = String::from_utf8_lossy(bytes).replace(out_text, "$OUT");
        let kept: Vec<&str> = text
            .split_inclusive('\n')
            .filter(|l| !l.contains(" MB/s)"))
            .collect();
        kept.concat().into_bytes()
    };
    let mut files: Vec<PathBuf> = walkdir::WalkDir::new(out.path())
        .sort_by_file_name()
        .into_iter()
        .map(|e| e.unwrap().into_path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    let files: Vec<String> = files
        .iter()
        .map(|p| {
            let name = p.strip_prefix(out.path()).unwrap().display().to_string();
            format!("{name}={}", hex(&scrub(&std::fs::read(p).unwrap())))
        })
        .collect();
    format!(
        "{command}\t{}\t{}\t{}\t{}",
        result
            .status
            .code()
            .map_or("signal".into(), |c| c.to_string()),
        hex(&scrub(&result.stdout)),
        hex(&scrub(&result.stderr)),
        files.join(" ")
    )
}

#[test]
fn the_cli_writes_what_it_wrote_before() {
    let lines: Vec<String> = commands().iter().map(|c| run(c)).collect();
    let manifest = repo().join(MANIFEST);
    if std::env::var_os("BVHVIEW_CLI_WRITE").is_some() {
        std::fs::write(&manifest, lines.join("\n") + "\n").unwrap();
        return;
    }
    let expected = std::fs::read_to_string(&manifest).unwrap();
    let expected: std::collections::HashMap<&str, &str> = expected
        .lines()
        .map(|line| (line.split('\t').next().unwrap(), line))
        .collect();
    let missing: Vec<String> = commands()
        .into_iter()
        .filter(|c| !expected.contains_key(c.as_str()))
        .collect();
    assert!(missing.is_empty(), "not in the manifest: {missing:?}");
    if cfg!(all(feature = "fbx", feature = "gltf")) {
        assert_eq!(
            expected.len(),
            lines.len(),
            "the manifest has commands the test no longer runs"
        );
    }
    let differ: Vec<String> = lines
        .iter()
        .map(|l| (expected[l.split('\t').next().unwrap()], l.as_str()))
        .filter(|(e, l)| e != l)
        .map(|(e, l)| format!("before: {e}\n   now: {l}"))
        .collect();
    assert!(
        differ.is_empty(),
        "{} of {} commands write something else now:\n{}",
        differ.len(),
        lines.len(),
        differ.join("\n")
    );
}
