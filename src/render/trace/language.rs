//! The two languages of the notes, a phrase in both, and the small words every note writes (axis
//! letters, numbers as `{}` writes them).

/// The language of `--explain`'s notes.
///
/// ```
/// use bvhview::model::pose::OffsetMode;
/// use bvhview::render::{draw::{Style, draw}, trace::{Language, Numbers, Recorder}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = bvhview::Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let (frame, mode) = (Some(take.motion.frame(1)), OffsetMode::Replace);
/// let explained = |language| {
///     let mut gl = Recorder::explaining(Numbers::Printf, &take.skeleton, frame, mode, language, None);
///     draw(&mut gl, &take.skeleton, frame, Style::Points, mode);
///     gl
/// };
/// let (english, chinese) = (explained(Language::English), explained(Language::Chinese));
/// assert!(english.lines[1].ends_with("// Hips: push, stack depth 1"));
/// assert!(chinese.lines[1].ends_with("// Hips：推入矩陣堆疊，深度 1"));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Language {
    /// English.
    #[default]
    English,
    /// Traditional Chinese, in the article's terms.
    Chinese,
}

/// The axis names, in order.
pub(super) fn axis_letters(axes: impl IntoIterator<Item = usize>, zh: bool) -> String {
    let letters: Vec<&str> = axes.into_iter().map(|a| ["X", "Y", "Z"][a]).collect();
    letters.join(if zh { "、" } else { ", " })
}

/// A number of a note: as `{}` writes an `f32` (`30`, `-3`, `0.033333`).
pub(super) fn plain(values: &[f32]) -> String {
    let values: Vec<String> = values.iter().map(|v| v.to_string()).collect();
    format!("({})", values.join(", "))
}

/// One phrase of a note in both languages, English first: the notes read as a two-column table,
/// and the language asked for picks the column.
pub(super) type Both = [String; 2];

/// A row of fixed text: the same phrase in English and in Chinese.
pub(super) fn both(english: &str, chinese: &str) -> Both {
    [english.to_string(), chinese.to_string()]
}
