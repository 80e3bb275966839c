//! World positions of every joint and End Site per frame, as CSV or JSON (`bvhview positions`).

use crate::error::Error;
use crate::motion::Motion;
use crate::pose::{FkPlan, FkScratch, LANES, OffsetMode, world_matrices};
use crate::skeleton::{Skeleton, Source};
use std::io::{self, Write};
use std::ops::Range;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Format {
    /// `frame,joint,x,y,z`, one joint per line.
    #[default]
    Csv,
    /// `{"frame_time":…,"joints":[…],"frames":[{"frame":0,"positions":[[x,y,z],…]},…]}`.
    Json,
}

/// Options of a positions export.
#[derive(Clone, Debug)]
pub struct PositionsOptions {
    pub format: Format,
    pub offset_mode: OffsetMode,
    /// Negate z, turning the right-handed BVH frame into a left-handed one (Direct3D).
    pub left_handed: bool,
    /// Multiplies every coordinate (1 keeps the file's units).
    pub scale: f32,
}

impl Default for PositionsOptions {
    fn default() -> PositionsOptions {
        PositionsOptions {
            format: Format::Csv,
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
        Error::Usage(format!(
            "--frames {text}: expected N, A..B (B left out), A..=B, A.. or ..B within frames 0 to {last}"
        ))
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
        return Err(Error::Usage(format!(
            "--frames {text}: no frames: A..B leaves B out (for frame A alone, give A or A..=A)"
        )));
    }
    if range.end > frame_count {
        return Err(bad());
    }
    Ok(range)
}

/// A position that is not a finite number (offsets and values near the float limit, or a large
/// `--scale`, overflow): the export stops rather than write `inf` or `NaN`, which CSV and JSON
/// readers refuse. It travels inside the `io::Error` that [`write_positions`] returns.
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

/// The name an export uses for a joint: its own, or `<parent>_End` for an End Site.
pub fn export_name(skeleton: &Skeleton, index: usize) -> String {
    let joint = &skeleton.joints[index];
    match (joint.end_site, joint.parent) {
        (true, Some(parent)) => format!("{}_End", skeleton.joints[parent].name),
        _ => joint.name.clone(),
    }
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
    let points = export_points(skeleton);
    // Held back until the first frames are known to be finite, so that a refused export of a
    // short take writes nothing at all.
    let mut header = Vec::new();
    match options.format {
        Format::Csv => writeln!(header, "frame,joint,x,y,z")?,
        Format::Json => {
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
    let names: Vec<String> = points.iter().map(|(name, _)| csv_field(name)).collect();
    let plan = FkPlan::new(skeleton, options.offset_mode);
    let threads = crate::cores().clamp(1, 8);
    let first = frames.start;
    // Blocks of frames formatted on every core and written in order as they are ready; a few
    // blocks at most wait for an earlier one.
    let blocks: Vec<Range<usize>> = frames
        .clone()
        .step_by(BLOCK)
        .map(|start| start..(start + BLOCK).min(frames.end))
        .collect();
    let mut failure = None;
    crate::parallel::map_in_order(
        blocks.len(),
        threads,
        2 * threads,
        |k| {
            let block = blocks[k].clone();
            format_block(
                skeleton, &plan, &names, &points, motion, block, first, options,
            )
        },
        |_, text| {
            let written = text
                .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))
                .and_then(|text| {
                    out.write_all(&std::mem::take(&mut header))?;
                    out.write_all(&text)
                });
            written.map_err(|e| failure = Some(e)).is_ok()
        },
    );
    if let Some(error) = failure {
        return Err(error);
    }
    out.write_all(&header)?;
    if options.format == Format::Json {
        writeln!(out, "]}}")?;
    }
    Ok(())
}

/// Appends a float in its shortest form that reads back to the same value (`ryu`), without
/// ryu's `.0` on whole numbers, so 30 prints as `30`.
fn push_float(text: &mut Vec<u8>, buffer: &mut ryu::Buffer, value: f32) {
    let printed = buffer.format(value);
    text.extend_from_slice(printed.strip_suffix(".0").unwrap_or(printed).as_bytes());
}

/// The text of `frames`: CSV rows, or JSON frame objects (comma-led except the very first).
#[allow(clippy::too_many_arguments)]
fn format_block(
    skeleton: &Skeleton,
    plan: &FkPlan,
    names: &[String],
    points: &[(String, usize)],
    motion: &Motion,
    frames: Range<usize>,
    first: usize,
    options: &PositionsOptions,
) -> Result<Vec<u8>, NotFinite> {
    let mut text = Vec::with_capacity(frames.len() * points.len() * 40);
    let mut buffer = ryu::Buffer::new();
    let (mut batch, mut scratch, mut matrices) = (Vec::new(), FkScratch::default(), Vec::new());
    let z_sign = if options.left_handed { -1.0 } else { 1.0 };
    let scale = options.scale;
    let joints = skeleton.joints.len();
    for frame in frames.clone() {
        let in_batch = (frame - frames.start) % LANES;
        if motion.frame_count() == 0 {
            // The rest pose: OFFSETs only.
            world_matrices(skeleton, &[], options.offset_mode, &mut matrices);
            batch = matrices.iter().map(|m| m.w_axis.truncate()).collect();
        } else if in_batch == 0 {
            // Eight frames at a time, side by side.
            let rows: Vec<&[f32]> = (frame..(frame + LANES).min(frames.end))
                .map(|f| motion.frame(f))
                .collect();
            plan.positions_of_frames(&rows, &mut batch, &mut scratch);
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
                return Err(NotFinite(format!(
                    "frame {frame}, {name}: the position ({}, {}, {}) is not a finite number \
                     (the offsets, the values or --scale overflow)",
                    p.x, p.y, p.z
                )));
            }
        }
        match options.format {
            Format::Csv => {
                for (name, &(_, joint)) in names.iter().zip(points) {
                    let p = positions[joint] * scale;
                    text.extend_from_slice(frame_number.as_bytes());
                    text.push(b',');
                    text.extend_from_slice(name.as_bytes());
                    for value in [p.x, p.y, p.z * z_sign] {
                        text.push(b',');
                        push_float(&mut text, &mut buffer, value);
                    }
                    text.push(b'\n');
                }
            }
            Format::Json => {
                if frame > first {
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
                        push_float(&mut text, &mut buffer, value);
                    }
                    text.push(b']');
                }
                text.extend_from_slice(b"]}");
            }
        }
    }
    Ok(text)
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
