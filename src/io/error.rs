//! Errors of every loader and command: where in which file, what was expected, what was found.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// What went wrong, and where: a broken file says its `file:line:column`.
///
/// ```
/// use bvhview::{Error, Take};
///
/// let folder = tempfile::tempdir().unwrap();
/// let path = folder.path().join("broken.bvh");
/// std::fs::write(&path, "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 x\n").unwrap();
/// match Take::open(&path) {
///     Err(Error::Parse { line, column, .. }) => assert_eq!((line, column), (4, 14)),
///     other => panic!("expected a parse error, got {other:?}"),
/// }
/// ```
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The input is malformed: `path:line:column: message`.
    Parse {
        /// The input's name: its path, or the name given to bytes in memory.
        path: String,
        /// The line, from 1.
        line: usize,
        /// The column, from 1.
        column: usize,
        /// What was expected and what was found.
        message: String,
    },
    /// An input file could not be read.
    Io {
        /// The file.
        path: PathBuf,
        /// Why the system could not read it.
        source: io::Error,
    },
    /// An output file could not be written.
    Output {
        /// The file.
        path: PathBuf,
        /// Why the system could not write it.
        source: io::Error,
    },
    /// An argument the caller gave is outside what it may be: its name as the library spells it
    /// (`frame_time`, `fps`, `size`), the value as given, and what is expected. Each front end
    /// names the argument its own way: the command line `--frame-time 0: …`, Python
    /// `frame_time=0: …`; [`fmt::Display`] writes `frame_time 0: …`.
    InvalidArgument {
        /// The argument's name, in snake case.
        name: &'static str,
        /// Its value as the caller gave it.
        value: String,
        /// What it may be.
        expected: String,
    },
    /// The input needs a part this build was made without (a format behind a cargo feature).
    Unsupported {
        /// The input's name.
        input: String,
        /// What it is (`FBX`, `glTF`, `MP4 video`).
        what: &'static str,
        /// The cargo feature that brings it.
        feature: &'static str,
    },
    /// Anything else the user asked for that cannot be done (a frame out of range, a bad option).
    Usage(String),
    /// The machine lacks something (a display, a library): not the input's fault.
    Environment(String),
    /// More memory than the machine gives was asked for (Python's `MemoryError`).
    Memory(String),
}

impl Error {
    /// [`Error::Io`]: `path` could not be read.
    pub fn io(path: &Path, source: io::Error) -> Error {
        Error::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// [`Error::Output`]: `path` could not be written.
    pub fn output(path: &Path, source: io::Error) -> Error {
        Error::Output {
            path: path.to_path_buf(),
            source,
        }
    }

    /// Whether the caller's input or request is at fault (a broken file, a missing input, a bad
    /// argument, a format this build lacks), rather than the machine (a display, memory, a
    /// disk that refuses a write). The command line exits 2 for the first, 1 for the second.
    pub fn is_the_callers(&self) -> bool {
        match self {
            Error::Parse { .. }
            | Error::Usage(_)
            | Error::InvalidArgument { .. }
            | Error::Unsupported { .. } => true,
            Error::Environment(_) | Error::Memory(_) | Error::Output { .. } => false,
            // A missing or unreadable input is the caller's input; the rest is the machine's.
            Error::Io { source, .. } => matches!(
                source.kind(),
                io::ErrorKind::NotFound
                    | io::ErrorKind::IsADirectory
                    | io::ErrorKind::InvalidData
                    | io::ErrorKind::FileTooLarge
            ),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Parse {
                path,
                line,
                column,
                message,
            } => write!(f, "{path}:{line}:{column}: {message}"),
            Error::Io { path, source } => match source.kind() {
                io::ErrorKind::NotFound => write!(f, "{}: no such file", path.display()),
                io::ErrorKind::PermissionDenied => {
                    write!(f, "{}: permission denied (cannot read it)", path.display())
                }
                _ => write!(f, "{}: {}", path.display(), io_message(source)),
            },
            Error::Output { path, source } => {
                let folder = path.parent().filter(|p| !p.as_os_str().is_empty());
                match (source.kind(), folder) {
                    // The folder is there, but nothing can be made in it (/proc answers a new
                    // name with "no such file"): said as such, not as a missing folder.
                    (io::ErrorKind::NotFound, Some(folder)) if folder.is_dir() => write!(
                        f,
                        "cannot write {}: nothing can be created in {} (the system says: {})",
                        path.display(),
                        folder.display(),
                        io_message(source)
                    ),
                    (io::ErrorKind::NotFound, Some(folder)) => write!(
                        f,
                        "cannot write {}: the folder {} does not exist",
                        path.display(),
                        folder.display()
                    ),
                    (io::ErrorKind::PermissionDenied, _) => {
                        write!(f, "cannot write {}: permission denied", path.display())
                    }
                    _ => write!(f, "cannot write {}: {}", path.display(), io_message(source)),
                }
            }
            Error::InvalidArgument {
                name,
                value,
                expected,
            } => write!(f, "{name} {value}: {expected}"),
            Error::Unsupported {
                input,
                what,
                feature,
            } => write!(
                f,
                "{input}: this bvhview was built without {what} (cargo feature `{feature}`); \
                 build it with `--features {feature}`"
            ),
            Error::Usage(message) | Error::Environment(message) | Error::Memory(message) => {
                f.write_str(message)
            }
        }
    }
}

/// The OS's message without Rust's "(os error N)" suffix, begun in lower case as the rest of
/// bvhview's messages are ("File name too long" → "file name too long").
fn io_message(error: &io::Error) -> String {
    let text = error.to_string();
    let text = match text.find(" (os error") {
        Some(cut) => &text[..cut],
        None => &text,
    };
    let mut chars = text.chars();
    match (chars.next(), chars.next()) {
        (Some(first), Some(second))
            if first.is_ascii_uppercase() && second.is_ascii_lowercase() =>
        {
            format!("{}{}", first.to_ascii_lowercase(), &text[1..])
        }
        _ => text.to_string(),
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } | Error::Output { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// A count with its noun, singular for 1 (`1 frame`, `0 frames`, `2 frames`); every noun counted
/// in messages takes a plain `s`.
pub fn counted(count: impl fmt::Display, noun: &str) -> String {
    let count = count.to_string();
    let plural = if count == "1" { "" } else { "s" };
    format!("{count} {noun}{plural}")
}

/// Most characters of user-supplied text (a name, a key) a message echoes.
pub const ECHO_CHARS: usize = 64;

/// `text` as a message echoes a name or key: quoted, with Rust's escapes (a newline in it
/// does not break the message's one line), and past [`ECHO_CHARS`] characters cut, with its
/// length said (a 10 MB name is damage; echoed whole it buries the message).
pub fn quoted(text: &str) -> String {
    match text.char_indices().nth(ECHO_CHARS) {
        None => format!("{text:?}"),
        Some((cut, _)) => format!("{:?}… ({} bytes)", &text[..cut], text.len()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_echo_is_one_line_and_cut_past_its_length() {
        assert_eq!(quoted("Left\nArm"), r#""Left\nArm""#);
        assert_eq!(quoted(&"é".repeat(64)), format!("{:?}", "é".repeat(64)));
        assert_eq!(
            quoted(&"é".repeat(5_000_000)),
            format!("{:?}… (10000000 bytes)", "é".repeat(64))
        );
    }
}
