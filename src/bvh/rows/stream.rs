//! A file read in chunks for the row reader: buffers kept between files, each chunk cut at a
//! line end and handed to the workers in order.

use super::chunks::{CHUNK, Job, last_line_end};
use crate::io::lines::{advance, count_lines};
use std::io::Read;

/// Where the rows come from: a reader, read a chunk at a time into each thread's buffer, or text
/// already in memory, which the threads parse where it lies.
pub(super) enum Source<'a> {
    Reader(&'a mut (dyn Read + Send)),
    Memory { text: &'a [u8], at: usize },
}

/// Chunk buffers between loads, as many as the threads one load uses at most (a core each, up
/// to eight): a new buffer would cost a page fault for every 4 KB of it when first read into,
/// each load again. Each process has its own: a child forked while a parent's thread held the
/// lock would wait for it for good.
pub(super) static KEPT_BUFFERS: crate::io::parallel::PerProcess<std::sync::Mutex<Vec<Vec<u8>>>> =
    crate::io::parallel::PerProcess::new(|| std::sync::Mutex::new(Vec::new()));

/// Buffers grown larger than this by a long line are not kept.
pub(super) const MOST_KEPT: usize = 2 * CHUNK;

/// A kept chunk buffer (or a new one), at least `length` bytes long.
pub(super) fn kept_buffer(length: usize) -> Vec<u8> {
    let mut buffer = lock(KEPT_BUFFERS.get()).pop().unwrap_or_default();
    if buffer.len() < length {
        buffer.resize(length, 0);
    }
    buffer
}

/// Gives a chunk buffer back to be kept when the worker ends, however it ends.
pub(super) struct KeptBuffer(pub(super) Vec<u8>);

impl Drop for KeptBuffer {
    fn drop(&mut self) {
        if self.0.capacity() > 0 && self.0.capacity() <= MOST_KEPT {
            let mut kept = lock(KEPT_BUFFERS.get());
            if kept.len() < crate::io::parallel::cores().clamp(1, 8) {
                kept.push(std::mem::take(&mut self.0));
            }
        }
    }
}

/// The reading side shared by the threads of `RowParser::feed_placed`.
pub(super) struct Stream<'a> {
    pub(super) input: Source<'a>,
    /// Text read after the last chunk handed out.
    pub(super) carry: Vec<u8>,
    pub(super) end_of_input: bool,
    pub(super) next_index: usize,
    /// Bytes to read at a time.
    pub(super) chunk: usize,
    /// Rows placed so far, and the room for rows.
    pub(super) placed: usize,
    pub(super) room_rows: usize,
    /// Where the next chunk starts.
    pub(super) line: usize,
    pub(super) column: usize,
    /// No more chunks: a problem was found, the room is used up, or the input ended.
    pub(super) stop: bool,
    pub(super) error: Option<std::io::Error>,
}

impl Stream<'_> {
    /// Reads the next chunk into `buffer`: the carried text, then up to a chunk's worth, cut
    /// after its last line end.
    pub(super) fn next_chunk(&mut self, buffer: &mut Vec<u8>) -> Option<Job> {
        if self.stop {
            return None;
        }
        if let Source::Memory { text, at } = &mut self.input {
            let (text, start): (&[u8], usize) = (text, *at);
            let rest = &text[start..];
            // Up to a chunk, cut after its last line end; a longer line makes the window grow.
            let mut window = self.chunk.min(rest.len());
            let cut = loop {
                if window == rest.len() {
                    break window;
                }
                match last_line_end(&rest[..window]) {
                    Some(cut) => break cut,
                    None => window = (window * 2).min(rest.len()),
                }
            };
            *at = start + cut;
            self.end_of_input = start + cut == text.len();
            return self.place(Some(start..start + cut), &rest[..cut]);
        }
        let Source::Reader(input) = &mut self.input else {
            unreachable!("memory is handled above")
        };
        let mut filled = self.carry.len();
        if buffer.len() < filled * 2 {
            buffer.resize(filled * 2, 0);
        }
        buffer[..filled].copy_from_slice(&self.carry);
        // A chunk's worth, or after a line that did not fit, the whole grown buffer.
        let mut wanted = self.chunk.min(buffer.len());
        let cut = loop {
            while !self.end_of_input && filled < wanted {
                match input.read(&mut buffer[filled..]) {
                    Ok(0) => self.end_of_input = true,
                    Ok(read) => filled += read,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                    Err(e) => {
                        self.error = Some(e);
                        self.stop = true;
                        return None;
                    }
                }
            }
            if self.end_of_input {
                break filled;
            }
            match last_line_end(&buffer[..filled]) {
                Some(cut) => break cut,
                None => {
                    buffer.resize(buffer.len().max(1) * 2, 0);
                    wanted = buffer.len();
                }
            }
        };
        self.carry.clear();
        self.carry.extend_from_slice(&buffer[cut..filled]);
        self.place(None, &buffer[..cut])
    }

    /// Places the chunk `text` (at `range` of the memory if it is there): counts its lines,
    /// which bound its rows.
    pub(super) fn place(
        &mut self,
        range: Option<std::ops::Range<usize>>,
        text: &[u8],
    ) -> Option<Job> {
        let cut = text.len();
        if cut == 0 {
            self.stop = true;
            return None;
        }
        let (breaks, since) = count_lines(text);
        let bound = breaks + usize::from(since > 0);
        let job = Job {
            index: self.next_index,
            length: cut,
            range,
            line: self.line,
            column: self.column,
            placed: self.placed,
            bound,
            limit: bound.min(self.room_rows - self.placed),
        };
        self.next_index += 1;
        self.placed += job.limit;
        (self.line, self.column) = advance((self.line, self.column), (breaks, since));
        self.stop = self.placed == self.room_rows || self.end_of_input;
        Some(job)
    }
}

/// Takes a lock; a thread that panicked while holding it left nothing half done that matters
/// here (the caller reports the first problem in file order), so a poisoned lock is taken too.
pub(super) fn lock<T>(mutex: &std::sync::Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}
