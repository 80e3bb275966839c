//! Errors of every loader and command: where in which file, what was expected, what was found.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use crate::io::message::{Argument, Message, RustSpelling, Spelling};

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
    /// The input's content is malformed or cannot be used, where no line and column say
    /// where: a binary FBX or glTF, an `.npy`, a mesh's skin, a dataset folder. A caller going
    /// through many files skips this one; nothing it asked for was wrong.
    Decoding {
        /// The input's name: its path, or the name given to bytes in memory.
        input: String,
        /// What is wrong with it.
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
    /// (`frame_time`, `fps`, `size`), the value as given (empty when the message shows none),
    /// and what is expected. Each front end names the argument its own way ([`Error::spelled`]):
    /// the command line `--frame-time 0: …`, Python `frame_time=0: …`; [`fmt::Display`] writes
    /// `frame_time 0: …`.
    InvalidArgument {
        /// The argument's name, in snake case.
        name: &'static str,
        /// Its value as the caller gave it, or empty.
        value: String,
        /// What it may be (it may name other arguments).
        expected: Message,
    },
    /// More of something than bvhview reads or makes: what was counted, the most allowed, and
    /// how many there were (or would be). The message says it in words, with the argument
    /// that raises the limit where one does (`max_size`).
    Limit {
        /// What was counted (`bytes`, `values`, `frames`, `mesh items`).
        what: &'static str,
        /// The most allowed.
        limit: u64,
        /// How many there were, or would be.
        found: u64,
        /// The whole message.
        message: Message,
    },
    /// The input's name ends in an extension of no format bvhview reads.
    UnknownFormat {
        /// The input's name.
        input: String,
        /// Its extension as written (empty when it has none).
        extension: String,
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
    /// Anything else the caller asked for that cannot be done (a skeleton that cannot take a
    /// motion, a file whose content is unusable); the message may name the caller's arguments.
    Usage(Message),
    /// The machine lacks something (a display, a library): not the input's fault.
    Environment(String),
    /// More memory than the machine gives was asked for (Python's `MemoryError`).
    Memory(String),
}

impl Error {
    /// [`Error::Io`]: `path` could not be read; a read held to `max_size` that went past it
    /// (the reader's own `PastMaxSize`) is the [`Error::Limit`] it is.
    pub fn io(path: &Path, source: io::Error) -> Error {
        let past = source
            .get_ref()
            .and_then(|inner| inner.downcast_ref::<PastMaxSize>());
        if let Some(&PastMaxSize { max_size }) = past {
            return Error::Limit {
                what: "bytes",
                limit: max_size,
                found: max_size.saturating_add(1),
                message: Message::from(format!("{}: more than ", path.display()))
                    .argument("max_size", Some(&max_size.to_string()))
                    .text(" bytes"),
            };
        }
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
            | Error::Decoding { .. }
            | Error::Usage(_)
            | Error::InvalidArgument { .. }
            | Error::Limit { .. }
            | Error::UnknownFormat { .. }
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

impl Error {
    /// [`Error::Decoding`]: `input`'s content is wrong, as `message` says.
    pub fn decoding(input: impl fmt::Display, message: impl fmt::Display) -> Error {
        Error::Decoding {
            input: input.to_string(),
            message: message.to_string(),
        }
    }

    /// [`Error::Usage`] of `message`.
    pub fn usage(message: impl Into<Message>) -> Error {
        Error::Usage(message.into())
    }

    /// The error said of `subject` (`walk.npy: …`): a message of its own keeps its arguments
    /// and its kind; an argument's error becomes a usage error that still names it.
    pub fn about(self, subject: &str) -> Error {
        let before = format!("{subject}: ");
        match self {
            Error::Usage(message) => Error::Usage(message.after(&before)),
            Error::Limit {
                what,
                limit,
                found,
                message,
            } => Error::Limit {
                what,
                limit,
                found,
                message: message.after(&before),
            },
            Error::InvalidArgument {
                name,
                value,
                expected,
            } => Error::Usage(
                Message::from(before)
                    .argument(name, (!value.is_empty()).then_some(value.as_str()))
                    .text(": ")
                    .then(expected),
            ),
            Error::Memory(text) => Error::Memory(format!("{before}{text}")),
            Error::Environment(text) => Error::Environment(format!("{before}{text}")),
            other => Error::Usage(Message::from(format!("{before}{other}"))),
        }
    }

    /// [`Error::Limit`]: `found` of `what` (`values`, `frames`), more than `limit`, said by
    /// `message`.
    pub fn limit(what: &'static str, limit: u64, found: u64, message: impl Into<Message>) -> Error {
        Error::Limit {
            what,
            limit,
            found,
            message: message.into(),
        }
    }

    /// [`Error::Limit`] of an input of `size` bytes, more than `max_size` allows.
    pub fn too_big(input: &str, size: u64, max_size: u64) -> Error {
        Error::Limit {
            what: "bytes",
            limit: max_size,
            found: size,
            message: Message::from(format!("{input}: {size} bytes, more than "))
                .argument("max_size", Some(&max_size.to_string())),
        }
    }

    /// [`Error::InvalidArgument`]: the argument `name` (snake case) given as `value` is not
    /// what is `expected`.
    pub fn invalid(
        name: &'static str,
        value: impl Into<String>,
        expected: impl Into<Message>,
    ) -> Error {
        Error::InvalidArgument {
            name,
            value: value.into(),
            expected: expected.into(),
        }
    }

    /// The message with each argument of the caller's it names spelled by `spelling` (what
    /// [`fmt::Display`] writes is [`RustSpelling`]'s).
    ///
    /// ```
    /// use bvhview::{Argument, Error, Spelling};
    ///
    /// #[derive(Debug)]
    /// struct Python;
    /// impl Spelling for Python {
    ///     fn argument(&self, argument: &Argument) -> String {
    ///         match &argument.value {
    ///             Some(value) => format!("{}={value}", argument.name),
    ///             None => argument.name.to_string(),
    ///         }
    ///     }
    ///     fn opening(&self, file: &str, with: &Argument) -> String {
    ///         format!("bvhview.load({file:?}, {}=…)", with.name)
    ///     }
    /// }
    ///
    /// let error = bvhview::limits::fps(0.0, false).unwrap_err();
    /// assert_eq!(
    ///     error.spelled(&Python),
    ///     "fps=0: expected frames per second from 0.01 to 1000"
    /// );
    /// assert_eq!(error.to_string(), "fps 0: expected frames per second from 0.01 to 1000");
    /// ```
    pub fn spelled(&self, spelling: &dyn Spelling) -> String {
        match self {
            Error::InvalidArgument {
                name,
                value,
                expected,
            } => {
                let argument = Argument {
                    name,
                    value: (!value.is_empty()).then(|| value.clone()),
                };
                format!(
                    "{}: {}",
                    spelling.argument(&argument),
                    expected.spelled(spelling)
                )
            }
            Error::Limit { message, .. } | Error::Usage(message) => message.spelled(spelling),
            Error::UnknownFormat { input, extension } => format!(
                "{input}: unknown extension '{extension}': bvhview reads .bvh, .fbx, .gltf, \
                 .glb and AMASS .npz files and .asf skeletons (with {})",
                spelling.argument(&Argument {
                    name: "motion",
                    value: Some(".amc".into())
                })
            ),
            Error::Parse {
                path,
                line,
                column,
                message,
            } => format!("{path}:{line}:{column}: {message}"),
            Error::Decoding { input, message } => format!("{input}: {message}"),
            Error::Io { path, source } => match source.kind() {
                io::ErrorKind::NotFound => format!("{}: no such file", path.display()),
                io::ErrorKind::PermissionDenied => {
                    format!("{}: permission denied (cannot read it)", path.display())
                }
                _ => format!("{}: {}", path.display(), io_message(source)),
            },
            Error::Output { path, source } => {
                let folder = path.parent().filter(|p| !p.as_os_str().is_empty());
                match (source.kind(), folder) {
                    // The folder is there, but nothing can be made in it (/proc answers a new
                    // name with "no such file"): said as such, not as a missing folder.
                    (io::ErrorKind::NotFound, Some(folder)) if folder.is_dir() => format!(
                        "cannot write {}: nothing can be created in {} (the system says: {})",
                        path.display(),
                        folder.display(),
                        io_message(source)
                    ),
                    (io::ErrorKind::NotFound, Some(folder)) => format!(
                        "cannot write {}: the folder {} does not exist",
                        path.display(),
                        folder.display()
                    ),
                    (io::ErrorKind::PermissionDenied, _) => {
                        format!("cannot write {}: permission denied", path.display())
                    }
                    _ => format!("cannot write {}: {}", path.display(), io_message(source)),
                }
            }
            Error::Unsupported {
                input,
                what,
                feature,
            } => format!(
                "{input}: this bvhview was built without {what} (cargo feature `{feature}`); \
                 build it with `--features {feature}`"
            ),
            Error::Environment(message) | Error::Memory(message) => message.clone(),
        }
    }
}

/// What a read held to `max_size` bytes fails with past it, as the source of an
/// [`io::ErrorKind::FileTooLarge`] error: [`Error::io`] turns it into an [`Error::Limit`] naming
/// the `max_size` argument (`found` is then "at least one byte more").
#[derive(Debug)]
pub(crate) struct PastMaxSize {
    /// The `max_size` the read was held to.
    pub max_size: u64,
}

impl fmt::Display for PastMaxSize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "more than max_size {} bytes", self.max_size)
    }
}

impl std::error::Error for PastMaxSize {}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.spelled(&RustSpelling))
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
