//! The Traditional Chinese chapter, TEACHING.zh-Hant.md, is written as Taiwan's graphics texts
//! are, in its prose (code blocks, inline code and the article's own words in the term table
//! are left alone):
//! - OpenCC's `s2twp` conversion (Simplified to Traditional, Taiwan standard, with Taiwan's
//!   phrases) changes nothing but the few known cases in [`ALLOWED`];
//! - commas, colons and semicolons between Chinese characters are full-width, and so are
//!   parentheses around Chinese text;
//! - the mainland words the chapter once used, and that OpenCC leaves as they are, stay out.
//!
//! Needs the `opencc` command (Debian's `opencc` package, which reads its configurations from
//! /usr/share/opencc; `scripts/test.sh` installs it). Without it this test fails and says so.
//! `BVHVIEW_TEACHING_ZH=FILE cargo test --test article teaching_zh` checks another copy, e.g. an older one
//! from `git show`.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};

/// Stands for what the checks skip (a code span, the article's word in the term table), so that
/// punctuation beside it is still seen.
const HIDDEN: char = '\u{FFFC}';

/// Changes `s2twp` makes that the chapter keeps, as (the chapter's text, what OpenCC makes of it).
/// Both the chapter and OpenCC's output are compared with each second text read as the first.
const ALLOWED: &[(&str, &str)] = &[
    // "pixel": 像素 is the word of Taiwan's graphics texts; OpenCC's Taiwan phrase list turns it
    // into 畫素, the word of camera specifications.
    ("像素", "畫素"),
    // OpenCC's own misconversion: the Taiwan phrase 算法 → 演算法 also fires inside 演算法, which
    // becomes 演演算法 (BYVoid/OpenCC issue 950).
    ("演算法", "演演算法"),
    // OpenCC's own misconversion: the particle 了 after a verb such as 說明 or 學習 is read as
    // part of 明了 or 了解 and becomes 瞭 (BYVoid/OpenCC issue 1497).
    ("了", "瞭"),
];

/// Mainland words that `s2twp` leaves alone, with the word the chapter uses instead. They may
/// appear only inside 「」, where the chapter quotes the article as it is written.
const AVOIDED: &[(&str, &str)] = &[
    ("幀", "影格"),
    ("節點", "關節 (a BVH joint)"),
    ("棧", "堆疊, 推入, 彈出"),
    ("當前", "目前"),
    ("遍曆", "走訪 or 遍歷 (遍曆 is the article's misspelling)"),
    ("替身", "虛設常式 (a stub)"),
    (
        "驅動程式",
        "主程式 (a small main program, not a device driver)",
    ),
    ("黃金測試", "參考圖片, 參考輸出"),
    // Not a mainland word: Taiwan's word for a camera's pixels. The chapter says 像素 (see
    // ALLOWED), one word throughout.
    ("畫素", "像素"),
];

fn chapter() -> (String, String) {
    let path = match std::env::var_os("BVHVIEW_TEACHING_ZH") {
        Some(path) => PathBuf::from(path),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("TEACHING.zh-Hant.md"),
    };
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    (path.display().to_string(), text)
}

/// The chapter's prose, line for line: fenced code blocks become empty lines, each inline code
/// span becomes one [`HIDDEN`] (and the line breaks inside it), and in the term table (the table
/// whose header starts `| 原文的用詞 |`) each row's first cell, the article's word as the article
/// writes it, becomes one [`HIDDEN`].
fn prose(markdown: &str) -> Vec<String> {
    // Fenced blocks first: their lines are dropped, and a backtick inside them opens no span.
    let mut outside = String::with_capacity(markdown.len());
    let mut fence: Option<(char, usize)> = None;
    for line in markdown.lines() {
        let trimmed = line.trim_start();
        let marker = trimmed.chars().next().filter(|c| *c == '`' || *c == '~');
        let run = marker.map_or(0, |c| trimmed.chars().take_while(|x| *x == c).count());
        match fence {
            Some((c, length)) => {
                if marker == Some(c) && run >= length && trimmed[run..].trim().is_empty() {
                    fence = None;
                }
            }
            None if run >= 3 => fence = Some((marker.unwrap(), run)),
            None => outside.push_str(line),
        }
        outside.push('\n');
    }
    // Code spans: a run of n backticks up to the next run of exactly n, across line breaks.
    let chars: Vec<char> = outside.chars().collect();
    let run_at = |i: usize| chars[i..].iter().take_while(|c| **c == '`').count();
    let mut text = String::with_capacity(outside.len());
    let mut i = 0;
    while i < chars.len() {
        if chars[i] != '`' {
            text.push(chars[i]);
            i += 1;
            continue;
        }
        let opening = run_at(i);
        let mut j = i + opening;
        let mut close = None;
        while j < chars.len() {
            if chars[j] == '`' {
                let run = run_at(j);
                if run == opening {
                    close = Some(j);
                    break;
                }
                j += run;
            } else {
                j += 1;
            }
        }
        match close {
            Some(j) => {
                text.push(HIDDEN);
                text.extend(chars[i..j].iter().filter(|c| **c == '\n'));
                i = j + opening;
            }
            None => {
                text.extend(&chars[i..i + opening]);
                i += opening;
            }
        }
    }
    let mut term_table = false;
    text.lines()
        .map(|line| {
            if line.starts_with("| 原文的用詞 |") {
                term_table = true;
            } else if !line.starts_with('|') {
                term_table = false;
            }
            match line.split_once('|').map(|(_, rest)| rest.split_once('|')) {
                Some(Some((_, rest))) if term_table => format!("|{HIDDEN}|{rest}"),
                _ => line.to_string(),
            }
        })
        .collect()
}

fn is_han(c: char) -> bool {
    matches!(c, '\u{3400}'..='\u{4DBF}' | '\u{4E00}'..='\u{9FFF}' | '\u{F900}'..='\u{FAFF}')
}

/// Runs OpenCC's `s2twp` over `text`; panics with what to install when the command is missing.
fn s2twp(text: &str) -> String {
    let mut child = Command::new("opencc")
        .args(["-c", "s2twp.json"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| {
            panic!(
                "cannot run the opencc command ({e}). This test checks TEACHING.zh-Hant.md with \
                 OpenCC's s2twp conversion: install Debian's opencc package \
                 (apt-get install opencc; scripts/test.sh installs it)"
            )
        });
    let mut stdin = child.stdin.take().unwrap();
    let input = text.to_string();
    let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()));
    let output = child.wait_with_output().unwrap();
    writer.join().unwrap().unwrap();
    assert!(
        output.status.success(),
        "opencc -c s2twp.json failed ({}): {}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    let converted = String::from_utf8(output.stdout).unwrap();
    match converted.strip_suffix('\n') {
        Some(trimmed) if !text.ends_with('\n') => trimmed.to_string(),
        _ => converted,
    }
}

/// The part of `before` that differs from `after`, and what it became, with a little context.
fn change(before: &str, after: &str) -> String {
    let (b, a): (Vec<char>, Vec<char>) = (before.chars().collect(), after.chars().collect());
    let start = b.iter().zip(&a).take_while(|(x, y)| x == y).count();
    let end = b[start..]
        .iter()
        .rev()
        .zip(a[start..].iter().rev())
        .take_while(|(x, y)| x == y)
        .count();
    let from = start.saturating_sub(4);
    let piece =
        |s: &[char], stop: usize| s[from..(stop + 4).min(s.len())].iter().collect::<String>();
    format!(
        "…{}… → …{}…",
        piece(&b, b.len() - end),
        piece(&a, a.len() - end)
    )
}

#[test]
fn opencc_s2twp_changes_nothing_but_the_allowed_cases() {
    let (name, text) = chapter();
    let lines = prose(&text);
    let converted = s2twp(&lines.join("\n"));
    let converted: Vec<&str> = converted.split('\n').collect();
    assert_eq!(
        converted.len(),
        lines.len(),
        "opencc changed the number of lines"
    );
    let allow = |line: &str| {
        ALLOWED.iter().fold(line.to_string(), |s, (ours, theirs)| {
            s.replace(theirs, ours)
        })
    };
    let changes: Vec<String> = lines
        .iter()
        .zip(&converted)
        .enumerate()
        .filter(|(_, (ours, theirs))| allow(ours) != allow(theirs))
        .map(|(i, (ours, theirs))| format!("{name}:{}: {}", i + 1, change(ours, theirs)))
        .collect();
    assert!(
        changes.is_empty(),
        "OpenCC's s2twp (Taiwan standard and phrases) would change {} lines of the chapter's \
         prose; use the Taiwan word, or if OpenCC is wrong, add the case to ALLOWED with why:\n{}",
        changes.len(),
        changes.join("\n")
    );
}

#[test]
fn punctuation_between_chinese_characters_is_full_width() {
    let (name, text) = chapter();
    let mut found = Vec::new();
    let side = |c: char| is_han(c) || c == HIDDEN;
    for (number, line) in prose(&text).iter().enumerate() {
        let chars: Vec<char> = line.chars().collect();
        // A comma, colon or semicolon with Chinese on one side and Chinese or code on the other,
        // spaces between allowed.
        for (i, c) in chars.iter().enumerate() {
            if !matches!(c, ',' | ':' | ';') {
                continue;
            }
            let before = chars[..i].iter().rev().find(|c| **c != ' ');
            let after = chars[i + 1..].iter().find(|c| **c != ' ');
            if let (Some(&b), Some(&a)) = (before, after)
                && side(b)
                && side(a)
                && (is_han(b) || is_han(a))
            {
                let from = i.saturating_sub(6);
                let context: String = chars[from..(i + 7).min(chars.len())].iter().collect();
                found.push(format!("{name}:{}: ASCII {c:?} in …{context}…", number + 1));
            }
        }
        // ASCII parentheses around Chinese text (a link's target is not text).
        let mut i = 0;
        while i < chars.len() {
            if chars[i] == '(' {
                let link = i > 0 && chars[i - 1] == ']';
                if let Some(length) = chars[i..].iter().position(|c| *c == ')') {
                    let inside = &chars[i + 1..i + length];
                    if !link && inside.iter().any(|c| is_han(*c)) {
                        let context: String = chars[i..=i + length].iter().take(30).collect();
                        found.push(format!(
                            "{name}:{}: ASCII parentheses around {context}",
                            number + 1
                        ));
                    }
                    i += length;
                }
            }
            i += 1;
        }
    }
    assert!(
        found.is_empty(),
        "Chinese prose takes full-width punctuation (，：；（）):\n{}",
        found.join("\n")
    );
}

#[test]
fn mainland_words_appear_only_in_quotations_of_the_article() {
    let (name, text) = chapter();
    let mut found = Vec::new();
    for (number, line) in prose(&text).iter().enumerate() {
        // What stands inside 「」 is quoted as written.
        let mut unquoted = String::new();
        let mut depth = 0usize;
        for c in line.chars() {
            match c {
                '「' => depth += 1,
                '」' => depth = depth.saturating_sub(1),
                _ if depth == 0 => unquoted.push(c),
                _ => {}
            }
        }
        for (word, instead) in AVOIDED {
            if unquoted.contains(word) {
                found.push(format!("{name}:{}: {word} (write {instead})", number + 1));
            }
        }
    }
    assert!(
        found.is_empty(),
        "mainland words in the prose:\n{}",
        found.join("\n")
    );
}

#[test]
fn prose_hides_code_and_the_articles_words_only() {
    let lines = prose(
        "a `b` c ``d ` e`` f `g\nh` i\n```sh\n幀, 節點\n```\n~~~~\n```\n~~~~\n\
         | 原文的用詞 | 本章用詞 |\n|---|---|\n| 幀 | 影格 |\n\n| 幀 | x |\n",
    );
    let hidden = HIDDEN;
    assert_eq!(
        lines,
        [
            format!("a {hidden} c {hidden} f {hidden}"),
            " i".to_string(),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
            format!("|{hidden}| 本章用詞 |"),
            format!("|{hidden}|---|"),
            format!("|{hidden}| 影格 |"),
            String::new(),
            "| 幀 | x |".to_string(),
        ]
    );
}

/// `bvhview trace --explain --lang zh`, which the chapter quotes in Part 5 and Part 6, writes its
/// notes in the same register: OpenCC's s2twp changes none of them (but the ALLOWED cases), and
/// none holds a mainland word of [`AVOIDED`]. Run on every input of tests/edge and
/// tests/oracle/inputs, and on the two files of exercise 1.3, so that every kind of note (each
/// verdict the inputs reach, flags 0 and 4, another axis, the article's root translation) is
/// seen.
#[test]
fn explain_writes_its_chinese_notes_in_taiwans_register() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    let control = std::fs::read_to_string(root.join("tests/edge/article_base_crlf.bvh")).unwrap();
    let mut inputs = Vec::new();
    for letters in [
        "Yrotation Yrotation Yrotation",
        "Xrotation Xrotation Yrotation",
    ] {
        let path = dir.path().join(format!("{}.bvh", &letters[..1]));
        let text = control.replace(
            "CHANNELS 3 Zrotation Xrotation Yrotation",
            &format!("CHANNELS 3 {letters}"),
        );
        std::fs::write(&path, text).unwrap();
        inputs.push(path);
    }
    for folder in ["tests/edge", "tests/oracle/inputs"] {
        for entry in std::fs::read_dir(root.join(folder)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "bvh") {
                inputs.push(path);
            }
        }
    }
    let mut notes = std::collections::BTreeSet::new();
    for path in &inputs {
        let out = crate::common::bvhview_command()
            .args([
                "trace",
                path.to_str().unwrap(),
                "--frame",
                "0",
                "--explain",
                "--lang",
                "zh",
            ])
            .output()
            .unwrap();
        for line in String::from_utf8(out.stdout).unwrap().lines() {
            if let Some((_, note)) = line.split_once("// ") {
                notes.insert(note.to_string());
            }
        }
    }
    assert!(notes.len() > 100, "{} notes", notes.len());
    let notes: Vec<String> = notes.into_iter().collect();
    let converted = s2twp(&notes.join("\n"));
    let allow = |line: &str| {
        ALLOWED.iter().fold(line.to_string(), |s, (ours, theirs)| {
            s.replace(theirs, ours)
        })
    };
    let changes: Vec<String> = notes
        .iter()
        .zip(converted.split('\n'))
        .filter(|(ours, theirs)| allow(ours) != allow(theirs))
        .map(|(ours, theirs)| change(ours, theirs))
        .collect();
    assert!(
        changes.is_empty(),
        "s2twp would change:\n{}",
        changes.join("\n")
    );
    for (word, instead) in AVOIDED {
        for note in &notes {
            assert!(
                !note.contains(word),
                "'{word}' (write {instead}) in: {note}"
            );
        }
    }
}
