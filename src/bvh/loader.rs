//! C++: `BVH::loadFile` and its helpers. A cursor over the file's bytes and a stack of open joints
//! (the article's `p` and `father`), dispatching on each keyword to a `process_*` function.
//!
//! What changed: the article advances `p` by fixed byte counts (`p += 7` after `OFFSET`, `p += 8`
//! per number, two bytes per line end), so it reads only CRLF files whose numbers have one width.
//! Here every step reads a whitespace-separated token, so spaces, tabs, LF, CRLF, lone CR, blank
//! lines and numbers of any width or with exponents all read the same. Every mismatch becomes an
//! [`Error::Parse`] with the line and column of the offending token instead of a crash or a tree
//! built from garbage. And the article reads the whole file into its buffer before `p` moves;
//! here the buffer fills from the file as `p` advances, so that only the hierarchy and the first
//! rows are in memory when the row loop starts, and the rows stream from the file.

pub use super::options::{Input, RowReader, Settings};
use super::rows::{self, RowParser, parse_number};
use crate::io::error::Error;
use crate::io::lines::{is_line_end, line_column, shown_first_word, shown_word};
use crate::limits::MAX_HEADER_BYTES;
use crate::model::motion::Motion;
use crate::model::skeleton::{Channel, Joint, RotationOrder, Skeleton};
use glam::Vec3;
use std::borrow::Cow;
use std::io::Read;
use std::path::Path;

/// C++: `class BVH`: a loaded file. The article keeps the loader's state (`p`, `father`,
/// `currentNode`) and the viewer's (`currentFrame`, `pFrame`) in the same object; here the loader
/// state lives in a private `Loader` for the length of one load, and the current frame belongs to
/// whoever shows the file. `clear` and `deleteRecursive` have no counterpart: loading returns a
/// new value, and dropping it frees every joint.
///
/// ```
/// use bvhview::bvh::load_bytes;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let text = b"HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Xposition Yposition Zposition\n \
///     End Site\n {\n  OFFSET 0 10 0\n }\n}\nMOTION\nFrames: 2\nFrame Time: 0.5\n0 1 2\n3 4 5\n";
/// let bvh = load_bytes(text, "inline")?;
/// assert_eq!(bvh.skeleton.joints.len(), 2); // Hips and its End Site
/// assert_eq!(bvh.motion.frame(1), [3.0, 4.0, 5.0]);
/// assert!(bvh.warnings.is_empty());
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Bvh {
    /// The HIERARCHY section: every joint and End Site in file order.
    pub skeleton: Skeleton,
    /// The MOTION section: the frame time and the rows.
    pub motion: Motion,
    /// Things that were accepted but deserve a word (e.g. rows beyond the Frames count).
    pub warnings: Vec<String>,
}

impl Default for Bvh {
    /// C++: `BVH::BVH`: an empty model, no joints and no frames (the article sets `frameTime` to 1
    /// and `jointCount` to 1 until a file is loaded; here the counts come from the file).
    fn default() -> Bvh {
        Bvh {
            skeleton: Skeleton::default(),
            motion: Motion::default(),
            warnings: Vec::new(),
        }
    }
}

/// C++: `BVH::loadFile`, in the article's steps and order: open the file and read it; check that
/// it starts with `HIERARCHY`; move the cursor over the hierarchy, dispatching each keyword to
/// its `process_*`, until `MOTION`; read `Frames:` and `Frame Time:`; then the rows. What changed,
/// step by step:
/// - read: the article reads the whole file into `buffer`; here the cursor's buffer fills from
///   the file as `p` advances (`Loader::token`), and the row loop streams the rest.
/// - the root: the article reads ROOT apart, at fixed offsets, with three position channels
///   assumed; here ROOT goes through `process_joint` like any joint, so any joint may have
///   position channels and a file may hold several roots.
/// - `counter`, the article's count of open braces, ends the loop at the root's `}`; here the
///   stack `father` is the count, and the loop ends at `MOTION` (or at the end of a file
///   without one: a skeleton with no frames).
/// - `Frames:` and `Frame Time:` are words read with or without a space before the colon, not
///   bytes at fixed distances (`p += 8`, `p += 12`).
/// - the row loop: one call, `Loader::read_rows`; see [`rows::read_rows_simple`] for the
///   article's loop in plain Rust beside the engine that runs.
pub fn load_file<'a>(input: impl Into<Input<'a>>, settings: Settings) -> Result<Bvh, Error> {
    // fopen, and the first fread.
    let mut bvh = Loader::open(input.into(), settings)?;
    // Is the file a BVH? It starts with HIERARCHY.
    bvh.process_hierarchy()?;
    // The hierarchy, keyword by keyword, until MOTION.
    loop {
        match bvh.next_keyword()? {
            Keyword::LeftBrace(brace) => bvh.process_left_brace(brace)?,
            Keyword::RightBrace(brace) => bvh.process_right_brace(brace)?,
            Keyword::Joint(keyword) => bvh.process_joint(keyword)?,
            Keyword::End(keyword) => bvh.process_end(keyword)?,
            Keyword::Offset(keyword) => bvh.process_offset(keyword)?,
            Keyword::Channels(keyword) => bvh.process_channels(keyword)?,
            Keyword::Motion => break,
            // A hierarchy without a MOTION section: a skeleton with zero frames.
            Keyword::EndOfFile => return Ok(bvh.finish(0, 0.0, (Vec::new(), Vec::new()))),
        }
    }
    // Frames: and Frame Time:.
    let (frames, frames_line) = bvh.process_frames()?;
    let frame_time = bvh.process_frame_time()?;
    // The row loop: Frames rows of one value per channel.
    let rows = bvh.read_rows(frames, frames_line, settings)?;
    Ok(bvh.finish(frames, frame_time, rows))
}

/// Parses BVH text. `source` names the input in error messages (`source:line:column: …`).
pub fn load_bytes(text: &[u8], source: &str) -> Result<Bvh, Error> {
    load_file(Input::Bytes(text, source), Settings::default())
}

/// A word of the file: where it starts and ends in the cursor's buffer.
#[derive(Clone, Copy)]
struct Token {
    at: usize,
    end: usize,
}

/// What the hierarchy loop dispatches on.
enum Keyword {
    LeftBrace(Token),
    RightBrace(Token),
    /// `ROOT` with no joint open, or `JOINT`.
    Joint(Token),
    /// `End` (of `End Site`).
    End(Token),
    Offset(Token),
    Channels(Token),
    Motion,
    EndOfFile,
}

fn is_space(byte: u8) -> bool {
    matches!(byte, b' ' | b'\t' | b'\r' | b'\n' | 0x0B | 0x0C)
}

/// The loader's state: the article's `p` over `buffer`, `father` and `currentNode`, and the
/// joints read so far.
struct Loader<'a> {
    /// C++: `buffer`: everything read so far. Borrowed for bytes in memory; owned and growing for
    /// a file, whose reads append to it.
    text: Cow<'a, [u8]>,
    /// C++: `unsigned char *p`, the read position in `text`.
    p: usize,
    /// The rest of the file, `None` once it has all been read (or for bytes in memory).
    file: Option<crate::io::read::Bounded<std::fs::File>>,
    /// The file's length when it is a regular file (a pipe's says nothing).
    length: Option<u64>,
    /// Bytes the next read of the file takes (each read doubles it).
    next_read: usize,
    /// Whether reading stopped at [`MAX_HEADER_BYTES`] with the hierarchy unfinished.
    cut: bool,
    source: String,
    joints: Vec<Joint>,
    has_offset: Vec<bool>,
    /// C++: `stack<BVHJoint*> father`: the joints whose `{` is open, innermost last.
    father: Vec<usize>,
    /// C++: `currentNode`: the joint the next `{`, OFFSET or CHANNELS belongs to.
    current_node: Option<usize>,
    /// A joint whose name was read and whose `{` must come next.
    awaiting_brace: Option<usize>,
    channel_count: usize,
    /// The deepest nesting accepted ([`Settings::max_depth`]).
    max_depth: usize,
}

impl<'a> Loader<'a> {
    /// C++: `fopen` and `fread`: the file opened, its first `first_read` bytes in the buffer.
    fn open(input: Input<'a>, settings: Settings) -> Result<Loader<'a>, Error> {
        let (text, file, length, source) = match input {
            Input::Bytes(text, source) => (Cow::Borrowed(text), None, None, source.to_string()),
            Input::Path(path) => {
                let io_error = |e| Error::io(path, e);
                let file = std::fs::File::open(path).map_err(io_error)?;
                let metadata = file.metadata().map_err(io_error)?;
                let length = metadata.is_file().then_some(metadata.len());
                let file = crate::io::read::Bounded::new(file, settings.max_size);
                let source = path.display().to_string();
                (Cow::Owned(Vec::new()), Some(file), length, source)
            }
        };
        let mut loader = Loader {
            text,
            p: 0,
            file,
            length,
            next_read: settings.first_read.max(1),
            cut: false,
            source,
            joints: Vec::new(),
            has_offset: Vec::new(),
            father: Vec::new(),
            current_node: None,
            awaiting_brace: None,
            channel_count: 0,
            max_depth: settings.max_depth,
        };
        loader.read_more()?;
        Ok(loader)
    }

    /// C++: `fread`, a piece at a time: appends the next piece of the file to the buffer.
    /// Returns whether anything was added (nothing at the end of the file, for bytes in memory,
    /// or past [`MAX_HEADER_BYTES`], where a hierarchy has never reached).
    fn read_more(&mut self) -> Result<bool, Error> {
        let Some(file) = self.file.as_mut() else {
            return Ok(false);
        };
        let Cow::Owned(buffer) = &mut self.text else {
            unreachable!("a file's buffer is owned");
        };
        if buffer.len() >= MAX_HEADER_BYTES {
            self.cut = true;
            return Ok(false);
        }
        let before = buffer.len();
        // A small file whole in one read: its length, and one byte more to see its end.
        let wanted = match self.length {
            Some(length) if length as usize - before.min(length as usize) < self.next_read => {
                length as usize - before.min(length as usize) + 1
            }
            _ => self.next_read,
        }
        .min(MAX_HEADER_BYTES - before);
        buffer.resize(before + wanted, 0);
        let read = loop {
            match file.read(&mut buffer[before..]) {
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                result => break result,
            }
        };
        let read = match read {
            Ok(read) => read,
            Err(e) => {
                buffer.truncate(before);
                return Err(Error::io(Path::new(&self.source), e));
            }
        };
        buffer.truncate(before + read);
        self.next_read = self.next_read.saturating_mul(2);
        if read == 0 {
            self.file = None;
        }
        Ok(read > 0)
    }

    /// Whether the buffer holds a byte at `at`, reading more of the file if it must.
    fn has(&mut self, at: usize) -> Result<bool, Error> {
        while at >= self.text.len() {
            if !self.read_more()? {
                return Ok(false);
            }
        }
        Ok(true)
    }

    fn word(&self, token: Token) -> &[u8] {
        &self.text[token.at..token.end]
    }

    fn is(&self, token: Token, keyword: &str) -> bool {
        self.word(token).eq_ignore_ascii_case(keyword.as_bytes())
    }

    fn error_at(&self, offset: usize, message: String) -> Error {
        let (line, column) = line_column(&self.text, offset);
        Error::Parse {
            path: self.source.clone(),
            line,
            column,
            message,
        }
    }

    /// An error at `found` (or at the end of the file) saying what was expected there.
    fn expected(&self, what: &str, found: Option<Token>) -> Error {
        let at = found.map_or(self.text.len(), |t| t.at);
        let found = match found {
            None if self.cut => format!(
                "no MOTION within the first {} MiB (no hierarchy is this long)",
                MAX_HEADER_BYTES >> 20
            ),
            None => "end of file".to_string(),
            Some(token) => shown_word(self.word(token)),
        };
        self.error_at(at, format!("expected {what}, found {found}"))
    }

    /// The next word; `{` and `}` are words of their own even when written against a name.
    fn token(&mut self) -> Result<Option<Token>, Error> {
        while self.has(self.p)? && is_space(self.text[self.p]) {
            self.p += 1;
        }
        let start = self.p;
        if !self.has(start)? {
            return Ok(None);
        }
        if matches!(self.text[start], b'{' | b'}') {
            self.p += 1;
        } else {
            while self.has(self.p)?
                && !is_space(self.text[self.p])
                && !matches!(self.text[self.p], b'{' | b'}')
            {
                self.p += 1;
            }
        }
        Ok(Some(Token {
            at: start,
            end: self.p,
        }))
    }

    fn peek_token(&mut self) -> Result<Option<Token>, Error> {
        let saved = self.p;
        let token = self.token();
        self.p = saved;
        token
    }

    fn number(&mut self, what: &str) -> Result<f32, Error> {
        let token = self.token()?;
        match token.and_then(|t| parse_number(self.word(t))) {
            Some(value) => Ok(value),
            None => Err(self.expected(what, token)),
        }
    }

    /// C++: the check of the first nine bytes against `"HIERARCHY"`. A UTF-8 byte-order mark
    /// and blank lines may come first.
    fn process_hierarchy(&mut self) -> Result<(), Error> {
        if self.has(2)? && self.text.starts_with(b"\xEF\xBB\xBF") {
            self.p = 3;
        }
        let header = self.token()?;
        if !header.is_some_and(|t| self.is(t, "HIERARCHY")) {
            return Err(self.not_a_bvh(header));
        }
        Ok(())
    }

    /// The error of a file that does not begin with HIERARCHY: not a BVH file, perhaps not
    /// motion at all, so its first word is shown only when it misspells HIERARCHY (a link to
    /// a private file once put a line of it in a dataset's manifest).
    fn not_a_bvh(&self, header: Option<Token>) -> Error {
        match header {
            Some(t) => {
                let found = shown_first_word(self.word(t), &["HIERARCHY"]);
                self.error_at(t.at, format!("expected HIERARCHY, found {found}"))
            }
            None => self.expected("HIERARCHY", header),
        }
    }

    /// C++: the `switch (*p)` of `loadFile`'s loop: the next keyword, if it may come here. The
    /// article dispatches on the first byte (`'J'`, `'O'`, …) and treats anything else as the
    /// end of the hierarchy; here the whole word is read, and a word out of place is an error
    /// that says what may come instead.
    fn next_keyword(&mut self) -> Result<Keyword, Error> {
        let token = self.token()?;
        if let Some(joint) = self.awaiting_brace
            && token.is_none_or(|t| self.word(t) != b"{")
        {
            let what = format!("'{{' after '{}'", self.joints[joint].name);
            return Err(self.expected(&what, token));
        }
        let Some(t) = token else {
            return match self.open_joint() {
                Some(open) => {
                    let what = format!("'}}' to close '{}'", self.joints[open].name);
                    Err(self.expected(&what, None))
                }
                None if self.joints.is_empty() => Err(self.expected("ROOT", None)),
                None => Ok(Keyword::EndOfFile),
            };
        };
        let open = self.open_joint();
        let in_end_site = open.is_some_and(|j| self.joints[j].end_site);
        Ok(match self.word(t) {
            b"{" => Keyword::LeftBrace(t),
            b"}" => Keyword::RightBrace(t),
            _ if self.is(t, "ROOT") && open.is_none() => Keyword::Joint(t),
            _ if self.is(t, "JOINT") && !in_end_site => Keyword::Joint(t),
            _ if self.is(t, "End") && open.is_some() && !in_end_site => Keyword::End(t),
            _ if self.is(t, "OFFSET") && open.is_some() => Keyword::Offset(t),
            _ if self.is(t, "CHANNELS") && open.is_some() && !in_end_site => Keyword::Channels(t),
            _ if self.is(t, "MOTION") && open.is_none() && !self.joints.is_empty() => {
                Keyword::Motion
            }
            _ if self.is(t, "MOTION") && !in_end_site && open.is_some() => {
                let name = &self.joints[open.unwrap_or_default()].name;
                let what = format!("'}}' to close '{name}' before MOTION");
                return Err(self.expected(&what, Some(t)));
            }
            _ => return Err(self.expected(self.expectation(), Some(t))),
        })
    }

    /// The joint whose `{` is open innermost, if any.
    fn open_joint(&self) -> Option<usize> {
        self.father.last().copied()
    }

    /// What may come next, for error messages.
    fn expectation(&self) -> &'static str {
        match self.open_joint() {
            None if self.joints.is_empty() => "ROOT",
            None => "ROOT or MOTION",
            Some(j) if self.joints[j].end_site => "OFFSET or '}' in End Site",
            Some(_) => "OFFSET, CHANNELS, JOINT, End Site or '}'",
        }
    }

    /// C++: `BVH::newNode`. The article copies bytes up to the line feed into a 24-byte array and
    /// drops the last one, assuming it is a carriage return. Here the name is the rest of the
    /// line, trimmed, of up to [`crate::limits::MAX_NAME_BYTES`] bytes (a longer one is damage,
    /// refused rather than repeated on every line of an export): names may hold spaces, ':' or
    /// '.'. A `{` written at the end of the same line is left for the main loop. The article's
    /// `addChild` (16 children at most, unchecked) is the push onto the parent's `children`.
    fn new_node(&mut self, keyword: Token, end_site: bool) -> Result<usize, Error> {
        while self.has(self.p)? && matches!(self.text[self.p], b' ' | b'\t') {
            self.p += 1;
        }
        let start = self.p;
        while self.has(self.p)? && !is_line_end(self.text[self.p]) {
            self.p += 1;
        }
        let mut line = &self.text[start..self.p];
        if let Some(brace) = line.iter().position(|&b| b == b'{' || b == b'}') {
            line = &line[..brace];
            self.p = start + brace;
        }
        // Counted as kept: bytes that are not UTF-8 become U+FFFD, three bytes each.
        let name = String::from_utf8_lossy(line.trim_ascii()).into_owned();
        if let Err(why) = crate::limits::name(name.len()) {
            return Err(self.error_at(start, why));
        }
        if name.is_empty() {
            let what = if end_site {
                "'Site' after End".to_string()
            } else {
                let keyword = String::from_utf8_lossy(self.word(keyword));
                format!("a joint name after {keyword}")
            };
            return Err(self.error_at(start, format!("expected {what}, found end of line")));
        }
        if self.father.len() >= self.max_depth {
            let levels = self.max_depth;
            return Err(self.error_at(
                keyword.at,
                format!("joints nest deeper than {levels} levels"),
            ));
        }
        let parent = self.father.last().copied();
        let index = self.joints.len();
        let mut joint = Joint::new(name, parent);
        joint.end_site = end_site;
        joint.first_channel = self.channel_count;
        self.joints.push(joint);
        self.has_offset.push(false);
        if let Some(parent) = parent {
            self.joints[parent].children.push(index);
        }
        self.awaiting_brace = Some(index);
        Ok(index)
    }

    /// C++: `BVH::processLeftBrace`: the joint just named becomes the top of the stack.
    fn process_left_brace(&mut self, brace: Token) -> Result<(), Error> {
        let Some(joint) = self.awaiting_brace.take() else {
            return Err(self.expected(self.expectation(), Some(brace)));
        };
        self.father.push(joint);
        self.current_node = Some(joint);
        Ok(())
    }

    /// C++: `BVH::processRightBrace`: pop the stack; its new top is the current joint again. The
    /// article pops without looking (its "debug 1"); here a `}` with nothing open, or closing a
    /// joint that never had an OFFSET, is an error. A `JOINT Site` with `CHANNELS 0` and no
    /// children, as some exporters write End Sites, is recorded as the End Site it is.
    fn process_right_brace(&mut self, brace: Token) -> Result<(), Error> {
        let Some(joint) = self.father.pop() else {
            return Err(self.expected(self.expectation(), Some(brace)));
        };
        if !self.has_offset[joint] {
            let what = format!("OFFSET in '{}'", self.joints[joint].name);
            return Err(self.expected(&what, Some(brace)));
        }
        let node = &mut self.joints[joint];
        if node.name.eq_ignore_ascii_case("Site")
            && node.parent.is_some()
            && node.channels.is_empty()
            && node.children.is_empty()
        {
            node.end_site = true;
        }
        self.current_node = self.father.last().copied();
        Ok(())
    }

    /// C++: `BVH::processJoint`: a child of the current joint (or a new root), named by the rest
    /// of the line. The article's 16-child array and its `assert` become a `Vec`.
    fn process_joint(&mut self, keyword: Token) -> Result<(), Error> {
        let joint = self.new_node(keyword, false)?;
        self.current_node = Some(joint);
        Ok(())
    }

    /// C++: `BVH::processEnd`: like a joint, but without channels. The article skips four bytes
    /// and keeps the rest of the line (`Site`) as the name; so does this.
    fn process_end(&mut self, keyword: Token) -> Result<(), Error> {
        let joint = self.new_node(keyword, true)?;
        self.current_node = Some(joint);
        Ok(())
    }

    /// C++: `BVH::processOffset`: three numbers, separated by any whitespace.
    fn process_offset(&mut self, keyword: Token) -> Result<(), Error> {
        let joint = self
            .current_node
            .expect("OFFSET is only dispatched inside a joint");
        if self.has_offset[joint] {
            let name = &self.joints[joint].name;
            return Err(self.error_at(keyword.at, format!("second OFFSET in '{name}'")));
        }
        let mut offset = [0.0f32; 3];
        for (axis, value) in offset.iter_mut().enumerate() {
            let what = format!("OFFSET's {} value (a number)", ["x", "y", "z"][axis]);
            *value = self.number(&what)?;
        }
        self.joints[joint].offset = Vec3::from_array(offset);
        self.has_offset[joint] = true;
        Ok(())
    }

    /// C++: `BVH::processChannels`. The article skips to the rotation names at fixed distances and
    /// keeps only their order; here every channel name is read and kept in file order, positions
    /// included, so the draw and the FK can apply them exactly as listed.
    fn process_channels(&mut self, keyword: Token) -> Result<(), Error> {
        let joint = self
            .current_node
            .expect("CHANNELS is only dispatched inside a joint");
        if !self.joints[joint].channels.is_empty() {
            let name = &self.joints[joint].name;
            return Err(self.error_at(keyword.at, format!("second CHANNELS in '{name}'")));
        }
        let count_token = self.token()?;
        let count: usize = match count_token
            .and_then(|t| std::str::from_utf8(self.word(t)).ok())
            .and_then(|s| s.parse().ok())
        {
            Some(count) => count,
            None => return Err(self.expected("the number of channels", count_token)),
        };
        let mut channels = Vec::new();
        for _ in 0..count {
            let token = self.token()?;
            let channel = token.and_then(|t| {
                std::str::from_utf8(self.word(t))
                    .ok()
                    .and_then(Channel::parse)
            });
            match channel {
                Some(channel) => channels.push(channel),
                None => {
                    let what = format!(
                        "{count} channel names (Xposition … Zrotation), {} so far",
                        channels.len()
                    );
                    return Err(self.expected(&what, token));
                }
            }
        }
        let node = &mut self.joints[joint];
        node.first_channel = self.channel_count;
        node.rotation_order = RotationOrder::get_flags(&channels);
        self.channel_count += channels.len();
        node.channels = channels;
        Ok(())
    }

    /// `Frames:` and `Frame Time:` may be written with the colon apart (`Frames :`).
    fn label(&mut self, word: &str, what: &str) -> Result<(), Error> {
        let token = self.token()?;
        let Some(t) = token else {
            return Err(self.expected(what, None));
        };
        if self.is(t, &format!("{word}:")) {
            return Ok(());
        }
        if self.is(t, word) && self.peek_token()?.is_some_and(|n| self.word(n) == b":") {
            self.token()?;
            return Ok(());
        }
        Err(self.expected(what, token))
    }

    /// C++: `frameCount = (unsigned)atoi(p)` after `Frames:`: the count, and its line (for the
    /// rows' messages).
    fn process_frames(&mut self) -> Result<(u64, usize), Error> {
        self.label("Frames", "'Frames:'")?;
        let token = self.token()?;
        let frames = token
            .and_then(|t| std::str::from_utf8(self.word(t)).ok())
            .and_then(|s| s.parse::<u64>().ok());
        match (frames, token) {
            (Some(frames), Some(t)) => Ok((frames, line_column(&self.text, t.at).0)),
            _ => Err(self.expected("the number of frames", token)),
        }
    }

    /// C++: `frameTime = (float)atof(p)` after `Frame Time:`, kept as a double here; then the
    /// rest of its line must be blank, as the rows start on the next one.
    fn process_frame_time(&mut self) -> Result<f64, Error> {
        let frame_word = self.token()?;
        if !frame_word.is_some_and(|t| self.is(t, "Frame")) {
            return Err(self.expected("'Frame Time:'", frame_word));
        }
        self.label("Time", "'Frame Time:'")?;
        let token = self.token()?;
        let frame_time = match token
            .and_then(|t| std::str::from_utf8(self.word(t)).ok())
            .and_then(|s| s.parse::<f64>().ok())
        {
            Some(time) if crate::limits::frame_time_in_file(time) => time,
            _ => {
                let what = format!(
                    "the frame time (seconds: 0, or {} to {})",
                    crate::limits::show(crate::limits::MIN_FRAME_TIME),
                    crate::limits::MAX_FRAME_TIME
                );
                return Err(self.expected(&what, token));
            }
        };
        while self.has(self.p)? && matches!(self.text[self.p], b' ' | b'\t') {
            self.p += 1;
        }
        if self.has(self.p)? && !is_line_end(self.text[self.p]) {
            let token = self.peek_token()?;
            return Err(self.expected("end of line after the frame time", token));
        }
        // Past the line end (CR LF is one): the rows start on the next line.
        if self.has(self.p)? {
            let crlf = self.text[self.p] == b'\r'
                && self.has(self.p + 1)?
                && self.text[self.p + 1] == b'\n';
            self.p += 1 + usize::from(crlf);
        }
        Ok(frame_time)
    }

    /// C++: the row loop at the end of `loadFile` (`for i < frameCount, for j < dataCount`):
    /// `frames` rows of one value per channel, from the cursor's position on. The engine
    /// ([`RowParser`]) reads what the buffer holds, then streams the rest of the file on every
    /// core; [`rows::read_rows_simple`] is the article's loop in plain Rust, the same values and
    /// errors (a test proves it). The article allocates `frameCount` rows first, whatever the file
    /// holds; here no more is reserved than the rest of the file could hold.
    fn read_rows(
        &mut self,
        frames: u64,
        frames_line: usize,
        settings: Settings,
    ) -> Result<(Vec<f32>, Vec<String>), Error> {
        let start = line_column(&self.text, self.p);
        let width = self.channel_count;
        if self
            .length
            .is_some_and(|length| self.text.len() as u64 >= length)
        {
            // Read to its length: one more read sees the end, and the rows are all in memory.
            self.read_more()?;
        }
        if settings.rows == RowReader::Simple {
            if let (Some(file), Cow::Owned(buffer)) = (self.file.as_mut(), &mut self.text) {
                file.read_to_end(buffer)
                    .map_err(|e| Error::io(Path::new(&self.source), e))?;
            }
            let text = &self.text[self.p..];
            return rows::read_rows_simple(text, &self.source, (frames, frames_line), width, start);
        }
        let carry = &self.text[self.p..];
        let room = match (&self.file, self.length) {
            (None, _) => carry.len() as u64,
            (Some(_), Some(length)) => {
                length.saturating_sub(self.text.len() as u64) + carry.len() as u64
            }
            (Some(_), None) => rows::UNKNOWN_ROOM,
        };
        let mut parser = RowParser::new(&self.source, frames, width, frames_line, start, room)
            .with_threads(settings.threads);
        match self.file.as_mut() {
            // Read whole: the rows are parsed where they lie.
            None => parser.feed_all_in_memory(carry)?,
            Some(file) => {
                let path = Path::new(&self.source);
                parser.feed_all(carry, file, &|e| Error::io(path, e))?;
            }
        }
        parser.finish()
    }

    /// The loaded file.
    fn finish(
        self,
        frames: u64,
        frame_time: f64,
        (data, warnings): (Vec<f32>, Vec<String>),
    ) -> Bvh {
        let motion = Motion::new(frame_time, self.channel_count, frames as usize, data);
        Bvh {
            skeleton: Skeleton {
                joints: self.joints,
                ..Skeleton::default()
            },
            motion,
            warnings,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file of `rows` rows after `header` (the text from MOTION on, without the rows).
    fn file_with(header: &str, rows: usize) -> Vec<u8> {
        let mut text = String::from(
            "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 3 Zrotation Xrotation Yrotation\n\
             \tEnd Site\n\t{\n\t\tOFFSET 0 1 0\n\t}\n}\n",
        );
        text.push_str(header);
        for row in 0..rows {
            text.push_str(&format!("{row} 1.5 -2.25\n"));
        }
        text.into_bytes()
    }

    /// The cursor reads a file a piece at a time: however small the pieces, the file loads as it
    /// does from memory, and a joint named MOTION is a joint (nothing scans ahead for MOTION).
    #[test]
    fn a_file_read_in_small_pieces_loads_as_from_memory() {
        let folder = tempfile::tempdir().unwrap();
        let dir = folder.path();
        let plain = file_with("MOTION\r\nFrames :\t3\r\nFRAME TIME : 0.01\r\n", 3);
        let named = String::from_utf8(plain.clone())
            .unwrap()
            .replace("ROOT Hips", "ROOT MOTION");
        for (name, bytes) in [("plain.bvh", plain), ("named.bvh", named.into_bytes())] {
            let path = dir.join(name);
            std::fs::write(&path, &bytes).unwrap();
            let memory = load_bytes(&bytes, &path.display().to_string()).unwrap();
            for first_read in [1, 2, 3, 7, 64, 1 << 16] {
                let settings = Settings {
                    first_read,
                    ..Settings::default()
                };
                let file = load_file(&path, settings).unwrap();
                assert_eq!(file.motion, memory.motion, "{name}, {first_read}");
                assert_eq!(file.skeleton.joints.len(), 2);
                assert_eq!(file.skeleton.joints[0].name, memory.skeleton.joints[0].name);
            }
        }
        std::fs::remove_dir_all(dir).unwrap();
    }
}
