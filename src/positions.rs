//! World positions of every joint and End Site per frame, as CSV or JSON (`bvhview positions`).

use crate::io::error::Error;
use crate::model::motion::Motion;
use crate::model::pose::{FkPlan, FkScratch, LANES, OffsetMode, world_matrices};
use crate::model::skeleton::export_name;
use crate::model::skeleton::{Skeleton, Source};
use glam::Vec3;
use std::io::{self, Write};
use std::ops::Range;
use std::sync::Mutex;

/// The text a positions export writes.
///
/// ```
/// use bvhview::{Take, positions::{PositionsFormat, PositionsOptions, write_positions}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let options = PositionsOptions { format: PositionsFormat::Json, ..PositionsOptions::default() };
/// let mut json = Vec::new();
/// write_positions(&mut json, &take.skeleton, &take.motion, 0..1, &options).unwrap();
/// assert!(json.starts_with(b"{\"frame_time\":"));
/// assert_eq!(PositionsOptions::default().format, PositionsFormat::Csv);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PositionsFormat {
    /// `frame,joint,x,y,z`, one joint per line.
    #[default]
    Csv,
    /// `{"frame_time":…,"joints":[…],"frames":[{"frame":0,"positions":[[x,y,z],…]},…]}`.
    Json,
}

/// Options of a positions export.
///
/// ```
/// use bvhview::{Take, positions::{PositionsOptions, write_positions}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// // Frame 0 in metres from centimetres, z negated for a left-handed engine.
/// let options = PositionsOptions { scale: 0.01, left_handed: true, ..Default::default() };
/// let mut csv = Vec::new();
/// write_positions(&mut csv, &take.skeleton, &take.motion, 0..1, &options).unwrap();
/// let text = String::from_utf8(csv).unwrap();
/// assert_eq!(text.lines().next(), Some("frame,joint,x,y,z"));
/// // The root 30 units up: 0.3 m as the nearest f32 prints, z (0) negated.
/// assert_eq!(text.lines().nth(1), Some("0,Hips,0,0.29999998,-0"));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct PositionsOptions {
    /// CSV or JSON.
    pub format: PositionsFormat,
    /// How position channels meet the OFFSET.
    pub offset_mode: OffsetMode,
    /// Negate z, turning the right-handed BVH frame into a left-handed one (Direct3D).
    pub left_handed: bool,
    /// Multiplies every coordinate (1 keeps the file's units).
    pub scale: f32,
}

impl Default for PositionsOptions {
    fn default() -> PositionsOptions {
        PositionsOptions {
            format: PositionsFormat::Csv,
            offset_mode: OffsetMode::Replace,
            left_handed: false,
            scale: 1.0,
        }
    }
}

/// Parses a frame range: `N`, `A..B` (B excluded), `A..=B`, `A..` or `..B`, checked against
/// `frame_count`. An empty take has one frame, the rest pose.
pub fn parse_frames(text: &str, frame_count: usize) -> Result<Range<usize>, Error> {
    let last = frame_count.saturating_sub(1);
    let bad = || {
        Error::invalid(
            "frames",
            text,
            format!("expected N, A..B (B left out), A..=B, A.. or ..B within frames 0 to {last}"),
        )
    };
    let number = |s: &str| -> Result<usize, Error> { s.trim().parse().map_err(|_| bad()) };
    let range = if let Some((a, b)) = text.split_once("..=") {
        let start = if a.is_empty() { 0 } else { number(a)? };
        start..number(b)?.checked_add(1).ok_or_else(bad)?
    } else if let Some((a, b)) = text.split_once("..") {
        let start = if a.is_empty() { 0 } else { number(a)? };
        let end = if b.is_empty() {
            frame_count
        } else {
            number(b)?
        };
        start..end
    } else {
        let n = number(text)?;
        n..n.checked_add(1).ok_or_else(bad)?
    };
    if range.start >= range.end {
        return Err(Error::invalid(
            "frames",
            text,
            "no frames: A..B leaves B out (for frame A alone, give A or A..=A)",
        ));
    }
    if range.end > frame_count {
        return Err(bad());
    }
    Ok(range)
}

/// A position that is not a finite number (offsets and values near the float limit, or a large
/// `--scale`, overflow): the export stops rather than write `inf` or `NaN`, which CSV and JSON
/// readers refuse. It travels inside the `io::Error` that [`write_positions`] returns.
///
/// ```
/// use bvhview::{Take, positions::{PositionsOptions, not_finite, write_positions}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let options = PositionsOptions { scale: f32::MAX, ..Default::default() };
/// let mut out = Vec::new();
/// let error = write_positions(&mut out, &take.skeleton, &take.motion, 0..1, &options).unwrap_err();
/// let why = not_finite(&error).expect("a position overflowed");
/// assert!(why.to_string().starts_with("frame 0, Hips: the position (0, inf, 0) is not a finite"));
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct NotFinite(pub String);

impl std::fmt::Display for NotFinite {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for NotFinite {}

/// The [`NotFinite`] inside an error of [`write_positions`], if that is what it is.
pub fn not_finite(error: &io::Error) -> Option<&NotFinite> {
    error.get_ref()?.downcast_ref::<NotFinite>()
}

/// The points an export lists, as (name, joint whose world position it is). BVH: every joint
/// and End Site. ASF: the root, then the end point of every bone, named by the bone (the end
/// of a bone is where its children, or its End Site, start).
pub fn export_points(skeleton: &Skeleton) -> Vec<(String, usize)> {
    match skeleton.source {
        Source::Bvh => (0..skeleton.joints.len())
            .map(|i| (export_name(skeleton, i), i))
            .collect(),
        Source::Acclaim => skeleton
            .joints
            .iter()
            .enumerate()
            .filter(|(_, j)| !j.end_site)
            .map(|(i, j)| match (j.parent, j.children.first()) {
                (Some(_), Some(&end)) => (j.name.clone(), end),
                _ => (j.name.clone(), i),
            })
            .collect(),
    }
}

/// Frames formatted per block; blocks go to the cores in turn and are written in order.
const BLOCK: usize = 2048;

/// Writes the positions of `frames` (indices into `motion`; for a take without frames, pass
/// `0..1` to get the rest pose).
pub fn write_positions<W: Write + Send>(
    out: &mut W,
    skeleton: &Skeleton,
    motion: &Motion,
    frames: Range<usize>,
    options: &PositionsOptions,
) -> io::Result<()> {
    write_with(out, skeleton, motion, frames, options, format_block_fast)
}

/// [`write_positions`] with the plain formatter (`format_block`) in place of the fast one:
/// the reference a test holds the fast one to, byte for byte.
pub fn write_positions_plain<W: Write + Send>(
    out: &mut W,
    skeleton: &Skeleton,
    motion: &Motion,
    frames: Range<usize>,
    options: &PositionsOptions,
) -> io::Result<()> {
    write_with(out, skeleton, motion, frames, options, |job, frames, _| {
        let text = format_block(job, frames)?;
        let end = text.len();
        Ok(Block { text, end })
    })
}

/// What every block of one export shares.
struct Job<'a> {
    skeleton: &'a Skeleton,
    motion: &'a Motion,
    plan: FkPlan,
    points: Vec<(String, usize)>,
    /// The points' names as CSV fields.
    names: Vec<String>,
    /// The first frame written (JSON puts a comma before every later one).
    first: usize,
    options: &'a PositionsOptions,
}

/// A block's text: `text[..end]` (the buffer is longer, and is used again for a later block).
struct Block {
    text: Vec<u8>,
    end: usize,
}

/// Formats a block of frames into a spare buffer (empty if none is left over).
type Formatter = fn(&Job, Range<usize>, Vec<u8>) -> Result<Block, NotFinite>;

fn write_with<W: Write + Send>(
    out: &mut W,
    skeleton: &Skeleton,
    motion: &Motion,
    frames: Range<usize>,
    options: &PositionsOptions,
    formatter: Formatter,
) -> io::Result<()> {
    let points = export_points(skeleton);
    // Held back until the first frames are known to be finite, so that a refused export of a
    // short take writes nothing at all.
    let mut header = Vec::new();
    match options.format {
        PositionsFormat::Csv => writeln!(header, "frame,joint,x,y,z")?,
        PositionsFormat::Json => {
            write!(
                header,
                "{{\"frame_time\":{},\"joints\":[",
                motion.frame_time
            )?;
            for (i, (name, _)) in points.iter().enumerate() {
                let comma = if i > 0 { "," } else { "" };
                write!(header, "{comma}{}", json_string(name))?;
            }
            write!(header, "],\"frames\":[")?;
        }
    }
    let job = Job {
        skeleton,
        motion,
        plan: FkPlan::new(skeleton, options.offset_mode),
        names: points.iter().map(|(name, _)| csv_field(name)).collect(),
        points,
        first: frames.start,
        options,
    };
    let threads = crate::io::parallel::cores().clamp(1, 8);
    // Blocks of frames formatted on every core and written in order as they are ready; a few
    // blocks at most wait for an earlier one.
    let blocks: Vec<Range<usize>> = frames
        .clone()
        .step_by(BLOCK)
        .map(|start| start..(start + BLOCK).min(frames.end))
        .collect();
    // Buffers written out go back here for later blocks: a fresh one costs a page fault every
    // 4 KB, as much as formatting a tenth of it.
    let spare: Mutex<Vec<Vec<u8>>> = Mutex::new(Vec::new());
    let take_spare = || spare.lock().ok().and_then(|mut s| s.pop());
    let mut failure = None;
    crate::io::parallel::map_in_order(
        blocks.len(),
        threads,
        2 * threads,
        |k| formatter(&job, blocks[k].clone(), take_spare().unwrap_or_default()),
        |_, block| {
            let written = block
                .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))
                .and_then(|block| {
                    out.write_all(&std::mem::take(&mut header))?;
                    out.write_all(&block.text[..block.end])?;
                    if let Ok(mut spare) = spare.lock() {
                        spare.push(block.text);
                    }
                    Ok(())
                });
            written.map_err(|e| failure = Some(e)).is_ok()
        },
    );
    if let Some(error) = failure {
        return Err(error);
    }
    out.write_all(&header)?;
    if options.format == PositionsFormat::Json {
        writeln!(out, "]}}")?;
    }
    Ok(())
}

/// The shortest text that reads back as the same f32, as `ryu` wrote it (which is what exports
/// have always held: `1e20`, not `1e+20`), without `.0` on whole numbers, so 30 prints as `30`.
/// The digits come from `zmij`, twice as fast as `ryu`; a test holds the two equal.
///
/// ```
/// use bvhview::positions::Shortest;
///
/// let mut shortest = Shortest::default();
/// assert_eq!(shortest.format(30.0), b"30");
/// assert_eq!(shortest.format(0.1), b"0.1");
/// assert_eq!(shortest.format(1e20), b"1e20");
/// assert_eq!(shortest.format(-2.5e-7), b"-2.5e-7");
/// ```
pub struct Shortest {
    digits: zmij::Buffer,
    /// The text of a number whose exponent lost its `+`.
    fixed: [u8; 24],
}

impl Default for Shortest {
    fn default() -> Shortest {
        Shortest {
            digits: zmij::Buffer::new(),
            fixed: [0; 24],
        }
    }
}

impl Shortest {
    /// The text of a finite `value` (anything at all for a non-finite one).
    #[inline(always)]
    pub fn format(&mut self, value: f32) -> &[u8] {
        let printed = self.digits.format_finite(value).as_bytes();
        let n = printed.len();
        // An f32's exponent has one or two digits: a `+` is second or third from the end (of
        // `1e+7` at least).
        if n >= 4 && (printed[n - 2] == b'+' || printed[n - 3] == b'+') {
            let plus = if printed[n - 2] == b'+' { n - 2 } else { n - 3 };
            self.fixed[..plus].copy_from_slice(&printed[..plus]);
            self.fixed[plus..n - 1].copy_from_slice(&printed[plus + 1..]);
            return &self.fixed[..n - 1];
        }
        printed.strip_suffix(b".0").unwrap_or(printed)
    }
}

/// Appends a float as [`Shortest`] writes it.
fn push_float(text: &mut Vec<u8>, shortest: &mut Shortest, value: f32) {
    text.extend_from_slice(shortest.format(value));
}

/// The refusal of a position that is not finite.
fn not_finite_at(frame: usize, name: &str, p: Vec3) -> NotFinite {
    NotFinite(format!(
        "frame {frame}, {name}: the position ({}, {}, {}) is not a finite number \
         (the offsets, the values or a scale overflow)",
        p.x, p.y, p.z
    ))
}

/// The world positions of frames `start..end` (at most [`LANES`]), every joint of each in turn
/// into `batch`; a take without frames has its rest pose as its one frame.
fn positions_of<'a>(
    job: &Job<'a>,
    start: usize,
    end: usize,
    batch: &mut Vec<Vec3>,
    scratch: &mut Fk<'a>,
) {
    if job.motion.frame_count() == 0 {
        // The rest pose: OFFSETs only.
        world_matrices(
            job.skeleton,
            &[],
            job.options.offset_mode,
            &mut scratch.matrices,
        );
        batch.clear();
        batch.extend(scratch.matrices.iter().map(|m| m.w_axis.truncate()));
    } else {
        // Eight frames at a time, side by side.
        scratch.rows.clear();
        scratch
            .rows
            .extend((start..end).map(|f| job.motion.frame(f)));
        job.plan
            .positions_of_frames(&scratch.rows, batch, &mut scratch.lanes);
    }
}

/// What FK needs between batches.
#[derive(Default)]
struct Fk<'a> {
    lanes: FkScratch,
    matrices: Vec<glam::Mat4>,
    rows: Vec<&'a [f32]>,
}

/// The text of `frames`: CSV rows, or JSON frame objects (comma-led except the very first).
/// The plain formatter, beside which [`format_block_fast`] is tested.
fn format_block(job: &Job, frames: Range<usize>) -> Result<Vec<u8>, NotFinite> {
    let Job {
        skeleton,
        motion,
        points,
        names,
        first,
        options,
        ..
    } = job;
    let mut text = Vec::with_capacity(frames.len() * points.len() * 40);
    let mut shortest = Shortest::default();
    let (mut batch, mut scratch) = (Vec::new(), Fk::default());
    let z_sign = if options.left_handed { -1.0 } else { 1.0 };
    let scale = options.scale;
    let joints = skeleton.joints.len();
    for frame in frames.clone() {
        let in_batch = (frame - frames.start) % LANES;
        if motion.frame_count() == 0 || in_batch == 0 {
            let end = (frame + LANES).min(frames.end);
            positions_of(job, frame, end, &mut batch, &mut scratch);
        }
        let positions = if motion.frame_count() == 0 {
            &batch[..]
        } else {
            &batch[in_batch * joints..(in_batch + 1) * joints]
        };
        let frame_number = frame.to_string();
        for (name, joint) in points {
            let p = positions[*joint] * scale;
            if !p.is_finite() {
                return Err(not_finite_at(frame, name, p));
            }
        }
        match options.format {
            PositionsFormat::Csv => {
                for (name, &(_, joint)) in names.iter().zip(points) {
                    let p = positions[joint] * scale;
                    text.extend_from_slice(frame_number.as_bytes());
                    text.push(b',');
                    text.extend_from_slice(name.as_bytes());
                    for value in [p.x, p.y, p.z * z_sign] {
                        text.push(b',');
                        push_float(&mut text, &mut shortest, value);
                    }
                    text.push(b'\n');
                }
            }
            PositionsFormat::Json => {
                if frame > *first {
                    text.push(b',');
                }
                text.extend_from_slice(format!("{{\"frame\":{frame},\"positions\":[").as_bytes());
                for (i, &(_, joint)) in points.iter().enumerate() {
                    let p = positions[joint] * scale;
                    if i > 0 {
                        text.push(b',');
                    }
                    text.push(b'[');
                    for (k, value) in [p.x, p.y, p.z * z_sign].into_iter().enumerate() {
                        if k > 0 {
                            text.push(b',');
                        }
                        push_float(&mut text, &mut shortest, value);
                    }
                    text.push(b']');
                }
                text.extend_from_slice(b"]}");
            }
        }
    }
    Ok(text)
}

/// Text written at a cursor into a buffer kept longer than what is written, so that a short
/// piece goes in as one or two fixed-size moves instead of a call to `memcpy` (a CSV row is
/// five pieces of 2 to 12 bytes; the calls cost as much as the float formatting saved).
struct Cursor {
    bytes: Vec<u8>,
    at: usize,
}

impl Cursor {
    /// Makes sure `n` more bytes fit.
    fn room(&mut self, n: usize) {
        if self.at + n > self.bytes.len() {
            let len = (self.at + n).max(2 * self.bytes.len());
            self.bytes.resize(len, 0);
        }
    }

    #[inline(always)]
    fn byte(&mut self, byte: u8) {
        self.bytes[self.at] = byte;
        self.at += 1;
    }

    /// Copies `piece` (any length; up to 64 bytes in two to four overlapping moves).
    #[inline(always)]
    fn put(&mut self, piece: &[u8]) {
        let (at, n) = (self.at, piece.len());
        let out = &mut self.bytes;
        // Moves of integers, not of byte arrays: the compiler would merge array copies of
        // different sizes into one call to `memcpy` with the size as an argument.
        match n {
            8..=16 => {
                let (head, tail) = (load::<8>(piece, 0), load::<8>(piece, n - 8));
                store(out, at, u64::from_le_bytes(head).to_le_bytes());
                store(out, at + n - 8, u64::from_le_bytes(tail).to_le_bytes());
            }
            4..=7 => {
                let (head, tail) = (load::<4>(piece, 0), load::<4>(piece, n - 4));
                store(out, at, u32::from_le_bytes(head).to_le_bytes());
                store(out, at + n - 4, u32::from_le_bytes(tail).to_le_bytes());
            }
            1..=3 => {
                out[at] = piece[0];
                out[at + n / 2] = piece[n / 2];
                out[at + n - 1] = piece[n - 1];
            }
            0 => {}
            17..=32 => {
                let (head, tail) = (load::<16>(piece, 0), load::<16>(piece, n - 16));
                store(out, at, u128::from_le_bytes(head).to_le_bytes());
                store(out, at + n - 16, u128::from_le_bytes(tail).to_le_bytes());
            }
            _ => out[at..at + n].copy_from_slice(piece),
        }
        self.at += n;
    }

    /// Appends a copy of `earlier` (at most 64 bytes, with 64 bytes of room past the end).
    #[inline(always)]
    fn copy_earlier(&mut self, earlier: Range<usize>) {
        let from = earlier.start;
        let piece: [u128; 4] =
            std::array::from_fn(|k| u128::from_le_bytes(load::<16>(&self.bytes, from + 16 * k)));
        let mut bytes = [0; 64];
        for (k, part) in piece.iter().enumerate() {
            store(&mut bytes, 16 * k, part.to_le_bytes());
        }
        self.put(&bytes[..earlier.len()]);
    }
}

/// The `N` bytes of `bytes` from `at`.
#[inline(always)]
fn load<const N: usize>(bytes: &[u8], at: usize) -> [u8; N] {
    bytes[at..at + N].try_into().expect("N bytes")
}

/// Writes `piece` into `bytes` at `at`.
#[inline(always)]
fn store<const N: usize>(bytes: &mut [u8], at: usize, piece: [u8; N]) {
    bytes[at..at + N].copy_from_slice(&piece);
}

/// The longest text [`Shortest`] writes for an f32 (`-0.0000012345678` is 16 bytes), with room.
const FLOAT_ROOM: usize = 24;

/// For each point, the point at its joint's parent, if that is one: a joint at a zero offset
/// (CMU's `LHipJoint`, `LowerBack`, `LeftFingerBase`: a quarter of CMU's rows) is where its
/// parent is, and where the bits agree its text is copied rather than formatted again.
fn twins(skeleton: &Skeleton, points: &[(String, usize)]) -> Vec<Option<usize>> {
    let mut point_of = vec![None; skeleton.joints.len()];
    for (i, &(_, joint)) in points.iter().enumerate() {
        point_of[joint].get_or_insert(i);
    }
    points
        .iter()
        .enumerate()
        .map(|(i, &(_, joint))| {
            let parent = skeleton.joints[joint].parent?;
            point_of[parent].filter(|&twin| twin < i)
        })
        .collect()
}

/// [`format_block`], fast: the same bytes (a test compares them on real files with every
/// option), written into a reused buffer through a [`Cursor`], each position checked as it is
/// written rather than in a pass of its own, and a point where its parent is (the same bits)
/// copied from the parent's text.
fn format_block_fast(job: &Job, frames: Range<usize>, spare: Vec<u8>) -> Result<Block, NotFinite> {
    let Job {
        skeleton,
        motion,
        points,
        names,
        first,
        options,
        ..
    } = job;
    let mut text = Cursor {
        bytes: spare,
        at: 0,
    };
    let mut shortest: [Shortest; 3] = Default::default();
    let (mut batch, mut scratch) = (Vec::new(), Fk::default());
    let z_sign = if options.left_handed { -1.0 } else { 1.0 };
    let scale = options.scale;
    let joints = skeleton.joints.len();
    let names_len: usize = names.iter().map(String::len).sum();
    let json = options.format == PositionsFormat::Json;
    let twins = twins(skeleton, points);
    // Where each point's `x,y,z` text is in this frame's rows, for its twins.
    let mut written = vec![0..0; points.len()];
    for start in frames.clone().step_by(LANES) {
        let end = (start + LANES).min(frames.end);
        positions_of(job, start, end, &mut batch, &mut scratch);
        for frame in start..end {
            let positions = if motion.frame_count() == 0 {
                &batch[..]
            } else {
                let in_batch = frame - start;
                &batch[in_batch * joints..(in_batch + 1) * joints]
            };
            let number = frame.to_string();
            let number = number.as_bytes();
            // A frame at most: per row the frame number, three floats and five separators (a
            // JSON row needs less), the names, and JSON's 25 bytes around the frame number;
            // then room for a copy of 64 bytes past the end.
            text.room(
                96 + number.len() + names_len + points.len() * (number.len() + 8 + 3 * FLOAT_ROOM),
            );
            if json {
                if frame > *first {
                    text.byte(b',');
                }
                text.put(b"{\"frame\":");
                text.put(number);
                text.put(b",\"positions\":[");
            }
            for (i, (name, &(ref plain_name, joint))) in names.iter().zip(points).enumerate() {
                if json {
                    if i > 0 {
                        text.byte(b',');
                    }
                    text.byte(b'[');
                } else {
                    text.put(number);
                    text.byte(b',');
                    text.put(name.as_bytes());
                    text.byte(b',');
                }
                let from = text.at;
                let position = positions[joint];
                let twin = twins[i].filter(|&t| {
                    let there = positions[points[t].1];
                    position.to_array().map(f32::to_bits) == there.to_array().map(f32::to_bits)
                });
                if let Some(twin) = twin {
                    // The same bits, so the same text (and finite: the twin was checked).
                    text.copy_earlier(written[twin].clone());
                } else {
                    let p = position * scale;
                    if !p.is_finite() {
                        return Err(not_finite_at(frame, plain_name, p));
                    }
                    // All three formatted before any is copied: a copy right after its
                    // formatting waits for the formatter's stores to reach the cache.
                    let [sx, sy, sz] = &mut shortest;
                    let (x, y, z) = (sx.format(p.x), sy.format(p.y), sz.format(p.z * z_sign));
                    text.put(x);
                    text.byte(b',');
                    text.put(y);
                    text.byte(b',');
                    text.put(z);
                }
                written[i] = from..text.at;
                text.byte(if json { b']' } else { b'\n' });
            }
            if json {
                text.put(b"]}");
            }
        }
    }
    Ok(Block {
        end: text.at,
        text: text.bytes,
    })
}

/// Quotes a CSV field only when it needs it (names with ',' or '"').
fn csv_field(name: &str) -> String {
    if name.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", name.replace('"', "\"\""))
    } else {
        name.to_string()
    }
}

fn json_string(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
