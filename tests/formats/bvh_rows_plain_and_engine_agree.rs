//! The row loop exists twice: `rows::read_rows_simple`, the article's loop in plain
//! Rust, and the engine the loader runs. Both must give the same values bit for bit, the same
//! row count and warnings, and the same error at the same line and column: on every file of the
//! repository, the whole corpus when it is there, every `tests/edge` input, and generated text.

use crate::common;
use bvhview::bvh::loader::{RowReader, Settings};
use common::*;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

/// A load's outcome in comparable form: values as bits, warnings, or the error's text.
fn outcome(path: &Path, settings: Settings) -> Result<(String, Vec<u32>, Vec<String>), String> {
    bvhview::bvh::load_file(path, settings)
        .map(|bvh| {
            let bits = bvh.motion.data.iter().map(|v| v.to_bits()).collect();
            let shape = format!(
                "{} joints, {} frames of {} channels, frame time {}",
                bvh.skeleton.joints.len(),
                bvh.motion.frame_count(),
                bvh.motion.channels,
                bvh.motion.frame_time
            );
            (shape, bits, bvh.warnings)
        })
        .map_err(|e| e.to_string())
}

/// The simple loop against the engine read whole, streamed on one thread and on two.
fn same_both_ways(path: &Path) {
    let simple = outcome(
        path,
        Settings {
            rows: RowReader::Simple,
            ..Settings::default()
        },
    );
    for (threads, first_read) in [(2, 64 << 10), (1, 1), (2, 1), (2, 1 << 30)] {
        let engine = outcome(
            path,
            Settings {
                threads,
                first_read,
                ..Settings::default()
            },
        );
        assert_eq!(
            simple,
            engine,
            "{}: {threads} threads, first read {first_read}",
            path.display()
        );
    }
}

fn bvh_files(folder: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(folder)
        .unwrap_or_else(|e| panic!("{}: {e}", folder.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bvh"))
        .collect();
    files.sort();
    files
}

#[test]
fn both_row_loops_agree_on_every_repository_file_and_edge_case() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut checked = 0;
    for folder in ["tests/data/bvh", "tests/edge", "tests/oracle/inputs"] {
        for path in bvh_files(&root.join(folder)) {
            same_both_ways(&path);
            checked += 1;
        }
    }
    assert!(checked >= 30, "{checked} files");
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn both_row_loops_agree_on_the_whole_corpus() {
    for folder in ["bvh", "bvh_malformed"] {
        let files = bvh_files(&shared_data(folder));
        assert!(!files.is_empty());
        for path in files {
            same_both_ways(&path);
        }
    }
}

/// Past the last row nothing waits for a whole line: a line longer than the engine's
/// chunks is counted in pieces, once, on its own line, and a NUL byte there stops both readers at
/// the same place, however far into the line it is.
#[test]
fn both_row_loops_agree_past_the_rows_on_long_lines_and_nul_bytes() {
    let control = std::fs::read(edge("article_base_crlf.bvh")).unwrap();
    let long = |byte: u8| vec![byte; 3 << 20];
    let tails: Vec<(&str, Vec<u8>)> = vec![
        ("a long line", [long(b'x'), b"\r\n1 2\n".to_vec()].concat()),
        (
            "a long blank line",
            [long(b' '), b"y\r\n".to_vec()].concat(),
        ),
        (
            "a long line in CRs",
            [b"\r".to_vec(), long(b'x'), b"\r\rz".to_vec()].concat(),
        ),
        ("a NUL at once", vec![0; 100]),
        ("a NUL far in", [long(b'x'), vec![0]].concat()),
        (
            "a NUL lines on",
            [b"1 2 3\r\n\r\n".to_vec(), long(b'x'), b"\n \t\0".to_vec()].concat(),
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (what, tail) in tails {
        let path = dir.path().join("tail.bvh");
        std::fs::write(&path, [control.clone(), tail].concat()).unwrap();
        let outcome = outcome(&path, Settings::default());
        match what {
            "a long line" | "a long blank line" => {
                // Blanks and then a word are one line: one row.
                let rows = if what == "a long line" {
                    "2 extra rows"
                } else {
                    "1 extra row "
                };
                let warnings = &outcome.as_ref().unwrap().2;
                assert_eq!(warnings.len(), 1, "{what}");
                assert!(warnings[0].starts_with(rows), "{what}: {warnings:?}");
                assert!(
                    warnings[0].ends_with("from line 21 on"),
                    "{what}: {warnings:?}"
                );
            }
            "a long line in CRs" => {
                let warnings = &outcome.as_ref().unwrap().2;
                assert!(
                    warnings[0].contains("2 extra rows") && warnings[0].ends_with("line 22 on"),
                    "{warnings:?}"
                );
            }
            _ => assert!(
                outcome
                    .as_ref()
                    .unwrap_err()
                    .contains("found a NUL byte after the last frame"),
                "{what}: {outcome:?}"
            ),
        }
        same_both_ways(&path);
    }
}

/// One word of a MOTION row: the usual shapes, exponents, signs, and now and then one that is
/// not a finite number.
fn word() -> impl Strategy<Value = String> {
    prop_oneof![
        8 => (-500.0f64..500.0, 0usize..7).prop_map(|(v, d)| format!("{v:.d$}")),
        2 => (-9.9f64..9.9, -40i32..40).prop_map(|(m, e)| format!("{m:.4}e{e}")),
        1 => (0u32..100_000).prop_map(|v| format!("+{v}")),
        1 => (0u32..1000).prop_map(|v| format!(".{v}")),
        1 => prop::sample::select(vec!["abc", "1e39", "nan", "-", "1.2.3", "inf", "0x10", "1,5"])
            .prop_map(str::to_string),
    ]
}

/// A whole MOTION section's text after `Frame Time:`: rows of about `width` words with random
/// blanks, blank lines and line ends.
fn rows_text(width: usize) -> impl Strategy<Value = String> {
    let row = prop::collection::vec(word(), width.saturating_sub(1)..=width + 1);
    let line = prop_oneof![
        10 => row.prop_map(|words| words.join(" ")),
        1 => prop::sample::select(vec!["", " ", "\t \t", "\0", " x\0"]).prop_map(str::to_string),
        1 => prop::collection::vec(word(), width..=width).prop_map(|w| format!("\t{}  ", w.join("\t"))),
    ];
    let end = prop::sample::select(vec!["\n", "\r\n", "\r"]);
    (prop::collection::vec((line, end), 0..12), any::<bool>()).prop_map(|(lines, trailing)| {
        let mut text: String = lines.iter().map(|(l, e)| format!("{l}{e}")).collect();
        if !trailing {
            text.truncate(text.trim_end_matches(['\r', '\n']).len());
        }
        text
    })
}

fn header(channels: &[usize]) -> String {
    let names = [
        "Xposition",
        "Yposition",
        "Zposition",
        "Zrotation",
        "Xrotation",
        "Yrotation",
    ];
    let mut text = String::from("HIERARCHY\n");
    for (i, &count) in channels.iter().enumerate() {
        let keyword = if i == 0 { "ROOT" } else { "JOINT" };
        text.push_str(&format!(
            "{keyword} j{i}\n{{\nOFFSET 1 2 3\nCHANNELS {count} {}\n",
            names[..count].join(" ")
        ));
    }
    text.push_str("End Site\n{\nOFFSET 0 1 0\n}\n");
    text.push_str(&"}\n".repeat(channels.len()));
    text
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, .. ProptestConfig::default() })]

    #[test]
    fn both_row_loops_agree_on_generated_rows(
        (channels, frames, rows) in prop::collection::vec(0usize..=6, 1..4).prop_flat_map(|channels| {
            // Rows of about the channels' width, a row or word off now and then.
            let width = channels.iter().sum::<usize>().max(1);
            (Just(channels), 0u64..12, rows_text(width))
        }),
    ) {
        let text = format!("{}MOTION\nFrames: {frames}\nFrame Time: 0.5\n{rows}", header(&channels));
        let dir = crate::common::scratch_folder("rows-simple");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("generated.bvh");
        std::fs::write(&path, &text).unwrap();
        same_both_ways(&path);
    }
}
