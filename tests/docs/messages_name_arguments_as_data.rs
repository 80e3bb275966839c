//! The library's messages name the caller's arguments as data (`Message::argument`), never as
//! the command line's flags: outside `src/cli/` no code line writes `--name`. Each front end
//! spells an argument its own way (`--max-size 8G`, Python's `max_size=8G`); a flag written
//! into a library message would reach Python users as a flag they cannot pass.

use std::path::{Path, PathBuf};

fn rust_files(folder: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(folder).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The line without a trailing `//` comment (one outside a string: an even count of quotes
/// before it).
fn code_of(line: &str) -> &str {
    let mut from = 0;
    while let Some(at) = line[from..].find("//") {
        let cut = from + at;
        if line[..cut].matches('"').count().is_multiple_of(2) {
            return &line[..cut];
        }
        from = cut + 2;
    }
    line
}

/// Where `code` writes a flag: `--` then a lower-case letter.
fn writes_a_flag(code: &str) -> bool {
    code.match_indices("--")
        .any(|(at, _)| code[at + 2..].starts_with(|c: char| c.is_ascii_lowercase()))
}

#[test]
fn no_library_message_writes_a_command_line_flag() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    let cli = root.join("src/cli");
    let mut found = Vec::new();
    for file in files.iter().filter(|f| !f.starts_with(&cli)) {
        if file.ends_with("src/main.rs") {
            continue;
        }
        let text = std::fs::read_to_string(file).unwrap();
        for (number, line) in text.lines().enumerate() {
            // A file's own tests may run the command line.
            if line.trim_start().starts_with("#[cfg(test)]") {
                break;
            }
            let code = code_of(line);
            // Cargo's flag, in the message of a build without a feature.
            if code.trim_start().starts_with("//") || code.contains("build it with `--features") {
                continue;
            }
            if writes_a_flag(code) {
                let shown = file.strip_prefix(root).unwrap().display();
                found.push(format!("{shown}:{}: {}", number + 1, line.trim()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "flags in library code:\n{}",
        found.join("\n")
    );
    // The check sees what it looks for.
    assert!(writes_a_flag(code_of(
        r#"format!("more than --max-size {n}")"#
    )));
    assert!(!writes_a_flag(code_of(
        r#"let x = 1; // `--max-size` in a comment"#
    )));
}
