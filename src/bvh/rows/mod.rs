//! The MOTION rows, read in chunks that end at line ends, the chunks parsed on every core.
//!
//! C++: the row loop at the end of `BVH::loadFile`. The article reads `Frames` rows with fixed
//! strides from a buffer holding the whole file. Here the rows arrive in pieces (a file is never
//! held whole), the cores take the pieces in turn and parse them without a `String` per number,
//! and every error still names its exact line and column.
//!
//! Two readers give the same values, bit for bit, and the same errors (a test runs both on every
//! file): [`read_rows_simple`], the article's few lines in plain Rust, one line and one word at a
//! time, which a student reads beside the article; and the engine, which the loader runs:
//! `number` reads one number as `(float)atof` does; `scan` finds the numbers of a piece of text,
//! row by row, 64 bytes at a time; this module feeds the pieces to the cores and puts their rows
//! in order ([`RowParser`]).

use crate::io::error::Error;
use crate::io::lines::{advance, count_lines, is_line_end};
use std::io::Read;

/// The smallest chunk: a small input is cut into about eight chunks, but not smaller ones.
const SMALLEST_CHUNK: usize = 64 * 1024;

/// The `room` of an input whose length is not known up front (a pipe, a device).
pub const UNKNOWN_ROOM: u64 = u64::MAX;

/// Values reserved up front for an input of unknown length (64 MB of `f32`).
const UNKNOWN_ROOM_VALUES: u64 = 16 << 20;

mod chunks;
mod ending;
mod located;
mod number;
mod scan;
mod simple;
#[cfg(target_arch = "x86_64")]
mod wide;
mod words;

pub use chunks::{CHUNK, last_line_end};
use ending::{Ending, nul_after_the_rows};
use located::Located;
use number::is_blank;
pub use number::parse_number;
pub use simple::read_rows_simple;

/// Makes every later load read its rows one number at a time (`rows/scan.rs`) even where the
/// CPU has AVX-512, or lets it use AVX-512 again: for benchmarks of the reader machines without
/// AVX-512 run.
pub fn read_one_at_a_time(on: bool) {
    words::ONE_AT_A_TIME.store(on, std::sync::atomic::Ordering::Relaxed);
}

/// Which reader the MOTION rows go through on this machine, in words (`bvhview --version` says
/// it): machines differ, and one without AVX-512 never runs `rows/wide.rs`.
pub fn row_reader() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    if wide::available() {
        return "AVX-512, eight numbers at a time (rows/wide.rs)";
    }
    if words::ONE_AT_A_TIME.load(std::sync::atomic::Ordering::Relaxed) {
        return "one number at a time (rows/scan.rs), AVX-512 turned off (read_one_at_a_time)";
    }
    "one number at a time (rows/scan.rs); this CPU has no AVX-512, so rows/wide.rs never runs"
}
use scan::parse_rows;
use words::SliceSink;

mod stream;

use stream::{KeptBuffer, Source, Stream, kept_buffer, lock};

/// The result's spare room, written by several threads at once (each in its own stretch).
#[derive(Clone, Copy)]
struct Room(*mut std::mem::MaybeUninit<f32>);

impl Room {
    /// # Safety
    /// `start + length` is within the capacity, and no one else uses that stretch meanwhile.
    #[allow(clippy::mut_from_ref)]
    unsafe fn stretch(&self, start: usize, length: usize) -> &mut [std::mem::MaybeUninit<f32>] {
        // SAFETY: as the caller promises.
        unsafe { std::slice::from_raw_parts_mut(self.0.add(start), length) }
    }
}

// SAFETY: the threads write disjoint stretches; see `RowParser::feed_placed`.
unsafe impl Send for Room {}
// SAFETY: as for Send: shared only to hand each thread its own stretch.
unsafe impl Sync for Room {}

/// What a thread made of a chunk.
struct Chunk {
    index: usize,
    placed: usize,
    rows: usize,
    /// Values written from its place on (its rows', and part of a row with a problem).
    written: usize,
    problem: Option<Located>,
    /// The text beyond the rows the chunk could write, with its line and column.
    rest: Option<(Vec<u8>, usize, usize)>,
}

/// Collects `frames` rows of `width` values from text fed in line-aligned chunks.
///
/// ```
/// use bvhview::bvh::rows::RowParser;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// // Two rows of three values, starting at line 4 column 1 (`Frames:` is on line 2).
/// let text = b"1 2 3\n4 5 6\n";
/// let mut parser = RowParser::new("inline", 2, 3, 2, (4, 1), text.len() as u64);
/// parser.feed(text)?;
/// let (values, warnings) = parser.finish()?;
/// assert_eq!(values, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
/// assert!(warnings.is_empty());
/// # Ok(())
/// # }
/// ```
pub struct RowParser {
    source: String,
    frames: u64,
    width: usize,
    frames_line: usize,
    rows: u64,
    data: Vec<f32>,
    /// The line the next chunk starts on, and the column after the text so far.
    line: usize,
    column: usize,
    /// The first ignored row's line, and how many rows are ignored.
    extra: Option<(usize, usize)>,
    /// Line ends seen, for a skeleton without channels.
    line_ends: u64,
    /// The text fed last ended inside a line past the rows that is already counted in `extra`
    /// (past the rows, text is fed without waiting for whole lines).
    in_extra_line: bool,
    threads: usize,
    /// Bytes read at a time: a megabyte, less for a small input (so that it is still split).
    chunk: usize,
    /// Bytes of input after the rows' start.
    input_left: u64,
    /// Rows moved down after the parallel pass (only blank lines should cause any).
    rows_moved: usize,
}

impl RowParser {
    /// The first chunk starts at `(start_line, start_column)`; `room` is the bytes left in the input,
    /// which bounds the allocation whatever `Frames:` says, or [`UNKNOWN_ROOM`] for a pipe or a
    /// device, whose length says nothing.
    pub fn new(
        source: &str,
        frames: u64,
        width: usize,
        frames_line: usize,
        (start_line, start_column): (usize, usize),
        room: u64,
    ) -> RowParser {
        // Each value takes at least two bytes ("0 "), so no more than this can be in the file.
        // Of an input of unknown length only a first stretch is reserved; the rest grows as read.
        let possible = if room == UNKNOWN_ROOM {
            UNKNOWN_ROOM_VALUES
        } else {
            room / 2 + 1
        };
        let wanted = frames.saturating_mul(width as u64).min(possible);
        let threads = crate::io::parallel::cores().clamp(1, 8);
        let data = Vec::with_capacity(wanted as usize);
        RowParser {
            source: source.to_string(),
            frames,
            width,
            frames_line,
            rows: 0,
            data,
            line: start_line,
            column: start_column,
            extra: None,
            line_ends: 0,
            in_extra_line: false,
            threads,
            chunk: (room / 8)
                .clamp(SMALLEST_CHUNK as u64, CHUNK as u64)
                .min(room.saturating_add(1)) as usize,
            input_left: room,
            rows_moved: 0,
        }
    }

    /// Counts the rows beyond `Frames:` in `chunk` from `from` on: the lines that are not blank.
    /// A NUL byte among them is an error. `chunk` may end inside a line (past the rows nothing
    /// waits for a whole line), but not between the CR and the LF of a CR LF.
    fn count_extra(&mut self, chunk: &[u8], from: usize) -> Result<(), Error> {
        let mut line = self.line + count_lines(&chunk[..from]).0;
        let mut p = from;
        // The rest of a line counted in the text fed before.
        let mut counted = std::mem::take(&mut self.in_extra_line) && from == 0;
        while p < chunk.len() {
            let b = chunk[p];
            if b == b'\n' || (b == b'\r' && chunk.get(p + 1) != Some(&b'\n')) {
                line += 1;
                p += 1;
                counted = false;
            } else if is_blank(b) || b == b'\r' {
                p += 1;
            } else {
                if !counted {
                    self.extra.get_or_insert((line, 0)).1 += 1;
                    counted = true;
                }
                while p < chunk.len() && !is_line_end(chunk[p]) {
                    if chunk[p] == 0 {
                        let at = advance((self.line, self.column), count_lines(&chunk[..p]));
                        return Err(nul_after_the_rows(&self.source, at));
                    }
                    p += 1;
                }
            }
        }
        self.in_extra_line = counted;
        Ok(())
    }

    /// Parses on at most `threads` threads (the default is every core).
    pub fn with_threads(mut self, threads: usize) -> RowParser {
        self.threads = threads.clamp(1, 8);
        self
    }

    /// Whether every row has been read (or there are no values to read): what comes next is
    /// only counted.
    fn past_the_rows(&self) -> bool {
        self.width == 0 || self.rows >= self.frames
    }

    /// Parses one chunk that ends at a line end (or at the end of the input; past the rows, it may
    /// end anywhere but between the CR and the LF of a CR LF).
    pub fn feed(&mut self, chunk: &[u8]) -> Result<(), Error> {
        // Nothing to parse (a file that ends right after `Frame Time:`): no parts to split into.
        if chunk.is_empty() {
            return Ok(());
        }
        let lines = count_lines(chunk);
        if self.width == 0 {
            self.line_ends += lines.0 as u64;
        } else if self.rows >= self.frames {
            self.count_extra(chunk, 0)?;
        } else {
            self.feed_rows(chunk)?;
        }
        (self.line, self.column) = advance((self.line, self.column), lines);
        Ok(())
    }

    /// Parses the rows of a chunk in order. This reads what the parallel pass leaves (see
    /// [`RowParser::feed_all`]), usually nothing.
    fn feed_rows(&mut self, chunk: &[u8]) -> Result<(), Error> {
        let needed = (self.frames - self.rows).min(usize::MAX as u64) as usize;
        let part = parse_rows(chunk, self.width, needed, &mut self.data);
        let first_row = self.rows;
        self.rows += part.rows as u64;
        if let Some((row, problem)) = part.problem {
            let located = Located::new(chunk, (self.line, self.column), row, problem);
            return Err(located.into_error(&self.source, self.width, first_row as usize));
        }
        if part.rows == needed {
            self.count_extra(chunk, part.end)?;
        }
        Ok(())
    }

    /// Reads and parses all the rows: `carry` (rows already read) and then everything `input`
    /// holds. `io_error` names the input in a read error.
    ///
    /// Every thread runs the same loop: under a lock it reads the next chunk (cut at a line end)
    /// and counts its lines, which places the chunk's rows in the result (each line at most one
    /// row); then it parses the chunk into that place while another thread reads. No thread waits
    /// for another at every chunk, and the reading overlaps the parsing. What the placing cannot
    /// cover (rows after `Frames`, or a file with blank lines that used up the room) is read
    /// after them in order.
    pub fn feed_all(
        &mut self,
        carry: &[u8],
        input: &mut (dyn Read + Send),
        io_error: &dyn Fn(std::io::Error) -> Error,
    ) -> Result<(), Error> {
        let mut carry = carry.to_vec();
        if self.width > 0 && self.rows == 0 {
            let (rest, after, _) = self.feed_placed(Source::Reader(input), carry, io_error)?;
            carry = after;
            if let Some((text, line, column)) = rest {
                (self.line, self.column) = (line, column);
                self.feed(&text)?;
            }
        }
        self.feed_in_order(carry, input, io_error)
    }

    /// [`RowParser::feed_all`] for text already in memory: the threads parse it where it lies,
    /// with no copy and no buffer of their own.
    pub fn feed_all_in_memory(&mut self, text: &[u8]) -> Result<(), Error> {
        // Memory is never read through a reader, so no read can fail.
        let source = self.source.clone();
        let never = move |e| Error::io(std::path::Path::new(&source), e);
        let mut rest_of_text: &[u8] = text;
        if self.width > 0 && self.rows == 0 {
            let source = Source::Memory { text, at: 0 };
            let (rest, _, at) = self.feed_placed(source, Vec::new(), &never)?;
            if let Some((rest, line, column)) = rest {
                (self.line, self.column) = (line, column);
                self.feed(&rest)?;
            }
            rest_of_text = &text[at..];
        }
        self.feed_in_order(rest_of_text.to_vec(), &mut std::io::empty(), &never)
    }

    /// The parallel pass of [`RowParser::feed_all`]: the rows placed by line counts. Returns the
    /// text left in the last chunk (beyond the rows placed, with its line and column) and the
    /// text read after the last chunk.
    #[allow(clippy::type_complexity)]
    fn feed_placed(
        &mut self,
        input: Source<'_>,
        carry: Vec<u8>,
        io_error: &dyn Fn(std::io::Error) -> Error,
    ) -> Result<(Option<(Vec<u8>, usize, usize)>, Vec<u8>, usize), Error> {
        let memory = match input {
            Source::Memory { text, .. } => Some(text),
            Source::Reader(_) => None,
        };
        let width = self.width;
        let room_rows =
            (self.frames.min(usize::MAX as u64) as usize).min(self.data.capacity() / width);
        let stream = std::sync::Mutex::new(Stream {
            input,
            carry,
            end_of_input: false,
            next_index: 0,
            chunk: self.chunk,
            placed: 0,
            room_rows,
            line: self.line,
            column: self.column,
            stop: room_rows == 0,
            error: None,
        });
        let room = Room(self.data.spare_capacity_mut().as_mut_ptr());
        let done = std::sync::Mutex::new(Vec::<Chunk>::new());
        let chunk_size = self.chunk;
        let work = || {
            let mut buffer = KeptBuffer(match memory {
                Some(_) => Vec::new(),
                None => kept_buffer(chunk_size + chunk_size / 4),
            });
            loop {
                let Some(job) = lock(&stream).next_chunk(&mut buffer.0) else {
                    return;
                };
                let text = match (memory, &job.range) {
                    (Some(memory), Some(range)) => &memory[range.clone()],
                    _ => &buffer.0[..job.length],
                };
                // SAFETY: each job's stretch starts where the previous job's ends and all of them
                // end by `room_rows`, inside the capacity; the result is not touched until every
                // worker has ended.
                let stretch = unsafe { room.stretch(job.placed * width, job.limit * width) };
                let mut sink = SliceSink {
                    room: stretch,
                    written: 0,
                };
                let part = parse_rows(text, width, job.limit, &mut sink);
                let mut chunk = Chunk {
                    index: job.index,
                    placed: job.placed,
                    rows: part.rows,
                    written: sink.written,
                    problem: None,
                    rest: None,
                };
                let start = (job.line, job.column);
                if let Some((row, problem)) = part.problem {
                    chunk.problem = Some(Located::new(text, start, row, problem));
                    lock(&stream).stop = true;
                } else if part.rows == job.limit && job.limit < job.bound {
                    let (line, column) = advance(start, count_lines(&text[..part.end]));
                    chunk.rest = Some((text[part.end..].to_vec(), line, column));
                }
                lock(&done).push(chunk);
            }
        };
        // No more threads than chunks.
        let threads = self
            .threads
            .min(1 + (self.input_left / self.chunk as u64) as usize);
        crate::io::parallel::on_threads(threads, work);
        let stream = stream.into_inner().unwrap_or_else(|e| e.into_inner());
        if let Some(error) = stream.error {
            return Err(io_error(error));
        }
        let mut chunks = done.into_inner().unwrap_or_else(|e| e.into_inner());
        chunks.sort_by_key(|c| c.index);
        // In file order: the first problem wins; rows placed after blank lines move down.
        let mut rows = 0;
        let mut rest = None;
        for chunk in chunks {
            // Every chunk before this one has ended, so `rows` is where its rows begin.
            if let Some(problem) = chunk.problem {
                return Err(problem.into_error(&self.source, width, rows));
            }
            // What `set_len` below relies on: the chunk's rows were all written.
            // Checked in release builds too: a wrong count here would expose uninitialised memory.
            assert!(chunk.written >= chunk.rows * width, "chunk {}", chunk.index);
            if chunk.placed != rows {
                self.rows_moved += chunk.rows;
                self.data.spare_capacity_mut().copy_within(
                    chunk.placed * width..(chunk.placed + chunk.rows) * width,
                    rows * width,
                );
            }
            rows += chunk.rows;
            rest = chunk.rest.or(rest);
        }
        assert!(rows * width <= self.data.capacity());
        // SAFETY: the first `rows` rows of the spare room were written by the workers (each
        // wrote its rows front to back from its place) and moved down to follow each other.
        unsafe { self.data.set_len(rows * width) };
        self.rows = rows as u64;
        (self.line, self.column) = (stream.line, stream.column);
        let at = match stream.input {
            Source::Memory { at, .. } => at,
            Source::Reader(_) => 0,
        };
        Ok((rest, stream.carry, at))
    }

    /// The rest of the rows in order, one chunk at a time.
    fn feed_in_order(
        &mut self,
        carry: Vec<u8>,
        input: &mut (dyn Read + Send),
        io_error: &dyn Fn(std::io::Error) -> Error,
    ) -> Result<(), Error> {
        let mut buffer = carry;
        let mut filled = buffer.len();
        buffer.resize((self.chunk + self.chunk / 4).max(filled * 2), 0);
        // Read at least this far before looking for a line end: a chunk, or after a line that
        // did not fit, the whole grown buffer.
        let mut wanted = self.chunk.min(buffer.len());
        loop {
            let mut end_of_input = false;
            while filled < wanted {
                let read = input.read(&mut buffer[filled..]).map_err(io_error)?;
                if read == 0 {
                    end_of_input = true;
                    break;
                }
                filled += read;
            }
            if end_of_input {
                return self.feed(&buffer[..filled]);
            }
            match last_line_end(&buffer[..filled]) {
                Some(cut) => {
                    self.feed(&buffer[..cut])?;
                    buffer.copy_within(cut..filled, 0);
                    filled -= cut;
                    wanted = self.chunk.min(buffer.len()).max(1);
                }
                // Past the rows, nothing waits for a whole line: what was read is counted now
                // (all but a last CR, whose LF may come next), and the buffer does not grow.
                None if self.past_the_rows() && filled > 1 => {
                    let cut = filled - usize::from(buffer[filled - 1] == b'\r');
                    self.feed(&buffer[..cut])?;
                    buffer.copy_within(cut..filled, 0);
                    filled -= cut;
                    wanted = self.chunk.min(buffer.len()).max(2);
                }
                // A line longer than what was read: make room and read on.
                None => {
                    buffer.resize(buffer.len() * 2, 0);
                    wanted = buffer.len();
                }
            }
        }
    }

    /// Checks that every frame arrived; returns the values and the warnings.
    pub fn finish(self) -> Result<(Vec<f32>, Vec<String>), Error> {
        let ending = Ending {
            rows: if self.width == 0 {
                self.line_ends
            } else {
                self.rows
            },
            at: (self.line, self.column),
            extra: self.extra,
        };
        ending.check(&self.source, self.frames, self.frames_line, self.width)?;
        Ok((self.data, ending.warnings(self.frames, self.frames_line)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows are placed by counting lines, so without blank lines none has to move afterwards.
    #[test]
    fn rows_without_blank_lines_are_parsed_in_place() {
        for newline in ["\n", "\r\n", "\r"] {
            let row = format!("1 2.5 -3{newline}");
            let rows = row.repeat(4 * SMALLEST_CHUNK / row.len());
            let frames = (4 * SMALLEST_CHUNK / row.len()) as u64;
            let mut parser =
                RowParser::new("t.bvh", frames, 3, 1, (2, 1), rows.len() as u64).with_threads(2);
            parser.chunk = SMALLEST_CHUNK;
            parser.input_left = rows.len() as u64;
            parser
                .feed_all(&[], &mut rows.as_bytes(), &|e| {
                    Error::io(std::path::Path::new("t"), e)
                })
                .unwrap();
            assert_eq!(parser.rows, frames);
            assert_eq!(parser.rows_moved, 0, "{newline:?}");
            let (data, _) = parser.finish().unwrap();
            assert_eq!(&data[data.len() - 3..], [1.0, 2.5, -3.0]);
        }
    }
}
