//! C++: `BVH::loadFile` and its helpers. A cursor over the file's bytes and a stack of open joints
//! (the article's `p` and `father`), dispatching on each keyword to a `process_*` function.
//!
//! What changed: the article advances `p` by fixed byte counts (`p += 7` after `OFFSET`, `p += 8`
//! per number, two bytes per line end), so it reads only CRLF files whose numbers have one width.
//! Here every step reads a whitespace-separated token, so spaces, tabs, LF, CRLF, lone CR, blank
//! lines and numbers of any width or with exponents all read the same. Every mismatch becomes an
//! [`Error::Parse`] with the line and column of the offending token instead of a crash or a tree
//! built from garbage.

use super::rows::{RowParser, parse_number};
use crate::error::Error;
use crate::limits::MAX_DEPTH;
use crate::lines::{is_line_end, line_column};
use crate::motion::Motion;
use crate::skeleton::{Channel, Joint, RotationOrder, Skeleton};
use glam::Vec3;
use std::path::Path;

/// C++: `class BVH`: a loaded file. The article keeps the loader's state (`p`, `father`,
/// `currentNode`) and the viewer's (`currentFrame`, `pFrame`) in the same object; here the loader
/// state lives in a private `Loader` for the length of one load, and the current frame belongs to
/// whoever shows the file. `clear` and `deleteRecursive` have no counterpart: loading returns a
/// new value, and dropping it frees every joint.
#[derive(Clone, Debug)]
pub struct Bvh {
    pub skeleton: Skeleton,
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

/// C++: `BVH::loadFile`, in the article's steps: open the file, read it, check that it starts with
/// `HIERARCHY`, move a cursor over the hierarchy dispatching each keyword to its `process_*`, then
/// read `Frames`, `Frame Time` and the rows. Those steps are [`load_file_with`]'s, in that order.
/// What changed: the rows, the bulk of a file, are not read into one buffer first but streamed
/// to every core by the row engine in [`super::rows`]; every mismatch is an error with its line
/// and column.
pub fn load_file(path: &Path) -> Result<Bvh, Error> {
    load_file_with(path, crate::cores(), u64::MAX)
}

/// [`load_file`] parsing on at most `threads` threads (1 when many files load at once), reading
/// no more than `max_size` bytes from the path, whatever it is (a file, a pipe, a device).
pub fn load_file_with(path: &Path, threads: usize, max_size: u64) -> Result<Bvh, Error> {
    load_file_streaming_over(path, threads, max_size, WHOLE_FILE)
}

/// Files up to this size (one smallest chunk) are read whole and parsed where they lie; larger
/// ones stream through chunk buffers, so memory stays at about the values' size however large the
/// file is. Streaming is also the faster way in a fresh process: every 4 KB page of a new buffer
/// the size of the file costs a page fault on its first write, while chunk buffers are kept from
/// load to load. A 5 MB file's first load on the 2-vCPU VM of the README's
/// measurements: 3.6–4.5 ms streamed, 5.4–7.7 ms read whole; loads after the first: 2.3 ms
/// either way.
pub const WHOLE_FILE: u64 = 64 << 10;

/// [`load_file_with`], streaming every file larger than `whole_file` bytes (tests give 0 to
/// stream small files too).
pub fn load_file_streaming_over(
    path: &Path,
    threads: usize,
    max_size: u64,
    whole_file: u64,
) -> Result<Bvh, Error> {
    let io_error = |e| Error::io(path, e);
    let source = path.display().to_string();
    // fopen.
    let file = std::fs::File::open(path).map_err(io_error)?;
    let metadata = file.metadata().map_err(io_error)?;
    let length = metadata.len();
    let mut file = crate::input::Bounded::new(file, max_size);
    // Not a pipe or a device: their length says nothing about what they hold.
    if metadata.is_file() && length <= whole_file {
        // One read of the whole file, the article's fread.
        use std::io::Read;
        let mut all = Vec::with_capacity(length as usize + 1);
        file.read_to_end(&mut all).map_err(io_error)?;
        return load_bytes_with_threads(&all, &source, threads);
    }
    // fread: the hierarchy and the MOTION header; the rows stay in the file for now. A file
    // without rows is read whole and loaded from memory.
    let (head, rows_start) =
        read_head(&mut file, length, &mut HeaderScan::default()).map_err(io_error)?;
    let Some(rows_start) = rows_start else {
        if head.len() > crate::limits::MAX_HEADER_BYTES {
            return Err(header_too_long(&head, &source));
        }
        return load_bytes_with_threads(&head, &source, threads);
    };
    // Check HIERARCHY, then the cursor loop: one `process_*` per keyword, then Frames and
    // Frame Time (`Loader::load`).
    let mut loader = Loader::new(&head[..rows_start], &source);
    let header = match loader.load() {
        Ok(header) => header,
        // The hierarchy ended where the cut did: something in it only looked like the motion
        // header (a joint named MOTION). Read it all the slow way. Any other error is the file's.
        Err(Error::Parse { line, column, .. })
            if (line, column) == line_column(&head, rows_start) =>
        {
            use std::io::Read;
            let mut all = head;
            file.read_to_end(&mut all).map_err(io_error)?;
            return load_bytes_with_threads(&all, &source, threads);
        }
        Err(error) => return Err(error),
    };
    let Header::Motion {
        frames,
        frame_time,
        frames_line,
    } = header
    else {
        unreachable!("the header was cut after its Frame Time line");
    };
    // The row loop: the row engine reads what was read already, then the rest of the file.
    let start = line_column(&head, rows_start);
    let rest = if metadata.is_file() {
        length.saturating_sub(rows_start as u64)
    } else {
        super::rows::UNKNOWN_ROOM
    };
    let mut rows = RowParser::new(
        &source,
        frames,
        loader.channel_count,
        frames_line,
        start,
        rest,
    )
    .with_threads(threads);
    rows.feed_all(&head[rows_start..], &mut file, &io_error)?;
    loader.finish_rows(frames, frame_time, rows)
}

/// Reads the start of `input` (`length` bytes, as far as is known) until [`HeaderScan`] finds
/// where the rows begin, or to the end. Each read doubles what is held, so however often the scan
/// looks again, it looks at no more than about twice the bytes read.
fn read_head(
    input: &mut impl std::io::Read,
    length: u64,
    scan: &mut HeaderScan,
) -> std::io::Result<(Vec<u8>, Option<usize>)> {
    let mut head = Vec::new();
    loop {
        let before = head.len();
        // One byte more than the rest of the file, so that its end is seen without a second read.
        let rest = length.saturating_sub(before as u64).saturating_add(1);
        let more = (before.max(64 * 1024) as u64).min(rest.max(4096)) as usize;
        head.resize(before + more, 0);
        let read = loop {
            match input.read(&mut head[before..]) {
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                result => break result?,
            }
        };
        head.truncate(before + read);
        if read == 0 {
            return Ok((head, None));
        }
        if let Some(start) = scan.rows_start(&head) {
            return Ok((head, Some(start)));
        }
        if head.len() > crate::limits::MAX_HEADER_BYTES {
            return Ok((head, None));
        }
    }
}

/// The error for a file whose rows do not begin within [`crate::limits::MAX_HEADER_BYTES`]: the
/// loader's own where the bytes read so far are already wrong (a link to /dev/zero fails at
/// 1:1), else one at the point where reading stopped.
fn header_too_long(head: &[u8], source: &str) -> Error {
    match Loader::new(head, source).load() {
        Err(error @ Error::Parse { line, column, .. })
            if (line, column) != line_column(head, head.len()) =>
        {
            error
        }
        _ => {
            let (line, column) = line_column(head, head.len());
            Error::Parse {
                path: source.to_string(),
                line,
                column,
                message: format!(
                    "no MOTION rows within the first {} MiB; a hierarchy is never this long",
                    crate::limits::MAX_HEADER_BYTES >> 20
                ),
            }
        }
    }
}

/// Finds where the MOTION rows begin while the head of a file streams in: the start of the line
/// after `MOTION`, `Frames: N` and `Frame Time: T`, read word by word as the loader reads them.
/// It settles what it has seen: a later call starts at the last `MOTION` whose header was cut
/// short by the end of the bytes, or where the last search for `MOTION` ended.
#[derive(Default)]
struct HeaderScan {
    /// No `MOTION` that matters starts before this.
    from: usize,
    /// Bytes looked at so far, counting looks again (what the tests bound).
    scanned: usize,
}

/// What followed a `MOTION`.
enum AfterMotion {
    /// The rows begin here.
    Rows(usize),
    /// The bytes ended first.
    CutShort,
    /// Not a MOTION header (a joint's name, or a malformed header the loader will report).
    Other,
}

impl HeaderScan {
    fn rows_start(&mut self, head: &[u8]) -> Option<usize> {
        loop {
            let motion = self.find_motion(head)?;
            match self.after_motion(head, motion + 6) {
                AfterMotion::Rows(start) => return Some(start),
                AfterMotion::CutShort => {
                    self.from = motion;
                    return None;
                }
                AfterMotion::Other => self.from = motion + 6,
            }
        }
    }

    /// The next word `MOTION` (any case) from `self.from`, standing alone between separators.
    /// When there is none yet, `self.from` moves to where one could still start.
    fn find_motion(&mut self, head: &[u8]) -> Option<usize> {
        let mut at = self.from;
        while at + 6 <= head.len() {
            self.scanned += 1;
            if head[at..at + 6].eq_ignore_ascii_case(b"MOTION")
                && (at == 0 || is_space(head[at - 1]) || head[at - 1] == b'}')
            {
                match head.get(at + 6) {
                    Some(&b) if is_space(b) => return Some(at),
                    Some(_) => {}
                    // Undecided until the next byte arrives.
                    None => break,
                }
            }
            at += 1;
        }
        self.from = at;
        None
    }

    /// Reads `Frames: N Frame Time: T` and the end of that line from `at`, as `Loader::load_motion`
    /// reads them.
    fn after_motion(&mut self, head: &[u8], mut at: usize) -> AfterMotion {
        let mut words: Vec<&[u8]> = Vec::with_capacity(8);
        loop {
            while at < head.len() && is_space(head[at]) {
                at += 1;
                self.scanned += 1;
            }
            let start = at;
            while at < head.len() && !is_space(head[at]) {
                at += 1;
                self.scanned += 1;
            }
            if at == head.len() {
                return AfterMotion::CutShort;
            }
            words.push(&head[start..at]);
            match motion_header(&words) {
                Some(true) => break,
                Some(false) => return AfterMotion::Other,
                None => {}
            }
        }
        // Only blanks may follow on the line; the rows start on the next one.
        while at < head.len() && matches!(head[at], b' ' | b'\t') {
            at += 1;
            self.scanned += 1;
        }
        match (head.get(at), head.get(at + 1)) {
            (None, _) | (Some(b'\r'), None) => AfterMotion::CutShort,
            (Some(b'\r' | b'\n'), _) => AfterMotion::Rows(next_line_start(head, at)),
            _ => AfterMotion::Other,
        }
    }
}

/// Whether `words`, read after MOTION, are a whole `Frames: N Frame Time: T` header the loader
/// accepts (`Some(true)`), cannot become one (`Some(false)`), or may with more words (`None`).
fn motion_header(words: &[&[u8]]) -> Option<bool> {
    // `Label:`, or `Label` then `:`; moves `i` past it.
    fn label(words: &[&[u8]], i: &mut usize, text: &str) -> Option<bool> {
        let word = words.get(*i)?;
        if word.eq_ignore_ascii_case(format!("{text}:").as_bytes()) {
            *i += 1;
            return Some(true);
        }
        if !word.eq_ignore_ascii_case(text.as_bytes()) {
            return Some(false);
        }
        let colon = words.get(*i + 1)?;
        *i += 2;
        Some(*colon == b":")
    }
    let text = |word: &[u8]| std::str::from_utf8(word).ok().map(str::to_string);
    let mut i = 0;
    if !label(words, &mut i, "Frames")? {
        return Some(false);
    }
    if text(words.get(i)?)
        .and_then(|f| f.parse::<u64>().ok())
        .is_none()
    {
        return Some(false);
    }
    i += 1;
    if !words.get(i)?.eq_ignore_ascii_case(b"Frame") {
        return Some(false);
    }
    i += 1;
    if !label(words, &mut i, "Time")? {
        return Some(false);
    }
    let time = text(words.get(i)?).and_then(|t| t.parse::<f64>().ok());
    Some(time.is_some_and(|t| t.is_finite() && t >= 0.0) && i + 1 == words.len())
}

/// Where the line after the one that ends at `at` starts (past CR LF, LF or CR).
fn next_line_start(text: &[u8], at: usize) -> usize {
    match (text.get(at), text.get(at + 1)) {
        (Some(b'\r'), Some(b'\n')) => at + 2,
        (Some(b'\r' | b'\n'), _) => at + 1,
        _ => at,
    }
}

/// Parses BVH text. `source` names the input in error messages (`source:line:column: …`).
pub fn load_bytes(text: &[u8], source: &str) -> Result<Bvh, Error> {
    load_bytes_with_threads(text, source, crate::cores())
}

fn load_bytes_with_threads(text: &[u8], source: &str, threads: usize) -> Result<Bvh, Error> {
    let mut loader = Loader::new(text, source);
    let (frames, frame_time, frames_line) = match loader.load()? {
        Header::NoMotion => return Ok(loader.finish(0, 0.0, Vec::new())),
        Header::Motion {
            frames,
            frame_time,
            frames_line,
        } => (frames, frame_time, frames_line),
    };
    // The rows start on the line after the frame time's.
    let start = next_line_start(text, loader.p);
    let mut rows = RowParser::new(
        source,
        frames,
        loader.channel_count,
        frames_line,
        line_column(text, start),
        (text.len() - start) as u64,
    )
    .with_threads(threads);
    rows.feed_all_in_memory(&text[start..])?;
    loader.finish_rows(frames, frame_time, rows)
}

/// How the hierarchy part ended.
enum Header {
    /// The file ends after the hierarchy: a skeleton without frames.
    NoMotion,
    /// `Frames:` and `Frame Time:` were read; the rows start at the loader's position.
    Motion {
        frames: u64,
        frame_time: f64,
        frames_line: usize,
    },
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
    fn new(text: &'a [u8], source: &'a str) -> Loader<'a> {
        Loader {
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
        }
    }

    /// The loaded file, once its rows are read.
    fn finish(self, frames: u64, frame_time: f64, data: Vec<f32>) -> Bvh {
        let motion = Motion::new(frame_time, self.channel_count, frames as usize, data);
        Bvh {
            skeleton: Skeleton {
                joints: self.joints,
                ..Skeleton::default()
            },
            motion,
            warnings: self.warnings,
        }
    }

    /// The loaded file once every chunk of rows was fed: the rows' check, values and warnings.
    fn finish_rows(self, frames: u64, frame_time: f64, rows: RowParser) -> Result<Bvh, Error> {
        let (data, warnings) = rows.finish()?;
        let mut bvh = self.finish(frames, frame_time, data);
        bvh.warnings.extend(warnings);
        Ok(bvh)
    }

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
    /// line, trimmed, of up to [`crate::limits::MAX_NAME_BYTES`] bytes (a longer one is damage,
    /// refused rather than repeated on every line of an export): names may hold spaces, ':' or
    /// '.'. A `{` written at the end of the same line is left for the main loop.
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
        let name = line.trim_ascii();
        if let Err(why) = crate::limits::name(name.len()) {
            return Err(self.error_at(start, why));
        }
        let name = String::from_utf8_lossy(name).into_owned();
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
    fn load(&mut self) -> Result<Header, Error> {
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
                    None => Ok(Header::NoMotion),
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

    /// C++: the second half of `BVH::loadFile`: the motion section after `MOTION`. The article
    /// allocates `Frames` rows up front and then reads that many rows with fixed strides whatever
    /// the file holds; here the allocation is bounded by what the rest of the file could hold,
    /// each row must be one line with exactly one value per channel, a file that ends early is an
    /// error, and rows beyond the count are ignored with a warning.
    fn load_motion(&mut self) -> Result<Header, Error> {
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
            Some(time) if crate::limits::frame_time_in_file(time) => time,
            _ => {
                let what = format!(
                    "the frame time (seconds, a number from 0 to {})",
                    crate::limits::MAX_FRAME_TIME
                );
                return Err(self.expected(&what, time_token));
            }
        };
        self.finish_line("end of line after the frame time")?;
        let (frames_line, _) = line_column(self.text, frames_at);
        Ok(Header::Motion {
            frames,
            frame_time,
            frames_line,
        })
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

    /// What `read_head` settles on, and the bytes the scan looked at, for `bytes` read in pieces.
    fn scan(bytes: &[u8]) -> (Option<usize>, usize, usize) {
        let mut scan = HeaderScan::default();
        let (head, start) = read_head(&mut &bytes[..], bytes.len() as u64, &mut scan).unwrap();
        (start, head.len(), scan.scanned)
    }

    #[test]
    fn the_header_scan_looks_at_each_byte_a_bounded_number_of_times() {
        let rows = 600_000; // about 8 MB
        // Legal spellings the loader accepts: found in the first piece read.
        for header in [
            "MOTION\nFrames: 600000\nFrame  Time: 0.01\n",
            "MOTION\r\nFrames :\t600000\r\nFRAME TIME : 0.01\r\n",
        ] {
            let bytes = file_with(header, rows);
            let (start, held, scanned) = scan(&bytes);
            let start = start.expect(header);
            assert_eq!(&bytes[start..start + 7], b"0 1.5 -", "{header:?}");
            assert!(
                held <= 64 * 1024 && scanned <= held,
                "{header:?}: {scanned}"
            );
        }
        // Malformed, or MOTION followed by a long run of blank lines: every byte is read, and the
        // scan looks at each a few times at most (it used to look again at everything after
        // MOTION for every 64 KB read).
        let blank_lines = "\n".repeat(8 << 20);
        for header in [
            "MOTION\nFrames: 600000\nFrameTime: 0.01\n".to_string(),
            format!("MOTION{blank_lines}Frames: 600000\nFrame Time: 0.01\n"),
        ] {
            let bytes = file_with(&header, rows);
            let (start, held, scanned) = scan(&bytes);
            assert!(held >= 8 << 20);
            assert!(
                scanned <= 3 * bytes.len(),
                "{} bytes, scanned {scanned}",
                bytes.len()
            );
            if header.contains("FrameTime") {
                assert_eq!(start, None);
                assert_eq!(held, bytes.len());
            } else {
                assert_eq!(&bytes[start.unwrap()..][..7], b"0 1.5 -");
            }
        }
    }

    #[test]
    fn a_joint_named_motion_is_not_the_header() {
        let bytes = file_with("MOTION\nFrames: 2\nFrame Time: 0.5\n", 2);
        let named = String::from_utf8(bytes)
            .unwrap()
            .replace("ROOT Hips", "ROOT MOTION");
        let (start, _, _) = scan(named.as_bytes());
        assert_eq!(
            &named.as_bytes()[start.unwrap()..],
            b"0 1.5 -2.25\n1 1.5 -2.25\n"
        );
    }
}
