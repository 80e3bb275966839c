//! `bvhview trace`: the calls one display() makes, in C with printf's %f.

mod common;
use common::*;
use std::process::Command;

fn trace(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_bvhview"))
        .arg("trace")
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// Every number in a line of C, in order.
fn numbers(line: &str) -> Vec<f64> {
    line.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
        .filter(|s| s.chars().any(|c| c.is_ascii_digit()))
        .map(|s| s.parse().unwrap())
        .collect()
}

#[test]
fn trace_of_tiny_crlf_is_pinned_and_matches_the_articles_calls() {
    let input = oracle("inputs/tiny_crlf.bvh").display().to_string();
    let ours = trace(&[&input, "--frame", "1"]);
    let pinned = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/snapshots/trace_tiny_crlf__f1__a10.txt"),
    )
    .unwrap();
    assert_eq!(ours, pinned);
    assert!(ours.contains("glPushMatrix();\nglTranslatef(5.000000, 30.000000, -3.000000);\n"));
    assert!(ours.contains("glutSolidSphere(1.000000, 20, 16);\n"));

    // The article's own trace (apitrace) from display()'s glClear on: same calls, same numbers.
    let article = std::fs::read_to_string(oracle("trace/tiny_crlf__f1__a10.txt")).unwrap();
    let display: Vec<&str> = article
        .lines()
        .skip_while(|l| !l.starts_with("glClear("))
        .collect();
    let ours: Vec<&str> = ours.lines().collect();
    assert_eq!(ours.len(), display.len());
    for (a, b) in ours.iter().zip(&display) {
        assert_eq!(a.split('(').next(), b.split('(').next());
        let (x, y) = (numbers(a), numbers(b));
        assert_eq!(x.len(), y.len(), "{a} / {b}");
        for (p, q) in x.iter().zip(&y) {
            assert!((p - q).abs() <= 5.1e-7, "{a} / {b}");
        }
    }
}

#[test]
fn trace_follows_the_frame_and_the_style() {
    let input = oracle("inputs/tiny_crlf.bvh").display().to_string();
    let frame0 = trace(&[&input, "--frame", "0"]);
    assert!(frame0.contains("glTranslatef(0.000000, 30.000000, 0.000000);\n"));
    let sticks = trace(&[&input, "--frame", "0", "--style", "sticks"]);
    assert!(!sticks.contains("glutSolidSphere"));
    assert!(sticks.contains("glDisable(GL_LIGHTING);\nglBegin(GL_LINES);\n"));
}

/// `--numbers apitrace` writes what a recording of the article's program holds, from init() on:
/// the two diff line for line with nothing to show.
#[test]
fn apitrace_numbers_diff_empty_against_the_articles_recording() {
    let input = oracle("inputs/tiny_crlf.bvh").display().to_string();
    let ours = trace(&[&input, "--frame", "1", "--numbers", "apitrace"]);
    let article = std::fs::read_to_string(oracle("trace/tiny_crlf__f1__a10.txt")).unwrap();
    assert_eq!(ours, article);
}

/// `--explain` (English and Chinese) is pinned; it is the same calls as the plain trace, indented
/// by the stack depth, and each sphere's note gives the world position `positions` reports.
#[test]
fn explain_annotates_the_same_calls_in_both_languages() {
    let input = oracle("inputs/tiny_crlf.bvh").display().to_string();
    let plain = trace(&[&input, "--frame", "1"]);
    let snapshots = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots");
    for (lang, golden) in [
        ("en", "trace_explain_tiny_crlf__f1__a10.txt"),
        ("zh", "trace_explain_zh_tiny_crlf__f1__a10.txt"),
    ] {
        let explained = trace(&[&input, "--frame", "1", "--explain", "--lang", lang]);
        assert_eq!(
            explained,
            std::fs::read_to_string(snapshots.join(golden)).unwrap(),
            "{lang}"
        );
        // Without the joint headers and the notes, and unindented: the plain trace.
        let calls: Vec<&str> = explained
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .map(|l| l.split(" // ").next().unwrap().trim())
            .collect();
        assert_eq!(calls, plain.lines().collect::<Vec<_>>(), "{lang}");
    }
    // Every sphere's world position, against `positions` (both print the same float).
    let explained = trace(&[&input, "--frame", "1", "--explain"]);
    let csv = std::process::Command::new(env!("CARGO_BIN_EXE_bvhview"))
        .args(["positions", &input, "--frames", "1"])
        .output()
        .unwrap()
        .stdout;
    let csv = String::from_utf8(csv).unwrap();
    let spheres: Vec<Vec<f64>> = explained
        .lines()
        .filter_map(|l| l.split_once("'s sphere, at ("))
        .map(|(_, at)| numbers(at.split(')').next().unwrap()))
        .collect();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').skip(2).map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(spheres.len(), 12);
    assert_eq!(spheres.len(), rows.len());
    for (sphere, row) in spheres.iter().zip(&rows) {
        for (a, b) in sphere.iter().zip(row) {
            assert!(
                (a - b).abs() <= 1e-4 * b.abs().max(1.0),
                "{sphere:?} vs {row:?}"
            );
        }
    }
}

/// Issue 25: where a joint's own columns are not the ones the article's `pFrame` reads
/// (position channels on a joint other than the root), `--explain` says which column the
/// article reads instead, warns once that the article misreads the file, numbers End Sites as
/// `info` does (they are not joints), and says whether position channels replace the OFFSET or
/// are added to it.
#[test]
fn explain_says_where_the_articles_pframe_points() {
    let input = edge("position_channels_non_root.bvh").display().to_string();
    let snapshots = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots");
    for (lang, golden) in [
        ("en", "trace_explain_position_channels_non_root__f1.txt"),
        ("zh", "trace_explain_zh_position_channels_non_root__f1.txt"),
    ] {
        let explained = trace(&[&input, "--frame", "1", "--explain", "--lang", lang]);
        assert_eq!(
            explained,
            std::fs::read_to_string(snapshots.join(golden)).unwrap(),
            "{lang}"
        );
        assert_eq!(
            explained.matches("// note: ").count() + explained.matches("// 注意：").count(),
            1
        );
    }
    let english = trace(&[&input, "--frame", "1", "--explain"]);
    assert!(english.contains(
        "// Zrotation: column [9]; the article's pFrame[0] is column [6], another channel's value"
    ));
    assert!(english.contains("// End Site of Chest: no MOTION columns"));
    let added = trace(&[&input, "--frame", "1", "--explain", "--offset-mode", "add"]);
    assert!(
        added.contains("OFFSET (0, 15, 0) plus Xposition = [6], Yposition = [7], Zposition = [8]")
    );
    // A file the article reads as it is: no note.
    let tiny = oracle("inputs/tiny_crlf.bvh").display().to_string();
    assert!(!trace(&[&tiny, "--explain"]).contains("// note: "));
}
