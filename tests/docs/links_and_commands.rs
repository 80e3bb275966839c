//! The documentation holds what it says.
//!
//! - Every relative link (`[text](path)`, `![alt](path)`) in README.md, docs/*.md, CHANGELOG.md,
//!   TEACHING.md and TEACHING.zh-Hant.md leads to a file or folder of the repository that exists.
//!   An anchor into README.md, CHANGELOG.md or docs/*.md must name one of its headings; anchors
//!   into the chapters are left out.
//! - Every `bvhview …` command in a ```sh, ```bash or ```console block of README.md and
//!   docs/*.md runs with the binary just built and succeeds, except the failures listed in
//!   [`EXPECTED_FAILURES`] and the window commands (see [`opens_window`]), each with its reason.
//!   `cargo run --release [-- ARGS]` counts as `bvhview ARGS`. Lines continued with `\` are joined.
//!
//! The commands run from the repository's root, so that their input paths resolve, with every
//! output (`-o PATH`, `--output PATH`) moved into a temporary folder; a later command that reads
//! an earlier one's output reads it there. Nothing is written into the repository: each output
//! path the docs name is checked to be as it was. The commands run without DISPLAY and
//! WAYLAND_DISPLAY, so that a window never opens. In a console block, the lines after a
//! `$ command` are its output, compared with what it prints (stdout, then stderr, the temporary
//! folder taken out of the paths). A command that reads `../shared` is skipped, and said so,
//! when that path is absent.
//!
//! The signs point right:
//! - The code map, docs/GUIDE.md's "Where the code is", names every folder under `src/`, and
//!   every path it names exists (read as [`code_map_paths`] says).
//! - Every `src/…`, `tests/…`, `docs/…` and `scripts/…` path written in README.md, TEACHING.md,
//!   TEACHING.zh-Hant.md, docs/*.md or a comment under `src/` exists; `*` and `…` stand for any
//!   run of characters within one name, and at least one file must fit.
//! - Nothing outside `tests/` points at an issue, a decision or an article by a number, or at
//!   DESIGN.md or STYLE.md, which a reader of the repository cannot open: the reason is said in
//!   place.
// Helpers of the tests a build without every feature leaves out.
#![cfg_attr(
    not(all(feature = "window", feature = "fbx", feature = "gltf")),
    allow(dead_code, unused_imports)
)]

use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant, SystemTime};

const BVHVIEW: &str = env!("CARGO_BIN_EXE_bvhview");

/// How long one command may take before it counts as hung.
const TIMEOUT: Duration = Duration::from_secs(60);

/// Commands the docs show failing on purpose: the command as written (words joined by one
/// space), its exit code, a piece of what it prints, and why it fails. Each must appear in the
/// docs, so the list cannot go stale.
const EXPECTED_FAILURES: &[(&str, i32, &str, &str)] = &[
    (
        "bvhview snapshto",
        2,
        "did you mean `bvhview snapshot`?",
        "a mistyped command is bad input; the message names the command meant",
    ),
    (
        "bvhview info tests/data/bvh_malformed/dali_test-invalid-hierarchy1.bvh",
        2,
        ":3:3: expected '{' after 'root', found 'OFFSET'",
        "a malformed file is bad input, reported with its line and column",
    ),
    (
        "bvhview diff a.png b.png",
        1,
        "1440 of 360000 pixels differ",
        "diff exits 1 when the pictures differ",
    ),
];

/// What a window command prints and its exit code, here where no display is set.
const NO_DISPLAY: &str = "no display to open a window on";

/// The subcommands; any other first word is a file for the window.
const SUBCOMMANDS: &[&str] = &[
    "print",
    "info",
    "positions",
    "snapshot",
    "trace",
    "diff",
    "skin-demo",
    "convert",
    "dataset",
    "retarget",
    "solve",
    "metrics",
    "generate",
    "help",
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// docs/*.md, in name order.
fn docs_folder() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = fs::read_dir(root().join("docs"))
        .expect("docs/ is there")
        .map(|entry| entry.expect("docs/ can be listed").path())
        .filter(|path| path.extension().is_some_and(|ext| ext == "md"))
        .collect();
    files.sort();
    files
}

/// The files whose links must resolve.
fn linked_docs() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = [
        "README.md",
        "CHANGELOG.md",
        "TEACHING.md",
        "TEACHING.zh-Hant.md",
    ]
    .iter()
    .map(|name| root().join(name))
    .collect();
    files.extend(docs_folder());
    files
}

/// The files whose commands must run.
fn command_docs() -> Vec<PathBuf> {
    let mut files = vec![root().join("README.md")];
    files.extend(docs_folder());
    files
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The line without its code spans (`…`, ``…``), which hold no links.
fn without_code_spans(line: &str) -> String {
    let mut prose = String::new();
    let mut rest = line;
    while let Some(start) = rest.find('`') {
        prose.push_str(&rest[..start]);
        let run = rest[start..].len() - rest[start..].trim_start_matches('`').len();
        let fence = &rest[start..start + run];
        let after = &rest[start + run..];
        match after.find(fence) {
            Some(end) => rest = &after[end + run..],
            None => {
                rest = after;
            }
        }
    }
    prose.push_str(rest);
    prose
}

/// The targets of `[text](target)` and `![alt](target)` outside code, with their line numbers.
fn links(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    let mut in_fence = false;
    for (index, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
            continue;
        }
        if in_fence {
            continue;
        }
        let prose = without_code_spans(line);
        let mut rest = prose.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            // The target ends at the parenthesis that closes it.
            let mut depth = 0usize;
            let mut end = None;
            for (i, c) in after.char_indices() {
                match c {
                    '(' => depth += 1,
                    ')' if depth == 0 => {
                        end = Some(i);
                        break;
                    }
                    ')' => depth -= 1,
                    _ => {}
                }
            }
            let Some(end) = end else { break };
            // A title ("…") may follow the target; <…> may wrap it.
            let target = after[..end].split_whitespace().next().unwrap_or("");
            let target = target.trim_start_matches('<').trim_end_matches('>');
            found.push((index + 1, target.to_string()));
            rest = &after[end + 1..];
        }
    }
    found
}

/// `%20` and the like, as a browser reads a link.
fn percent_decoded(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        if bytes[i] == b'%'
            && i + 2 < bytes.len()
            && let (Some(high), Some(low)) = (hex(bytes[i + 1]), hex(bytes[i + 2]))
        {
            out.push((high * 16 + low) as u8);
            i += 3;
            continue;
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The anchors GitHub gives a file's headings: lower case, letters, digits, `-` and `_` kept,
/// spaces made `-`, the rest dropped; a repeated heading gets `-1`, `-2`, ….
fn anchors(text: &str) -> Vec<String> {
    let mut found: Vec<String> = Vec::new();
    let mut in_fence = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
            continue;
        }
        let Some(heading) = line.strip_prefix('#') else {
            continue;
        };
        if in_fence {
            continue;
        }
        let heading = heading.trim_start_matches('#');
        if !heading.starts_with(' ') {
            continue;
        }
        let slug: String = heading
            .trim()
            .to_lowercase()
            .chars()
            .filter_map(|c| match c {
                ' ' => Some('-'),
                c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                _ => None,
            })
            .collect();
        let repeats = found
            .iter()
            .filter(|a| {
                **a == slug
                    || a.strip_prefix(&format!("{slug}-"))
                        .is_some_and(|n| n.parse::<u32>().is_ok())
            })
            .count();
        found.push(if repeats == 0 {
            slug
        } else {
            format!("{slug}-{repeats}")
        });
    }
    found
}

/// Whether a link's anchor is checked: links into the README, the changelog and docs/ (the
/// chapters' own anchors are theirs to keep).
fn anchors_checked(file: &Path, repository: &Path) -> bool {
    let Ok(relative) = file.strip_prefix(repository) else {
        return false;
    };
    let relative = relative.to_string_lossy();
    relative == "README.md"
        || relative == "CHANGELOG.md"
        || (relative.starts_with("docs/") && relative.ends_with(".md"))
}

#[test]
fn every_relative_link_leads_to_a_file() {
    let repository = root().canonicalize().expect("the repository's root");
    let mut checked = 0;
    let mut anchors_seen = 0;
    let mut broken = Vec::new();
    for doc in linked_docs() {
        let text = read(&doc);
        let name = doc
            .strip_prefix(root())
            .unwrap_or(&doc)
            .display()
            .to_string();
        for (line, target) in links(&text) {
            let lower = target.to_ascii_lowercase();
            if target.is_empty()
                || lower.starts_with("http://")
                || lower.starts_with("https://")
                || lower.starts_with("mailto:")
            {
                continue;
            }
            let (path, anchor) = match target.split_once('#') {
                Some((path, anchor)) => (path, Some(anchor)),
                None => (target.as_str(), None),
            };
            let path = path.split('?').next().unwrap_or("");
            if path.starts_with('/') {
                broken.push(format!("{name}:{line}: {target}: not a relative link"));
                continue;
            }
            let file = if path.is_empty() {
                doc.canonicalize().expect("the doc itself")
            } else {
                checked += 1;
                let resolved = doc.parent().expect("a folder").join(percent_decoded(path));
                match resolved.canonicalize() {
                    Ok(found) if found.starts_with(&repository) => found,
                    Ok(_) => {
                        broken.push(format!("{name}:{line}: {target}: outside the repository"));
                        continue;
                    }
                    Err(_) => {
                        broken.push(format!("{name}:{line}: {target}: no such file"));
                        continue;
                    }
                }
            };
            if let Some(anchor) = anchor
                && anchors_checked(&file, &repository)
            {
                anchors_seen += 1;
                if !anchors(&read(&file)).contains(&percent_decoded(anchor)) {
                    broken.push(format!(
                        "{name}:{line}: {target}: no heading makes #{anchor}"
                    ));
                }
            }
        }
    }
    println!("docs: {checked} relative links and {anchors_seen} anchors checked");
    assert!(
        checked > 20,
        "only {checked} relative links found: is the parser right?"
    );
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

/// One command found in a doc's code block.
#[derive(Debug, PartialEq)]
struct DocCommand {
    /// Where it is: `docs/GUIDE.md:120`.
    place: String,
    /// The command as written, continuation lines joined, without its `$ ` prompt.
    text: String,
    /// In a console block, the lines shown after it.
    output: Option<Vec<String>>,
}

/// The commands of every sh, bash, shell or console block, in order.
fn commands(name: &str, text: &str) -> Vec<DocCommand> {
    let mut found: Vec<DocCommand> = Vec::new();
    let mut block: Option<bool> = None; // Some(is_console) inside a shell block
    let mut in_other_block = false;
    let mut pending: Option<(usize, String)> = None; // a command continued with `\`
    for (index, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if let Some(info) = line.strip_prefix("```") {
            if block.is_some() || in_other_block {
                block = None;
                in_other_block = false;
                pending = None;
            } else {
                match info.split_whitespace().next().unwrap_or("") {
                    "sh" | "bash" | "shell" => block = Some(false),
                    "console" => block = Some(true),
                    _ => in_other_block = true,
                }
            }
            continue;
        }
        let Some(console) = block else { continue };
        let (start, piece) = match pending.take() {
            Some((start, so_far)) => (start, format!("{so_far} {line}")),
            None if console => match line.strip_prefix("$ ") {
                Some(command) => (index + 1, command.to_string()),
                None => {
                    if let Some(last) = found.last_mut() {
                        last.output
                            .get_or_insert_with(Vec::new)
                            .push(raw.trim_end().to_string());
                    }
                    continue;
                }
            },
            None => (index + 1, line.to_string()),
        };
        if let Some(head) = piece.strip_suffix('\\') {
            pending = Some((start, head.trim_end().to_string()));
            continue;
        }
        let piece = piece.trim().to_string();
        if piece.is_empty() || piece.starts_with('#') {
            continue;
        }
        found.push(DocCommand {
            place: format!("{name}:{start}"),
            text: piece,
            output: console.then(Vec::new),
        });
    }
    found
}

/// The words the shell would make of a plain command line: quotes and backslashes as the shell
/// reads them, a `#` starting a word begins a comment. Anything else the shell would act on
/// (pipes, redirections, globs, variables) is refused: the docs' commands stay plain.
fn words(line: &str) -> Result<Vec<String>, String> {
    let mut words = Vec::new();
    let mut word = String::new();
    let mut in_word = false;
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        match c {
            ' ' | '\t' => {
                if in_word {
                    words.push(std::mem::take(&mut word));
                    in_word = false;
                }
            }
            '#' if !in_word => break,
            '\'' => {
                in_word = true;
                loop {
                    match chars.next() {
                        Some('\'') => break,
                        Some(c) => word.push(c),
                        None => return Err("a ' left open".into()),
                    }
                }
            }
            '"' => {
                in_word = true;
                loop {
                    match chars.next() {
                        Some('"') => break,
                        Some('\\') => match chars.next() {
                            Some(c @ ('"' | '\\' | '$' | '`')) => word.push(c),
                            Some(c) => {
                                word.push('\\');
                                word.push(c);
                            }
                            None => return Err("a \" left open".into()),
                        },
                        Some(c @ ('$' | '`')) => {
                            return Err(format!("'{c}' inside double quotes"));
                        }
                        Some(c) => word.push(c),
                        None => return Err("a \" left open".into()),
                    }
                }
            }
            '\\' => {
                in_word = true;
                match chars.next() {
                    Some(c) => word.push(c),
                    None => return Err("a \\ at the end".into()),
                }
            }
            '|' | '&' | ';' | '<' | '>' | '(' | ')' | '$' | '`' | '*' | '?' | '[' | '{' => {
                return Err(format!("the shell would act on '{c}'"));
            }
            '~' if !in_word => return Err("the shell would act on '~'".into()),
            c => {
                in_word = true;
                word.push(c);
            }
        }
    }
    if in_word {
        words.push(word);
    }
    Ok(words)
}

/// bvhview's arguments when the line runs bvhview: `bvhview ARGS`, `cargo run --release` (the
/// window) or `cargo run --release -- ARGS`. None for any other program.
fn bvhview_args(words: &[String]) -> Option<Vec<String>> {
    let words: Vec<&str> = words.iter().map(String::as_str).collect();
    match words.as_slice() {
        ["bvhview", args @ ..] => Some(args.iter().map(|s| s.to_string()).collect()),
        ["cargo", "run", "--release"] => Some(Vec::new()),
        ["cargo", "run", "--release", "--", args @ ..] => {
            Some(args.iter().map(|s| s.to_string()).collect())
        }
        _ => None,
    }
}

/// Whether a line is meant to run bvhview, judged from its first words alone (for a line the
/// shell lexer refused).
fn looks_like_bvhview(line: &str) -> bool {
    let first: Vec<&str> = line.split_whitespace().take(4).collect();
    matches!(
        first.as_slice(),
        ["bvhview", ..] | ["cargo", "run", "--release"] | ["cargo", "run", "--release", "--"]
    )
}

/// Whether bvhview would open a window: no subcommand (the viewer), or `skin-demo` without an
/// output. Here, without a display, such a command exits 1 with [`NO_DISPLAY`]: that is the
/// documented answer on a machine without one.
fn opens_window(args: &[String]) -> bool {
    let writes = args
        .iter()
        .any(|a| a == "-o" || a == "--output" || a.starts_with("--output="));
    match args.first().map(String::as_str) {
        Some("skin-demo") => !writes,
        Some(first) if SUBCOMMANDS.contains(&first) => false,
        _ => !args
            .iter()
            .any(|a| matches!(a.as_str(), "-h" | "--help" | "-V" | "--version")),
    }
}

/// Where an output the docs name is written instead: under `temp`, at the same relative path.
/// Devices (`/dev/stdout`) stay as they are.
fn moved_output(path: &str, temp: &Path) -> Option<String> {
    if path.starts_with("/dev/") || path == "-" {
        return None;
    }
    let relative = path.trim_start_matches('/');
    let relative = relative.trim_start_matches("../");
    let moved = format!("{}/{relative}", temp.display());
    let parent = Path::new(moved.trim_end_matches('/'))
        .parent()
        .expect("under the temporary folder")
        .to_path_buf();
    fs::create_dir_all(&parent).expect("a folder for the output");
    Some(moved)
}

/// The arguments with every output moved under `temp` and every earlier output read from
/// there; also the output paths as the docs name them.
fn rewritten(
    args: &[String],
    temp: &Path,
    earlier: &mut HashMap<String, String>,
) -> (Vec<String>, Vec<String>) {
    let mut out = Vec::with_capacity(args.len());
    let mut named = Vec::new();
    let mut next_is_output = false;
    for arg in args {
        if next_is_output {
            next_is_output = false;
            named.push(arg.clone());
            match moved_output(arg, temp) {
                Some(moved) => {
                    earlier.insert(arg.clone(), moved.clone());
                    out.push(moved);
                }
                None => out.push(arg.clone()),
            }
        } else if arg == "-o" || arg == "--output" {
            next_is_output = true;
            out.push(arg.clone());
        } else if let Some(path) = arg.strip_prefix("--output=") {
            named.push(path.to_string());
            match moved_output(path, temp) {
                Some(moved) => {
                    earlier.insert(path.to_string(), moved.clone());
                    out.push(format!("--output={moved}"));
                }
                None => out.push(arg.clone()),
            }
        } else if let Some(moved) = earlier.get(arg) {
            out.push(moved.clone());
        } else {
            out.push(arg.clone());
        }
    }
    (out, named)
}

/// What a file in the repository looks like, to tell that nothing wrote it.
fn state(path: &Path) -> Option<(u64, Option<SystemTime>)> {
    fs::metadata(path)
        .ok()
        .map(|meta| (meta.len(), meta.modified().ok()))
}

struct Outcome {
    code: Option<i32>,
    printed: String,
}

/// Runs bvhview from the repository's root with no display; stdout then stderr.
fn run(args: &[String], temp: &Path, place: &str) -> Result<Outcome, String> {
    let stdout_path = temp.join(".stdout");
    let stderr_path = temp.join(".stderr");
    let stdout = fs::File::create(&stdout_path).expect("a file for stdout");
    let stderr = fs::File::create(&stderr_path).expect("a file for stderr");
    let mut child = Command::new(BVHVIEW)
        .args(args)
        .current_dir(root())
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(stderr)
        .spawn()
        .map_err(|e| format!("{place}: cannot start {BVHVIEW}: {e}"))?;
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("the command's status") {
            break status;
        }
        if started.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("{place}: still running after {TIMEOUT:?}: killed"));
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let mut printed = fs::read_to_string(&stdout_path).unwrap_or_default();
    printed.push_str(&fs::read_to_string(&stderr_path).unwrap_or_default());
    let _ = fs::remove_file(&stdout_path);
    let _ = fs::remove_file(&stderr_path);
    Ok(Outcome {
        code: status.code(),
        printed,
    })
}

/// Lines without trailing blanks, trailing empty lines dropped.
fn tidy<'a>(lines: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut lines: Vec<String> = lines.map(|l| l.trim_end().to_string()).collect();
    while lines.last().is_some_and(|l| l.is_empty()) {
        lines.pop();
    }
    lines
}

/// What running one doc's commands gave.
#[derive(Default)]
struct Report {
    ran: usize,
    skipped: Vec<String>,
    failures: Vec<String>,
    expected_seen: Vec<&'static str>,
}

fn run_doc(doc: &Path) -> Report {
    let name = doc
        .strip_prefix(root())
        .unwrap_or(doc)
        .display()
        .to_string();
    let temp = tempfile::tempdir().expect("a temporary folder");
    let mut earlier = HashMap::new();
    let mut report = Report::default();
    for command in commands(&name, &read(doc)) {
        let place = &command.place;
        let words = match words(&command.text) {
            Ok(words) => words,
            Err(why) => {
                if looks_like_bvhview(&command.text) {
                    report
                        .failures
                        .push(format!("{place}: `{}`: {why}", command.text));
                }
                continue;
            }
        };
        let Some(args) = bvhview_args(&words) else {
            continue;
        };
        if let Some(missing) = args
            .iter()
            .find(|a| a.starts_with("../shared/") && !root().join(a).exists())
        {
            report.skipped.push(format!(
                "{place}: `{}` skipped: {missing} is absent (../shared/data is not beside the checkout)",
                command.text
            ));
            continue;
        }
        let (args, outputs) = rewritten(&args, temp.path(), &mut earlier);
        let before: Vec<_> = outputs.iter().map(|o| state(&root().join(o))).collect();
        let outcome = match run(&args, temp.path(), place) {
            Ok(outcome) => outcome,
            Err(why) => {
                report.failures.push(why);
                continue;
            }
        };
        report.ran += 1;
        for (output, was) in outputs.iter().zip(&before) {
            if state(&root().join(output)) != *was {
                report.failures.push(format!(
                    "{place}: `{}` wrote {output} in the repository",
                    command.text
                ));
            }
        }
        let printed = outcome
            .printed
            .replace(&format!("{}/", temp.path().display()), "");
        let as_written = words.join(" ");
        let (code, needle, why) = if let Some(&(text, code, needle, why)) = EXPECTED_FAILURES
            .iter()
            .find(|(text, ..)| *text == as_written)
        {
            report.expected_seen.push(text);
            (code, needle, why)
        } else if opens_window(&args) {
            (
                1,
                NO_DISPLAY,
                "a window needs a display, and none is set here",
            )
        } else {
            (0, "", "")
        };
        if outcome.code != Some(code) {
            report.failures.push(format!(
                "{place}: `{}` exited {:?}, expected {code}{}{}:\n{printed}",
                command.text,
                outcome.code,
                if why.is_empty() { "" } else { ": " },
                why
            ));
            continue;
        }
        if !printed.contains(needle) {
            report.failures.push(format!(
                "{place}: `{}` did not print `{needle}`:\n{printed}",
                command.text
            ));
        }
        if let Some(shown) = &command.output {
            let shown = tidy(shown.iter().map(String::as_str));
            let actual = tidy(printed.lines());
            if shown != actual {
                report.failures.push(format!(
                    "{place}: `{}` printed\n{}\nwhere the doc shows\n{}",
                    command.text,
                    actual.join("\n"),
                    shown.join("\n")
                ));
            }
        }
    }
    println!("{name}: {} bvhview commands ran", report.ran);
    report
}

#[cfg(all(feature = "window", feature = "fbx", feature = "gltf"))]
#[test]
fn every_command_in_the_docs_runs() {
    let docs = command_docs();
    assert!(
        docs.len() >= 5,
        "README.md and docs/*.md: found only {docs:?}"
    );
    let reports: Vec<Report> = std::thread::scope(|scope| {
        let handles: Vec<_> = docs
            .iter()
            .map(|doc| scope.spawn(move || run_doc(doc)))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a doc's commands ran"))
            .collect()
    });
    let ran: usize = reports.iter().map(|r| r.ran).sum();
    let mut failures = Vec::new();
    for report in &reports {
        for skipped in &report.skipped {
            println!("{skipped}");
        }
        failures.extend(report.failures.iter().cloned());
    }
    for (text, ..) in EXPECTED_FAILURES {
        if !reports.iter().any(|r| r.expected_seen.contains(text)) {
            failures.push(format!(
                "EXPECTED_FAILURES lists `{text}`, which no doc runs any more"
            ));
        }
    }
    println!("docs: {ran} bvhview commands ran");
    assert!(ran > 20, "only {ran} commands found: is the parser right?");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn the_parser_joins_lines_and_moves_outputs() {
    let doc = "text\n\n```sh\nbvhview snapshot a.bvh \\\n    --frame 2 -o out/x.png   # a comment\n# only a comment\ncargo build\n```\n\n```console\n$ bvhview diff out/x.png 'b c.png'\n3 of 9 pixels differ\n```\n\n```text\nbvhview not run\n```\n";
    let found = commands("t.md", doc);
    assert_eq!(
        found,
        vec![
            DocCommand {
                place: "t.md:4".into(),
                text: "bvhview snapshot a.bvh --frame 2 -o out/x.png   # a comment".into(),
                output: None,
            },
            DocCommand {
                place: "t.md:7".into(),
                text: "cargo build".into(),
                output: None,
            },
            DocCommand {
                place: "t.md:11".into(),
                text: "bvhview diff out/x.png 'b c.png'".into(),
                output: Some(vec!["3 of 9 pixels differ".into()]),
            },
        ]
    );
    let first = words(&found[0].text).unwrap();
    assert_eq!(
        first,
        [
            "bvhview",
            "snapshot",
            "a.bvh",
            "--frame",
            "2",
            "-o",
            "out/x.png"
        ]
    );
    assert_eq!(bvhview_args(&words(&found[1].text).unwrap()), None);
    let temp = tempfile::tempdir().unwrap();
    let mut earlier = HashMap::new();
    let (args, named) = rewritten(&bvhview_args(&first).unwrap(), temp.path(), &mut earlier);
    let moved = format!("{}/out/x.png", temp.path().display());
    assert_eq!(args[5], moved);
    assert_eq!(named, ["out/x.png"]);
    assert!(temp.path().join("out").is_dir());
    let third = bvhview_args(&words(&found[2].text).unwrap()).unwrap();
    let (args, named) = rewritten(&third, temp.path(), &mut earlier);
    assert_eq!(args, ["diff", moved.as_str(), "b c.png"]);
    assert!(named.is_empty());
    assert!(words("bvhview info x.bvh | head").is_err());
    assert!(looks_like_bvhview("bvhview info *.bvh"));
    assert!(!looks_like_bvhview(
        "cargo run --release --example precision -- *.bvh"
    ));
    assert!(opens_window(&[]));
    assert!(opens_window(&["skin-demo".to_string()]));
    assert!(!opens_window(&["--help".to_string()]));
    assert_eq!(
        anchors("# A b\n## ASF/AMC (the CMU set)\n```\n# not\n```\n### A b\n#nope\n"),
        ["a-b", "asfamc-the-cmu-set", "a-b-1"]
    );
    assert_eq!(
        links("[a](docs/A.md#x) `[b](no.md)` ![c](p.png \"t\")\n```\n[d](no.md)\n```\n"),
        [(1, "docs/A.md#x".to_string()), (1, "p.png".to_string())]
    );
}

/// Every Rust block of the two chapters is the repository's code, line for line (indentation
/// aside): `load_file`'s body and `draw_recursive` as TEACHING.md shows them beside the article's
/// `loadFile` and `drawRecursive`. So "the article's statements, in its order", and what else
/// `draw_recursive` holds (its two `gl.note` calls), are what the code says.
#[test]
fn the_chapters_rust_blocks_are_the_code() {
    let mut sources = Vec::new();
    let mut stack = vec![root().join("src")];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let lines: Vec<String> = read(&path)
                    .lines()
                    .map(|l| l.trim().to_string())
                    .filter(|l| !l.is_empty())
                    .collect();
                sources.push((path, lines));
            }
        }
    }
    let mut blocks = 0;
    for chapter in ["TEACHING.md", "TEACHING.zh-Hant.md"] {
        let text = read(&root().join(chapter));
        let mut lines = text.lines().enumerate();
        while let Some((at, line)) = lines.next() {
            // `ignore`: the excerpts are parts of src/, not programs; rustdoc reads the
            // chapters as the `teaching` modules' docs and would run them.
            if line != "```rust,ignore" {
                continue;
            }
            let block: Vec<String> = lines
                .by_ref()
                .map(|(_, l)| l)
                .take_while(|l| *l != "```")
                .map(|l| l.trim().to_string())
                .filter(|l| !l.is_empty())
                .collect();
            let found = sources.iter().any(|(_, code)| {
                code.windows(block.len())
                    .any(|window| window == block.as_slice())
            });
            assert!(
                found,
                "{chapter}:{}: this Rust block is not in src/ as it stands:\n{}",
                at + 1,
                block.join("\n")
            );
            blocks += 1;
        }
    }
    assert_eq!(
        blocks, 4,
        "load_file's body and draw_recursive, in each chapter"
    );
}

/// The folders a path may start from, read from the repository's root wherever it is written.
const ROOT_FOLDERS: &[&str] = &[
    "src/",
    "tests/",
    "docs/",
    "scripts/",
    "assets/",
    "python/",
    "examples/",
    "bench/",
    "fuzz/",
];

/// The folders whose paths [`every_path_the_docs_and_comments_write_exists`] checks.
const CHECKED_FOLDERS: &[&str] = &["src/", "tests/", "docs/", "scripts/"];

/// Every file under `folder`, in name order; hidden folders, build outputs and Python's caches
/// left out.
fn files_under(folder: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![folder.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.expect("a folder's entry").path();
            let name = path.file_name().unwrap_or_default().to_string_lossy();
            if path.is_dir() {
                if !name.starts_with('.') && name != "target" && name != "__pycache__" {
                    stack.push(path);
                }
            } else {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The section "Where the code is" of docs/GUIDE.md, with the line number of its heading.
fn code_map_section() -> (usize, Vec<String>) {
    let guide = read(&root().join("docs/GUIDE.md"));
    let lines: Vec<&str> = guide.lines().collect();
    let start = lines
        .iter()
        .position(|l| *l == "## Where the code is")
        .expect("GUIDE.md has a section \"## Where the code is\"");
    let section = lines[start + 1..]
        .iter()
        .take_while(|l| !l.starts_with("## ") && !l.starts_with("# "))
        .map(|l| l.to_string())
        .collect();
    (start + 1, section)
}

/// Whether a code span is a path: no blanks, only the characters of file names, and a folder
/// (`x/`), a Rust file (`x.rs`) or anything under one of [`ROOT_FOLDERS`].
fn is_path_span(span: &str) -> bool {
    !span.is_empty()
        && span
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '/' | '-'))
        && (span.ends_with('/')
            || span.ends_with(".rs")
            || ROOT_FOLDERS.iter().any(|f| span.starts_with(f)))
}

/// The paths a code map names, read as the map's reader reads them: each bullet (`- `, at any
/// depth) that opens with a path names the folder the bullet is about (a file's own folder for a
/// file), taken inside its parent bullet's folder; the bullet's other paths are inside that folder,
/// except those starting with one of [`ROOT_FOLDERS`], which start from the repository's root.
/// Outside the bullets every path starts from the root. Gives each path as written, as resolved
/// (relative to the root), and the line it is on.
fn code_map_paths(first_line: usize, section: &[String]) -> Vec<(usize, String, String)> {
    // The bullets with their continuation lines joined, so that a code span may wrap.
    let mut blocks: Vec<(usize, Option<usize>, String)> = Vec::new(); // line, indent, text
    for (index, line) in section.iter().enumerate() {
        let indent = line.len() - line.trim_start().len();
        let trimmed = line.trim_start();
        if trimmed.is_empty() {
            continue;
        }
        if let Some(rest) = trimmed.strip_prefix("- ") {
            blocks.push((first_line + index + 1, Some(indent), rest.to_string()));
        } else if indent > 0
            && let Some((_, Some(_), text)) = blocks.last_mut()
        {
            text.push(' ');
            text.push_str(trimmed);
        } else if let Some((_, None, text)) = blocks.last_mut() {
            text.push(' ');
            text.push_str(trimmed);
        } else {
            blocks.push((first_line + index + 1, None, trimmed.to_string()));
        }
    }
    let mut found = Vec::new();
    let mut open: Vec<(usize, String)> = Vec::new(); // indent, folder
    for (line, indent, text) in blocks {
        let parent = match indent {
            Some(indent) => {
                while open.last().is_some_and(|(i, _)| *i >= indent) {
                    open.pop();
                }
                open.last().map(|(_, f)| f.clone()).unwrap_or_default()
            }
            None => {
                open.clear();
                String::new()
            }
        };
        let resolve = |folder: &str, span: &str| {
            if ROOT_FOLDERS.iter().any(|f| span.starts_with(f)) {
                span.to_string()
            } else {
                format!("{folder}{span}")
            }
        };
        let spans: Vec<&str> = text
            .split('`')
            .skip(1)
            .step_by(2)
            .filter(|s| is_path_span(s))
            .collect();
        let mut folder = parent.clone();
        if let (Some(indent), Some(first)) = (indent, spans.first()) {
            let path = resolve(&parent, first);
            folder = match path.rfind('/') {
                Some(at) => path[..=at].to_string(),
                None => String::new(),
            };
            open.push((indent, folder.clone()));
        }
        for (index, span) in spans.into_iter().enumerate() {
            // The path a bullet opens with is inside its parent's folder.
            let inside = if index == 0 && indent.is_some() {
                &parent
            } else {
                &folder
            };
            found.push((line, span.to_string(), resolve(inside, span)));
        }
    }
    found
}

#[test]
fn the_code_map_names_every_src_folder_and_every_path_it_names_exists() {
    let (first_line, section) = code_map_section();
    let paths = code_map_paths(first_line, &section);
    let mut wrong = Vec::new();
    for (line, written, path) in &paths {
        if !root().join(path).exists() {
            wrong.push(format!(
                "docs/GUIDE.md:{line}: `{written}` ({path}) does not exist"
            ));
        }
    }
    let named: Vec<&str> = paths
        .iter()
        .map(|(_, _, path)| path.as_str())
        .filter(|p| p.ends_with('/'))
        .collect();
    let mut folders = std::collections::BTreeSet::new();
    for file in files_under(&root().join("src")) {
        let mut folder = file.parent().expect("a file's folder");
        while folder != root().join("src") {
            let relative = folder.strip_prefix(root()).expect("under the root");
            folders.insert(format!("{}/", relative.display()));
            folder = folder.parent().expect("inside src/");
        }
    }
    for folder in &folders {
        if !named.contains(&folder.as_str()) {
            wrong.push(format!(
                "docs/GUIDE.md, \"Where the code is\": the folder `{folder}` is not named"
            ));
        }
    }
    let folders = folders.len();
    println!(
        "code map: {} paths named, {} of them folders; {folders} folders under src/",
        paths.len(),
        named.len()
    );
    assert!(
        paths.len() > 100 && folders > 20,
        "only {} paths in the code map and {folders} folders under src/: is the parser right?",
        paths.len()
    );
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Whether `name` fits `pattern`, where `*` and `…` stand for any run of characters.
fn fits(pattern: &str, name: &str) -> bool {
    let pattern = pattern.replace('…', "*");
    let mut pieces = pattern.split('*');
    let first = pieces.next().unwrap_or("");
    let Some(mut rest) = name.strip_prefix(first) else {
        return false;
    };
    let pieces: Vec<&str> = pieces.collect();
    for (i, piece) in pieces.iter().enumerate() {
        if i + 1 == pieces.len() {
            return rest.len() >= piece.len() && rest.ends_with(piece);
        }
        match rest.find(piece) {
            Some(at) => rest = &rest[at + piece.len()..],
            None => return false,
        }
    }
    rest.is_empty()
}

/// Whether a path written in the docs names something that exists: as written, or, where it
/// holds `*` or `…` (any run of characters within one name), at least one file or folder that
/// fits it.
fn path_exists(repository: &Path, path: &str) -> bool {
    if repository.join(path).exists() {
        return true;
    }
    if !path.contains(['*', '…']) {
        return false;
    }
    let mut candidates = vec![repository.to_path_buf()];
    for name in path.split('/').filter(|n| !n.is_empty()) {
        let mut next = Vec::new();
        for candidate in &candidates {
            if name.contains(['*', '…']) {
                let Ok(entries) = fs::read_dir(candidate) else {
                    continue;
                };
                for entry in entries.flatten() {
                    if fits(name, &entry.file_name().to_string_lossy()) {
                        next.push(entry.path());
                    }
                }
            } else if candidate.join(name).exists() {
                next.push(candidate.join(name));
            }
        }
        candidates = next;
    }
    !candidates.is_empty()
}

/// The paths under [`CHECKED_FOLDERS`] a text writes, in or out of code: each starts where no
/// character of a path (`python/tests/…` is not `tests/…`) comes before it, runs over the
/// characters of file names, `*` and `…`, and loses the full stop or comma of its sentence.
fn written_paths(text: &str) -> Vec<String> {
    let is_path_char =
        |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '/' | '-' | '*' | '…');
    let mut found = Vec::new();
    for (at, _) in text.char_indices() {
        let rest = &text[at..];
        if !CHECKED_FOLDERS.iter().any(|f| rest.starts_with(f))
            || text[..at].chars().next_back().is_some_and(is_path_char)
        {
            continue;
        }
        let end = rest.find(|c: char| !is_path_char(c)).unwrap_or(rest.len());
        let path = rest[..end].trim_end_matches(['.', ',']);
        found.push(path.to_string());
    }
    found
}

/// The comments of a Rust file: whole lines of `//`, `///` and `//!`, and what follows ` // ` on
/// a line of code.
fn comments(source: &str) -> Vec<(usize, &str)> {
    source
        .lines()
        .enumerate()
        .filter_map(|(index, line)| {
            let trimmed = line.trim_start();
            if trimmed.starts_with("//") {
                Some((index + 1, trimmed))
            } else {
                line.split_once(" // ")
                    .map(|(_, comment)| (index + 1, comment))
            }
        })
        .collect()
}

#[test]
fn every_path_the_docs_and_comments_write_exists() {
    let repository = root();
    let mut texts: Vec<(String, usize, String)> = Vec::new(); // file, line, text
    let mut docs = vec![
        root().join("README.md"),
        root().join("TEACHING.md"),
        root().join("TEACHING.zh-Hant.md"),
    ];
    docs.extend(docs_folder());
    for doc in docs {
        let name = doc
            .strip_prefix(root())
            .unwrap_or(&doc)
            .display()
            .to_string();
        for (index, line) in read(&doc).lines().enumerate() {
            texts.push((name.clone(), index + 1, line.to_string()));
        }
    }
    for file in files_under(&root().join("src")) {
        if file.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let name = file
            .strip_prefix(root())
            .unwrap_or(&file)
            .display()
            .to_string();
        for (line, comment) in comments(&read(&file)) {
            texts.push((name.clone(), line, comment.to_string()));
        }
    }
    let mut checked = 0;
    let mut wrong = Vec::new();
    for (file, line, text) in &texts {
        for path in written_paths(text) {
            checked += 1;
            if !path_exists(&repository, &path) {
                wrong.push(format!("{file}:{line}: {path} does not exist"));
            }
        }
    }
    println!("docs and comments: {checked} paths checked");
    assert!(
        checked > 300,
        "only {checked} paths found: is the parser right?"
    );
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The places a text points at an issue or decision by number ("issue 44", "Issue #12",
/// "decision 14"), at DESIGN.md or STYLE.md, or at an article by its seed number ("seed 001"):
/// things a reader of the repository cannot open.
fn references_outside(text: &str) -> Vec<String> {
    let lower = text.to_ascii_lowercase();
    let bytes = lower.as_bytes();
    let mut found = Vec::new();
    for (word, numbered) in [
        ("issue", true),
        ("decision", true),
        ("seed", true),
        ("design.md", false),
        ("style.md", false),
    ] {
        for (at, _) in lower.match_indices(word) {
            if at > 0 && bytes[at - 1].is_ascii_alphanumeric() {
                continue;
            }
            let mut end = at + word.len();
            if numbered {
                if bytes.get(end) == Some(&b's') && word != "seed" {
                    end += 1;
                }
                if bytes.get(end) == Some(&b' ') {
                    end += 1;
                } else if word == "seed" {
                    continue; // `xsens_seed002` is a file's name
                }
                if bytes.get(end) == Some(&b'#') {
                    end += 1;
                }
                if !bytes.get(end).is_some_and(u8::is_ascii_digit) {
                    continue;
                }
                while bytes.get(end).is_some_and(u8::is_ascii_digit) {
                    end += 1;
                }
            }
            found.push(text[at..end].to_string());
        }
    }
    found
}

#[test]
fn no_issue_decision_or_seed_number_outside_the_tests() {
    let mut files: Vec<PathBuf> = [
        "README.md",
        "TEACHING.md",
        "TEACHING.zh-Hant.md",
        "CHANGELOG.md",
        "python/README.md",
    ]
    .iter()
    .map(|name| root().join(name))
    .collect();
    for folder in [
        "src",
        "docs",
        "scripts",
        "bench",
        "examples",
        "fuzz/src",
        "python/src",
        "python/bvhview",
    ] {
        files.extend(files_under(&root().join(folder)));
    }
    let mut read_files = 0;
    let mut wrong = Vec::new();
    for file in &files {
        let bytes = fs::read(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let Ok(text) = String::from_utf8(bytes) else {
            continue; // a picture
        };
        read_files += 1;
        let name = file
            .strip_prefix(root())
            .unwrap_or(file)
            .display()
            .to_string();
        for (index, line) in text.lines().enumerate() {
            for reference in references_outside(line) {
                wrong.push(format!("{name}:{}: {reference}", index + 1));
            }
        }
    }
    println!("{read_files} files read for issue, decision and seed numbers");
    assert!(read_files > 150, "only {read_files} files read");
    assert!(
        wrong.is_empty(),
        "say the reason in place of a number nobody outside can look up:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn the_sign_checks_read_paths_as_a_reader_would() {
    let map = [
        "Intro `scripts/import_graph.py`, `cargo doc --open`.",
        "",
        "- `src/lib.rs` and `take.rs`; `tests/docs.rs`.",
        "- `src/model/` is the model: `local =",
        "  T(t)`, `skeleton.rs`.",
        "  - `pose/` (`mod.rs`, `lanes.rs`)",
        "",
        "  - `body/sides/` `tests.rs`",
        "- `src/io/` `limits.rs`",
    ]
    .map(String::from);
    let resolved: Vec<(usize, String)> = code_map_paths(10, &map)
        .into_iter()
        .map(|(line, _, path)| (line, path))
        .collect();
    let expected = [
        (11, "scripts/import_graph.py"),
        (13, "src/lib.rs"),
        (13, "src/take.rs"),
        (13, "tests/docs.rs"),
        (14, "src/model/"),
        (14, "src/model/skeleton.rs"),
        (16, "src/model/pose/"),
        (16, "src/model/pose/mod.rs"),
        (16, "src/model/pose/lanes.rs"),
        (18, "src/model/body/sides/"),
        (18, "src/model/body/sides/tests.rs"),
        (19, "src/io/"),
        (19, "src/io/limits.rs"),
    ]
    .map(|(line, path)| (line, path.to_string()));
    assert_eq!(resolved, expected);
    assert_eq!(
        written_paths("see src/io/limits.rs, python/tests/x.py and `tests/data/bvh/*.bvh`."),
        ["src/io/limits.rs", "tests/data/bvh/*.bvh"]
    );
    assert!(path_exists(&root(), "tests/data/bvh/*.bvh"));
    assert!(path_exists(&root(), "src/…"));
    assert!(!path_exists(&root(), "src/retarget/fast.rs"));
    assert!(!path_exists(&root(), "tests/data/bvh/*.nothing"));
    assert_eq!(
        comments("//! a\nlet x = 1; // b\nlet url = \"https://x\";\n"),
        [(1, "//! a"), (2, "b")]
    );
    assert_eq!(
        references_outside(
            "Issue 44, issue #12, issues 45–49, decision 14, DESIGN.md, seed 001, xsens_seed002, tissue 3, the issue"
        ),
        [
            "Issue 44",
            "issue #12",
            "issues 45",
            "decision 14",
            "seed 001",
            "DESIGN.md"
        ]
    );
}
