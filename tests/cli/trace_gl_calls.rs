//! `bvhview trace`: the calls one display() makes, in C with printf's %f.

use crate::common;
use common::*;

fn trace(args: &[&str]) -> String {
    let out = crate::common::bvhview_command()
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
    let csv = crate::common::bvhview_command()
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

/// Where a joint's own columns are not the ones the article's `pFrame` reads
/// (position channels on a joint other than the root), `--explain` says which column the
/// article reads instead, numbers End Sites as `info` does (they are not joints), and says whether
/// position channels replace the OFFSET or are added to it. Its first line says what
/// the article's program does with the file (here it rejects it, at the `Z` its `p += 30` lands
/// on), and the second that the notes below are what its draw would do.
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
        assert!(
            explained
                .lines()
                .next()
                .unwrap()
                .contains("_Z_ _90_ file format error!!")
        );
    }
    let english = trace(&[&input, "--frame", "1", "--explain"]);
    assert!(english.starts_with(
        "// what the article's program does with this file: rejects it: at line 9, column 44 its \
         dispatcher meets a byte it has no case for and prints _Z_ _90_ file format error!!; \
         loadFile returns 0 (init then prints the null root anyway, which crashes)\n\
         // the article's program stops before it draws: the notes below say what its draw would \
         make of each joint's channels\n"
    ));
    assert!(english.contains(
        "// Zrotation: column [9]; the article turns about X here, by pFrame[0], column [6]"
    ));
    assert!(english.contains("replaced by Xposition = [6], Yposition = [7], Zposition = [8]; the article translates by the OFFSET alone"));
    assert!(english.contains("// End Site of Chest: no MOTION columns"));
    let added = trace(&[&input, "--frame", "1", "--explain", "--offset-mode", "add"]);
    assert!(
        added.contains("OFFSET (0, 15, 0) plus Xposition = [6], Yposition = [7], Zposition = [8]")
    );
    // A file the article reads as it is.
    let tiny = oracle("inputs/tiny_crlf.bvh").display().to_string();
    assert!(
        trace(&[&tiny, "--explain"]).starts_with(
            "// what the article's program does with this file: reads it as written: "
        )
    );
}

/// The four words, in English and in Chinese.
const WORDS: [(&str, &str); 4] = [
    ("reads it as written", "如實讀入"),
    ("misreads it", "讀錯"),
    ("rejects it", "拒絕"),
    ("crashes on it", "當掉"),
];

/// `trace FILE --explain`'s first line, in English or Chinese, whether bvhview loads the file or
/// not (then the line comes before the error, and the exit code is 2).
fn verdict(path: &str, lang: &str) -> String {
    let out = crate::common::bvhview_command()
        .args(["trace", path, "--explain", "--lang", lang])
        .output()
        .unwrap();
    assert!(matches!(out.status.code(), Some(0 | 2)), "{path}");
    let stdout = String::from_utf8(out.stdout).unwrap();
    stdout.lines().next().unwrap_or_default().to_string()
}

/// The table at the end of tests/edge/README.md gives, for every input of tests/edge,
/// tests/oracle/inputs and tests/data/bvh, what the article's program rebuilt from its text did
/// with it in one of four words. `--explain` must say the same word, in both languages, and the
/// table must list every such file.
#[test]
fn explain_says_what_the_articles_program_does_with_every_input() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("tests/edge/README.md")).unwrap();
    let table = readme
        .split("## In one word")
        .nth(1)
        .expect("tests/edge/README.md has its table in one word");
    let rows: Vec<(String, String)> = table
        .lines()
        .filter_map(|line| {
            let cells: Vec<&str> = line.split('|').map(str::trim).collect();
            let path = cells.get(1)?.strip_prefix('`')?.strip_suffix('`')?;
            Some((path.to_string(), cells.get(2)?.to_string()))
        })
        .collect();
    let mut listed: Vec<String> = rows.iter().map(|(path, _)| path.clone()).collect();
    listed.sort();
    let mut present = Vec::new();
    for folder in ["tests/edge", "tests/oracle/inputs", "tests/data/bvh"] {
        for entry in std::fs::read_dir(root.join(folder)).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            if name.ends_with(".bvh") || name.ends_with(".asf") {
                present.push(format!("{folder}/{name}"));
            }
        }
    }
    present.sort();
    assert_eq!(
        listed, present,
        "the table lists every input, and only those"
    );
    let mut counts = [0; 4];
    for (path, word) in &rows {
        let (index, (english, chinese)) = WORDS
            .iter()
            .enumerate()
            .find(|(_, (english, _))| english == word)
            .unwrap_or_else(|| panic!("{path}: '{word}' is not one of the four words"));
        counts[index] += 1;
        let full = root.join(path).display().to_string();
        let en = verdict(&full, "en");
        assert!(
            en.starts_with(&format!(
                "// what the article's program does with this file: {english}"
            )),
            "{path}: the table says '{word}', --explain says\n{en}"
        );
        let zh = verdict(&full, "zh");
        assert!(
            zh.starts_with(&format!("// 原文的程式對這個檔案：{chinese}")),
            "{path}: the table says '{word}', --explain --lang zh says\n{zh}"
        );
    }
    // Every word occurs.
    assert!(counts.iter().all(|&n| n > 0), "{counts:?}");
}

/// For the flags the article's six cases do not expect, `--explain` says what it turns:
/// `Yrotation Yrotation Yrotation` gives flags 4, for which `roateSpace` has no case (nothing
/// turns, `pFrame` moves on), and `Xrotation Xrotation Yrotation` gives 1, the flags of ZYX.
#[test]
fn explain_names_the_axes_the_articles_flags_turn() {
    let control = std::fs::read_to_string(edge("article_base_crlf.bvh")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let chest = "CHANNELS 3 Zrotation Xrotation Yrotation";
    for (letters, english, chinese) in [
        (
            "Yrotation Yrotation Yrotation",
            [
                "// joint 1, Chest: MOTION columns [6]–[8]; the article's flags 4: roateSpace has no case 4, so it turns nothing here, and pFrame still moves on by 3",
                "// Yrotation: column [6]; the article does not turn this joint (its flags are 4)",
                "// what the article's program does with this file: misreads it: it does not turn 'Chest' at all, where the file turns it about Y, Y, Y",
            ],
            [
                "// 關節 1 Chest：MOTION 第 [6]–[8] 欄；原文的 flags 是 4：roateSpace 沒有 case 4，這裡不旋轉，pFrame 仍前進 3",
                "// Yrotation：第 [6] 欄；原文不轉這個關節（它的 flags 是 4）",
                "// 原文的程式對這個檔案：讀錯：它完全不轉 'Chest'，檔案要它依序繞 Y、Y、Y 軸旋轉",
            ],
        ),
        (
            "Xrotation Xrotation Yrotation",
            [
                "// joint 1, Chest: MOTION columns [6]–[8]; the article's flags 1 (zyx): it turns about Z, Y, X",
                "// Xrotation: column [6]; the article turns about Z here, by the same pFrame[0]",
                "// what the article's program does with this file: misreads it: it turns 'Chest' about Z, Y, X where the file says X, X, Y",
            ],
            [
                "// 關節 1 Chest：MOTION 第 [6]–[8] 欄；原文的 flags 是 1（zyx）：依序繞 Z、Y、X 軸旋轉",
                "// Xrotation：第 [6] 欄；原文在這裡繞 Z 軸旋轉，用的是同一個 pFrame[0]",
                "// 原文的程式對這個檔案：讀錯：它讓 'Chest' 依序繞 Z、Y、X 軸旋轉，檔案寫的是 X、X、Y",
            ],
        ),
    ] {
        let path = dir.path().join("chest.bvh");
        std::fs::write(
            &path,
            control.replace(chest, &format!("CHANNELS 3 {letters}")),
        )
        .unwrap();
        let path = path.display().to_string();
        for (lang, notes) in [("en", english), ("zh", chinese)] {
            let explained = trace(&[&path, "--frame", "1", "--explain", "--lang", lang]);
            for note in notes {
                assert!(
                    explained.contains(note),
                    "{letters} ({lang}): no\n{note}\nin\n{explained}"
                );
            }
        }
    }
}

/// The root's OFFSET is read in 5-byte steps, with one more where a step lands on a
/// space, so its numbers may be four or five characters wide (with one space between): `10.25
/// 20.50 30.75` is read as written. Six characters are not: the second step lands inside the
/// first number (y = atof("0 20.500 …") = 0), the third inside the second (z = 500), as the
/// rebuilt program prints them (`Hips : 10.250000,0.000000,500.000000`).
#[test]
fn the_articles_root_offset_takes_four_or_five_characters() {
    let control = std::fs::read_to_string(edge("article_base_crlf.bvh")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for (offset, said) in [
        ("10.25 20.50 30.75", "reads it as written"),
        ("1.25 2.50 3.75", "reads it as written"),
        (
            "10.250 20.500 30.750",
            "misreads it: it reads the OFFSET of 'Hips' as (10.25, 0, 500) where the file says (10.25, 20.5, 30.75)",
        ),
    ] {
        let path = dir.path().join("root.bvh");
        std::fs::write(
            &path,
            control.replace("OFFSET 0.00 0.00 0.00", &format!("OFFSET {offset}")),
        )
        .unwrap();
        let first = verdict(&path.display().to_string(), "en");
        assert!(
            first.starts_with(&format!(
                "// what the article's program does with this file: {said}"
            )),
            "{offset}: {first}"
        );
    }
}

/// The chapters quote the start of `bvhview trace …` and of `… --explain` as they print: each
/// code block after a line that names a `bvhview trace` command and ends in "starts:" (or "starts
/// like this:", "的開頭是：", "的開頭是這樣：") is the first lines of that command's output.
#[test]
fn the_chapters_quote_the_start_of_trace_as_it_prints() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut checked = 0;
    for chapter in ["TEACHING.md", "TEACHING.zh-Hant.md"] {
        let text = std::fs::read_to_string(root.join(chapter)).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        for (i, line) in lines.iter().enumerate() {
            let ends = [
                "starts:",
                "starts like this:",
                "的開頭是：",
                "的開頭是這樣：",
            ];
            if !ends.iter().any(|end| line.ends_with(end)) {
                continue;
            }
            let Some(command) = line
                .split('`')
                .find(|part| part.starts_with("bvhview trace "))
            else {
                continue;
            };
            // The block follows, after a blank line.
            let fence = i + 1 + usize::from(lines[i + 1].is_empty());
            assert!(lines[fence].starts_with("```"), "{chapter}:{}", fence + 1);
            let block: Vec<&str> = lines[fence + 1..]
                .iter()
                .take_while(|l| !l.starts_with("```"))
                .copied()
                .collect();
            let args: Vec<&str> = command.split_whitespace().skip(2).collect();
            let printed = trace(&args);
            let start: Vec<&str> = printed.lines().take(block.len()).collect();
            assert_eq!(block, start, "{chapter}:{}: `{command}`", i + 1);
            checked += 1;
        }
    }
    assert_eq!(checked, 4, "two quotes in each chapter");
}

/// Every verdict line the chapters quote (a code span or a line of a code block that starts
/// `// what the article's program does with this file:` or `// 原文的程式對這個檔案：`) is one
/// that `trace --explain` prints, in that language, for an input of tests/edge,
/// tests/oracle/inputs or tests/data/bvh, or for a file the chapters' exercises make: `five.bvh`
/// (Part 1), the two files of exercise 5.14 (made sparse here, Linux only) and those of 5.15. A quote that ends in
/// `…` is the start of one.
#[test]
fn the_chapters_quote_verdicts_that_explain_prints() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    let control_path = edge("article_base_crlf.bvh");
    let control = std::fs::read_to_string(&control_path).unwrap();
    let mut inputs: Vec<std::path::PathBuf> = Vec::new();
    let five = dir.path().join("five.bvh");
    std::fs::write(
        &five,
        control.replace("OFFSET 0.00 0.00 0.00", "OFFSET 10.25 20.50 30.75"),
    )
    .unwrap();
    inputs.push(five);
    // Exercise 5.15: Chest's OFFSET with a short z, then a short x.
    for (name, offset) in [
        ("z.bvh", "OFFSET 0.000000 15.000000 0\r"),
        ("x.bvh", "OFFSET 0 15.000000 0.000000\r"),
    ] {
        let path = dir.path().join(name);
        std::fs::write(
            &path,
            control.replace("OFFSET 0.000000 15.000000 0.000000\r", offset),
        )
        .unwrap();
        inputs.push(path);
    }
    #[cfg(target_os = "linux")]
    for length in [2_500_000_000u64, 4_294_967_803] {
        use std::os::unix::fs::MetadataExt;
        let big = dir.path().join(format!("big_{length}.bvh"));
        std::fs::copy(&control_path, &big).unwrap();
        let file = std::fs::OpenOptions::new().write(true).open(&big).unwrap();
        file.set_len(length).unwrap();
        if file.metadata().unwrap().blocks() * 512 > 1 << 20 {
            panic!("{}: the file system stores holes", dir.path().display());
        }
        inputs.push(big);
    }
    for folder in ["tests/edge", "tests/oracle/inputs", "tests/data/bvh"] {
        for entry in std::fs::read_dir(root.join(folder)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "bvh") {
                inputs.push(path);
            }
        }
    }
    let mut printed = Vec::new();
    for path in &inputs {
        for lang in ["en", "zh"] {
            printed.push(verdict(&path.display().to_string(), lang));
        }
    }
    let starts = [
        "// what the article's program does with this file:",
        "// 原文的程式對這個檔案：",
    ];
    let mut quoted = 0;
    for chapter in ["TEACHING.md", "TEACHING.zh-Hant.md"] {
        let text = std::fs::read_to_string(root.join(chapter)).unwrap();
        for (number, line) in text.lines().enumerate() {
            // In a code span, or a whole line of a code block.
            let mut quotes: Vec<&str> = line.split('`').skip(1).step_by(2).collect();
            quotes.push(line);
            for quote in quotes {
                if !starts.iter().any(|start| quote.starts_with(start)) {
                    continue;
                }
                let found = match quote.strip_suffix('…') {
                    Some(start) => printed.iter().any(|p| p.starts_with(start)),
                    None => printed.iter().any(|p| p == quote),
                };
                assert!(
                    found,
                    "{chapter}:{}: no input makes --explain say\n{quote}",
                    number + 1
                );
                quoted += 1;
            }
        }
    }
    assert!(quoted >= 20, "{quoted} quotes");
}
