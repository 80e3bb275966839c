//! The MOTION text cut into chunks that end at line ends, and the chunk a thread is handed.

/// Bytes of MOTION text handed to the parser at a time.
pub const CHUNK: usize = 1 << 20;

/// The last place a chunk may end: after an LF, or after a CR that is not the buffer's last byte
/// (it might be followed by an LF in the next read). `None` if there is none.
pub fn last_line_end(buffer: &[u8]) -> Option<usize> {
    let last = buffer.len().checked_sub(1)?;
    for i in (0..=last).rev() {
        match buffer[i] {
            b'\n' => return Some(i + 1),
            b'\r' if i < last => return Some(i + 1),
            _ => {}
        }
    }
    None
}

/// A chunk handed to a thread: its text is in the thread's buffer, or at `range` of the text
/// held in memory.
pub(super) struct Job {
    pub(super) index: usize,
    pub(super) length: usize,
    pub(super) range: Option<std::ops::Range<usize>>,
    /// Where its text starts.
    pub(super) line: usize,
    pub(super) column: usize,
    /// The row its rows go to, how many lines it has (at most that many rows), and how many rows
    /// it may write (fewer only in the last chunk, at the end of the room).
    pub(super) placed: usize,
    pub(super) bound: usize,
    pub(super) limit: usize,
}
