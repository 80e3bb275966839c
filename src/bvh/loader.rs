//! C++: `BVH::loadFile` and its helpers. A cursor over the file's bytes and a stack of open joints
//! (the article's `p` and `father`), dispatching on each keyword to a `process_*` function.
//!
//! What changed: the article advances `p` by fixed byte counts (`p += 7` after `OFFSET`, `p += 8`
//! per number, two bytes per line end), so it reads only CRLF files whose numbers have one width.
//! Here every step reads a whitespace-separated token, so spaces, tabs, LF, CRLF, lone CR, blank
//! lines and numbers of any width or with exponents all read the same. Every mismatch becomes an
//! [`Error::Parse`] with the line and column of the offending token instead of a crash or a tree
//! built from garbage.

use crate::error::{Error, line_column};
use crate::motion::Motion;
use crate::skeleton::{Channel, Joint, RotationOrder, Skeleton};
use glam::Vec3;
use std::path::Path;

/// Deepest nesting of joints the loader accepts; deeper files are refused, not a stack overflow.
pub const MAX_DEPTH: usize = 1000;

/// C++: `class BVH`: a loaded file. The article keeps the loader's state (`p`, `father`,
/// `currentNode`) and the viewer's (`currentFrame`, `pFrame`) in the same object; here the loader
/// state lives in a private `Loader` for the length of one load, and the current frame belongs to
/// whoever shows the file. `clear` and `deleteRecursive` have no counterpart: loading returns a
/// new value, and dropping it frees every joint.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    pub skeleton: Skeleton,
    pub motion: Motion,
    /// Things that were accepted but deserve a word (e.g. rows beyond the Frames count).
    pub warnings: Vec<String>,
}

/// C++: `BVH::loadFile`. Reads the whole file, then parses it; see [`load_bytes`].
pub fn load_file(path: &Path) -> Result<Bvh, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    load_bytes(&bytes, &path.display().to_string())
}

/// Parses BVH text. `source` names the input in error messages (`source:line:column: …`).
pub fn load_bytes(text: &[u8], source: &str) -> Result<Bvh, Error> {
    let mut loader = Loader {
        text,
        p: 0,
        source,
        joints: Vec::new(),
        has_offset: Vec::new(),
        father: Vec::new(),
        current_node: None,
        awaiting_brace: None,
        channel_count: 0,
        warnings: Vec::new(),
    };
    let motion = loader.load()?;
    Ok(Bvh {
        skeleton: Skeleton {
            joints: loader.joints,
            ..Skeleton::default()
        },
        motion,
        warnings: loader.warnings,
    })
}

/// A word of the file and the byte offset where it starts.
#[derive(Clone, Copy)]
struct Token<'a> {
    text: &'a [u8],
    at: usize,
}

impl Token<'_> {
    fn is(&self, keyword: &str) -> bool {
        self.text.eq_ignore_ascii_case(keyword.as_bytes())
    }
}

fn is_space(byte: u8) -> bool {
    matches!(byte, b' ' | b'\t' | b'\r' | b'\n' | 0x0B | 0x0C)
}

fn is_line_end(byte: u8) -> bool {
    byte == b'\n' || byte == b'\r'
}

/// How a found token is quoted in an error message.
fn describe(token: Option<Token<'_>>) -> String {
    match token {
        None => "end of file".to_string(),
        Some(token) => {
            let text = String::from_utf8_lossy(token.text);
            if text.chars().count() > 40 {
                let short: String = text.chars().take(40).collect();
                format!("'{short}…'")
            } else {
                format!("'{text}'")
            }
        }
    }
}

/// Parses one number as the article does (`(float)atof(p)`: read as a double, then rounded to a
/// float), but refuses anything that is not entirely a finite number.
pub(crate) fn parse_number(text: &[u8]) -> Option<f32> {
    let value: f64 = std::str::from_utf8(text).ok()?.parse().ok()?;
    let value = value as f32;
    value.is_finite().then_some(value)
}

struct Loader<'a> {
    text: &'a [u8],
    /// C++: `unsigned char *p`, the read position.
    p: usize,
    source: &'a str,
    joints: Vec<Joint>,
    has_offset: Vec<bool>,
    /// C++: `stack<BVHJoint*> father`: the joints whose `{` is open, innermost last.
    father: Vec<usize>,
    /// C++: `currentNode`: the joint the next `{`, OFFSET or CHANNELS belongs to.
    current_node: Option<usize>,
    /// A joint whose name was read and whose `{` must come next, with its keyword's offset.
    awaiting_brace: Option<(usize, usize)>,
    channel_count: usize,
    warnings: Vec<String>,
}

impl<'a> Loader<'a> {
    fn error_at(&self, offset: usize, message: String) -> Error {
        let (line, column) = line_column(self.text, offset);
        Error::Parse {
            path: self.source.to_string(),
            line,
            column,
            message,
        }
    }

    /// An error at `found` (or at the end of the file) saying what was expected there.
    fn expected(&self, what: &str, found: Option<Token<'_>>) -> Error {
        let at = found.map_or(self.text.len(), |t| t.at);
        self.error_at(at, format!("expected {what}, found {}", describe(found)))
    }

    fn skip_space(&mut self) {
        while self.p < self.text.len() && is_space(self.text[self.p]) {
            self.p += 1;
        }
    }

    /// The next word; `{` and `}` are words of their own even when written against a name.
    fn token(&mut self) -> Option<Token<'a>> {
        self.skip_space();
        let start = self.p;
        let text = self.text;
        match text.get(start) {
            None => return None,
            Some(b'{') | Some(b'}') => self.p += 1,
            Some(_) => {
                while self.p < text.len()
                    && !is_space(text[self.p])
                    && text[self.p] != b'{'
                    && text[self.p] != b'}'
                {
                    self.p += 1;
                }
            }
        }
        Some(Token {
            text: &text[start..self.p],
            at: start,
        })
    }

    fn peek_token(&mut self) -> Option<Token<'a>> {
        let saved = self.p;
        let token = self.token();
        self.p = saved;
        token
    }

    fn number(&mut self, what: &str) -> Result<f32, Error> {
        let token = self.token();
        match token {
            Some(t) => match parse_number(t.text) {
                Some(value) => Ok(value),
                None => Err(self.expected(what, token)),
            },
            None => Err(self.expected(what, None)),
        }
    }

    /// C++: `BVH::newNode`. The article copies bytes up to the line feed into a 24-byte array and
    /// drops the last one, assuming it is a carriage return. Here the name is the rest of the
    /// line, trimmed, of any length: names may hold spaces, ':' or '.'. A `{` written at the end
    /// of the same line is left for the main loop.
    fn new_node(&mut self, keyword: Token<'_>, end_site: bool) -> Result<usize, Error> {
        while self.p < self.text.len() && matches!(self.text[self.p], b' ' | b'\t') {
            self.p += 1;
        }
        let start = self.p;
        while self.p < self.text.len() && !is_line_end(self.text[self.p]) {
            self.p += 1;
        }
        let mut line = &self.text[start..self.p];
        if let Some(brace) = line.iter().position(|&b| b == b'{' || b == b'}') {
            line = &line[..brace];
            self.p = start + brace;
        }
        let name = String::from_utf8_lossy(line.trim_ascii()).into_owned();
        if name.is_empty() {
            let what = if end_site {
                "'Site' after End".to_string()
            } else {
                format!(
                    "a joint name after {}",
                    String::from_utf8_lossy(keyword.text)
                )
            };
            return Err(self.error_at(start, format!("expected {what}, found end of line")));
        }
        if self.father.len() >= MAX_DEPTH {
            return Err(self.error_at(
                keyword.at,
                format!("joints nest deeper than {MAX_DEPTH} levels"),
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
        self.awaiting_brace = Some((index, keyword.at));
        Ok(index)
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

    /// C++: the body of `BVH::loadFile`: check the header, then read the hierarchy token by token,
    /// then the motion. The article treats ROOT apart (it skips to fixed offsets for its OFFSET
    /// and assumes three position channels first); here ROOT is a joint like the others, so
    /// position channels may sit on any joint, in any order, and a root written `JOINT` loads.
    fn load(&mut self) -> Result<Motion, Error> {
        if self.text.starts_with(b"\xEF\xBB\xBF") {
            self.p = 3;
        }
        let header = self.token();
        if !header.is_some_and(|t| t.is("HIERARCHY")) {
            return Err(self.expected("HIERARCHY", header));
        }
        loop {
            let token = self.token();
            if let Some((joint, _)) = self.awaiting_brace
                && token.is_none_or(|t| t.text != b"{")
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
                    // A hierarchy without a MOTION section: a skeleton with zero frames.
                    None => Ok(Motion::new(0.0, self.channel_count, 0, Vec::new())),
                };
            };
            let in_end_site = self.open_joint().is_some_and(|j| self.joints[j].end_site);
            match t.text {
                b"{" => self.process_left_brace(t)?,
                b"}" => self.process_right_brace(t)?,
                _ if t.is("ROOT") && self.open_joint().is_none() => self.process_joint(t)?,
                _ if t.is("JOINT") && !in_end_site => self.process_joint(t)?,
                _ if t.is("End") && self.open_joint().is_some() && !in_end_site => {
                    self.process_end(t)?
                }
                _ if t.is("OFFSET") && self.open_joint().is_some() => self.process_offset(t)?,
                _ if t.is("CHANNELS") && self.open_joint().is_some() && !in_end_site => {
                    self.process_channels(t)?
                }
                _ if t.is("MOTION") && self.open_joint().is_none() && !self.joints.is_empty() => {
                    return self.load_motion();
                }
                _ if t.is("MOTION") && !in_end_site && self.open_joint().is_some() => {
                    let open = self.open_joint().unwrap_or_default();
                    let what = format!("'}}' to close '{}' before MOTION", self.joints[open].name);
                    return Err(self.expected(&what, Some(t)));
                }
                _ => return Err(self.expected(self.expectation(), Some(t))),
            }
        }
    }

    /// C++: `BVH::processLeftBrace`: the joint just named becomes the top of the stack.
    fn process_left_brace(&mut self, brace: Token<'_>) -> Result<(), Error> {
        let Some((joint, _)) = self.awaiting_brace.take() else {
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
    fn process_right_brace(&mut self, brace: Token<'_>) -> Result<(), Error> {
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
    fn process_joint(&mut self, keyword: Token<'_>) -> Result<(), Error> {
        let joint = self.new_node(keyword, false)?;
        self.current_node = Some(joint);
        Ok(())
    }

    /// C++: `BVH::processEnd`: like a joint, but without channels. The article skips four bytes
    /// and keeps the rest of the line (`Site`) as the name; so does this.
    fn process_end(&mut self, keyword: Token<'_>) -> Result<(), Error> {
        let joint = self.new_node(keyword, true)?;
        self.current_node = Some(joint);
        Ok(())
    }

    /// C++: `BVH::processOffset`: three numbers, separated by any whitespace.
    fn process_offset(&mut self, keyword: Token<'_>) -> Result<(), Error> {
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
    fn process_channels(&mut self, keyword: Token<'_>) -> Result<(), Error> {
        let joint = self
            .current_node
            .expect("CHANNELS is only dispatched inside a joint");
        if !self.joints[joint].channels.is_empty() {
            let name = &self.joints[joint].name;
            return Err(self.error_at(keyword.at, format!("second CHANNELS in '{name}'")));
        }
        let count_token = self.token();
        let count: usize = match count_token
            .and_then(|t| std::str::from_utf8(t.text).ok())
            .and_then(|s| s.parse().ok())
        {
            Some(count) => count,
            None => return Err(self.expected("the number of channels", count_token)),
        };
        let mut channels = Vec::new();
        for _ in 0..count {
            let token = self.token();
            match token.and_then(|t| std::str::from_utf8(t.text).ok().and_then(Channel::parse)) {
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
        let token = self.token();
        let Some(t) = token else {
            return Err(self.expected(what, None));
        };
        let with_colon = format!("{word}:");
        if t.is(&with_colon) {
            return Ok(());
        }
        if t.is(word) && self.peek_token().is_some_and(|n| n.text == b":") {
            self.token();
            return Ok(());
        }
        Err(self.expected(what, token))
    }

    /// The motion section after `MOTION`. C++: the second half of `BVH::loadFile`. The article
    /// allocates `Frames` rows up front and then reads that many rows with fixed strides whatever
    /// the file holds; here the allocation is bounded by what the rest of the file could hold,
    /// each row must be one line with exactly one value per channel, a file that ends early is an
    /// error, and rows beyond the count are ignored with a warning.
    fn load_motion(&mut self) -> Result<Motion, Error> {
        self.label("Frames", "'Frames:'")?;
        let frames_token = self.token();
        let frames: u64 = match frames_token
            .and_then(|t| std::str::from_utf8(t.text).ok())
            .and_then(|s| s.parse().ok())
        {
            Some(frames) => frames,
            None => return Err(self.expected("the number of frames", frames_token)),
        };
        let frames_at = frames_token.map_or(0, |t| t.at);
        let frame_word = self.token();
        if !frame_word.is_some_and(|t| t.is("Frame")) {
            return Err(self.expected("'Frame Time:'", frame_word));
        }
        self.label("Time", "'Frame Time:'")?;
        let time_token = self.token();
        let frame_time = match time_token
            .and_then(|t| std::str::from_utf8(t.text).ok())
            .and_then(|s| s.parse::<f64>().ok())
        {
            Some(time) if time.is_finite() && time >= 0.0 => time,
            _ => {
                return Err(self.expected("the frame time (seconds, a number ≥ 0)", time_token));
            }
        };
        self.finish_line("end of line after the frame time")?;
        let (frames_line, _) = line_column(self.text, frames_at);
        let data = self.read_rows(frames, frames_line)?;
        let frame_count = frames as usize;
        Ok(Motion::new(
            frame_time,
            self.channel_count,
            frame_count,
            data,
        ))
    }

    /// Requires that nothing but spaces follows on the current line.
    fn finish_line(&mut self, what: &str) -> Result<(), Error> {
        while self.p < self.text.len() && matches!(self.text[self.p], b' ' | b'\t') {
            self.p += 1;
        }
        if self.p < self.text.len() && !is_line_end(self.text[self.p]) {
            let token = self.peek_token();
            return Err(self.expected(what, token));
        }
        Ok(())
    }

    /// Reads `frames` rows of `channel_count` values, one row per line.
    fn read_rows(&mut self, frames: u64, frames_line: usize) -> Result<Vec<f32>, Error> {
        let width = self.channel_count;
        let remaining = (self.text.len() - self.p) as u64;
        if width == 0 {
            // No columns: rows are empty lines and cannot be counted reliably; the count may not
            // exceed the lines left, so a huge count cannot make the caller loop for ever.
            let lines_left = self.text[self.p..]
                .iter()
                .filter(|&&b| b == b'\n' || b == b'\r')
                .count() as u64;
            if frames > lines_left {
                return Err(self.error_at(
                    self.text.len(),
                    format!(
                        "Frames: {frames} (line {frames_line}) but only {lines_left} lines follow"
                    ),
                ));
            }
            return Ok(Vec::new());
        }
        // Each value takes at least two bytes ("0 "), so no more than this can be in the file.
        let possible_values = remaining / 2 + 1;
        let wanted = frames.saturating_mul(width as u64);
        let mut data = Vec::with_capacity(wanted.min(possible_values) as usize);
        for frame in 0..frames {
            self.skip_space();
            if self.p == self.text.len() {
                return Err(self.error_at(
                    self.p,
                    format!(
                        "expected {frames} frames as Frames: says (line {frames_line}), \
                         found {frame}: the file ends"
                    ),
                ));
            }
            self.read_row(frame, width, &mut data)?;
        }
        self.skip_space();
        if self.p < self.text.len() {
            let (line, _) = line_column(self.text, self.p);
            let extra = self.text[self.p..]
                .split(|&b| b == b'\n' || b == b'\r')
                .filter(|row| !row.trim_ascii().is_empty())
                .count();
            let rows = if extra == 1 { "row" } else { "rows" };
            self.warnings.push(format!(
                "{extra} extra {rows} after the {frames} announced by Frames: (line {frames_line}) \
                 ignored, from line {line} on"
            ));
        }
        Ok(data)
    }

    /// One MOTION row: exactly `width` numbers on one line.
    fn read_row(&mut self, frame: u64, width: usize, data: &mut Vec<f32>) -> Result<(), Error> {
        let text = self.text;
        let mut count = 0;
        loop {
            while self.p < text.len() && matches!(text[self.p], b' ' | b'\t' | 0x0B | 0x0C) {
                self.p += 1;
            }
            if self.p == text.len() || is_line_end(text[self.p]) {
                break;
            }
            let start = self.p;
            while self.p < text.len() && !is_space(text[self.p]) {
                self.p += 1;
            }
            let word = &text[start..self.p];
            if count == width {
                return Err(self.error_at(
                    start,
                    format!(
                        "frame {} has more than the {width} values the channels need",
                        frame + 1
                    ),
                ));
            }
            match parse_number(word) {
                Some(value) => data.push(value),
                None => {
                    let found = Token {
                        text: word,
                        at: start,
                    };
                    return Err(self.expected("a finite number", Some(found)));
                }
            }
            count += 1;
        }
        if count < width {
            return Err(self.error_at(
                self.p,
                format!(
                    "frame {} has {count} values, expected {width} (one per channel)",
                    frame + 1
                ),
            ));
        }
        Ok(())
    }
}
