//! A message that may name the caller's arguments. The library says which argument (`max_size`,
//! `take`), as data; each front end spells it its own way: the command line `--max-size 8G`,
//! Python `max_size=8G`, Rust (what [`fmt::Display`] writes) `max_size 8G`.

use std::fmt;

/// One of the caller's arguments as a message names it: its name in snake case, as the library
/// spells it, and the value given or meant, when the message shows one.
///
/// ```
/// use bvhview::Error;
///
/// match bvhview::limits::frame_time_option(Some(0.0)).unwrap_err() {
///     Error::InvalidArgument { name, value, .. } => {
///         assert_eq!((name, value.as_str()), ("frame_time", "0"))
///     }
///     other => panic!("{other:?}"),
/// }
/// let message = bvhview::Message::of_argument("max_size", Some("8G"));
/// let argument = message.arguments().next().unwrap();
/// assert_eq!((argument.name, argument.value.as_deref()), ("max_size", Some("8G")));
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Argument {
    /// The argument's name, in snake case (`max_size`, `frame_time`).
    pub name: &'static str,
    /// The value given, or a placeholder for one (`NAME|INDEX`).
    pub value: Option<String>,
}

/// How a front end writes an argument, and an opening of a file with one.
///
/// ```
/// use bvhview::{Argument, Message, Spelling};
///
/// #[derive(Debug)]
/// struct CommandLine;
/// impl Spelling for CommandLine {
///     fn argument(&self, argument: &Argument) -> String {
///         let flag = argument.name.replace('_', "-");
///         match &argument.value {
///             Some(value) => format!("--{flag} {value}"),
///             None => format!("--{flag}"),
///         }
///     }
///     fn opening(&self, file: &str, with: &Argument) -> String {
///         format!("bvhview info {file} {}", self.argument(with))
///     }
/// }
///
/// let message = Message::from("too big; raise ").argument("max_size", Some("8G"));
/// assert_eq!(message.spelled(&CommandLine), "too big; raise --max-size 8G");
/// assert_eq!(message.to_string(), "too big; raise max_size 8G");
/// ```
pub trait Spelling: fmt::Debug {
    /// `argument` as this front end's user writes it.
    fn argument(&self, argument: &Argument) -> String;
    /// How this front end's user opens `file` with `with` (an ASF skeleton with its motion).
    fn opening(&self, file: &str, with: &Argument) -> String;
}

/// The library's own spelling, what [`fmt::Display`] writes: `max_size 8G`, and an opening as
/// Rust writes it.
///
/// ```
/// use bvhview::{Message, RustSpelling};
///
/// let message = Message::from("give its skeleton: ").opening("07.asf", "motion", "07_05.amc");
/// assert_eq!(
///     message.spelled(&RustSpelling),
///     r#"give its skeleton: Take::open_with("07.asf", OpenOptions::new().motion("07_05.amc"))"#
/// );
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct RustSpelling;

impl Spelling for RustSpelling {
    fn argument(&self, argument: &Argument) -> String {
        match &argument.value {
            Some(value) => format!("{} {value}", argument.name),
            None => argument.name.to_string(),
        }
    }

    fn opening(&self, file: &str, with: &Argument) -> String {
        let value = with.value.as_deref().unwrap_or("");
        format!(
            "Take::open_with({file:?}, OpenOptions::new().{}({value:?}))",
            with.name
        )
    }
}

/// Text with the caller's arguments in it as data, spelled by [`Message::spelled`].
///
/// ```
/// use bvhview::Message;
///
/// let message = Message::from("two takes; ")
///     .argument("take", Some("NAME|INDEX"))
///     .text(" picks another");
/// assert_eq!(message.to_string(), "two takes; take NAME|INDEX picks another");
/// assert_eq!(message.arguments().next().unwrap().name, "take");
/// ```
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Message {
    parts: Vec<Part>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
enum Part {
    Text(String),
    Argument(Argument),
    Opening { file: String, with: Argument },
}

impl Message {
    /// A message that starts with the argument `name` (snake case), with `value` when one is
    /// shown: the edit or option a message is about.
    pub fn of_argument(name: &'static str, value: Option<&str>) -> Message {
        Message::default().argument(name, value)
    }

    /// `self`, then `text`.
    pub fn text(mut self, text: impl Into<String>) -> Message {
        let text = text.into();
        match self.parts.last_mut() {
            Some(Part::Text(last)) => last.push_str(&text),
            _ => self.parts.push(Part::Text(text)),
        }
        self
    }

    /// `self`, then the argument `name` (snake case), with `value` when one is shown.
    pub fn argument(mut self, name: &'static str, value: Option<&str>) -> Message {
        self.parts.push(Part::Argument(Argument {
            name,
            value: value.map(str::to_string),
        }));
        self
    }

    /// `self`, then how to open `file` with the argument `name` set to `value`.
    pub fn opening(mut self, file: &str, name: &'static str, value: &str) -> Message {
        self.parts.push(Part::Opening {
            file: file.to_string(),
            with: Argument {
                name,
                value: Some(value.to_string()),
            },
        });
        self
    }

    /// `self`, then `more`.
    pub fn then(mut self, more: Message) -> Message {
        for part in more.parts {
            match part {
                Part::Text(text) => self = self.text(text),
                other => self.parts.push(other),
            }
        }
        self
    }

    /// `before`, then `self`: a message put after its subject (`x.fbx: …`).
    pub fn after(mut self, before: &str) -> Message {
        match self.parts.first_mut() {
            Some(Part::Text(first)) => first.insert_str(0, before),
            _ => self.parts.insert(0, Part::Text(before.to_string())),
        }
        self
    }

    /// The arguments the message names, in order.
    pub fn arguments(&self) -> impl Iterator<Item = &Argument> {
        self.parts.iter().filter_map(|part| match part {
            Part::Argument(argument) | Part::Opening { with: argument, .. } => Some(argument),
            Part::Text(_) => None,
        })
    }

    /// Whether the message starts with `prefix` (its text before any argument).
    pub fn starts_with(&self, prefix: &str) -> bool {
        match self.parts.first() {
            Some(Part::Text(first)) => first.starts_with(prefix),
            _ => prefix.is_empty(),
        }
    }

    /// The message with each argument written as `spelling` writes it.
    pub fn spelled(&self, spelling: &dyn Spelling) -> String {
        let mut out = String::new();
        for part in &self.parts {
            match part {
                Part::Text(text) => out.push_str(text),
                Part::Argument(argument) => out.push_str(&spelling.argument(argument)),
                Part::Opening { file, with } => out.push_str(&spelling.opening(file, with)),
            }
        }
        out
    }
}

impl From<String> for Message {
    fn from(text: String) -> Message {
        Message {
            parts: vec![Part::Text(text)],
        }
    }
}

impl From<&str> for Message {
    fn from(text: &str) -> Message {
        Message::from(text.to_string())
    }
}

impl fmt::Display for Message {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.spelled(&RustSpelling))
    }
}

#[cfg(test)]
mod tests {
    use super::{Message, RustSpelling};

    #[test]
    fn text_joins_and_a_subject_goes_first() {
        let message = Message::from("a")
            .text("b")
            .argument("motion", Some("x.amc"))
            .after("f: ");
        assert_eq!(message.spelled(&RustSpelling), "f: abmotion x.amc");
        assert!(message.starts_with("f: a"));
        let opening = Message::default().opening("s.asf", "motion", "m.amc");
        assert_eq!(
            opening.to_string(),
            r#"Take::open_with("s.asf", OpenOptions::new().motion("m.amc"))"#
        );
        assert!(!opening.starts_with("T"));
    }
}
