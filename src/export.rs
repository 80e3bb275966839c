//! World positions of every joint and End Site per frame, as CSV or JSON (`bvhview positions`).

use crate::error::Error;
use crate::motion::Motion;
use crate::pose::{OffsetMode, world_matrices};
use crate::skeleton::Skeleton;
use std::io::{self, Write};
use std::ops::Range;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
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
    let bad = || {
        Error::Usage(format!(
            "--frames {text}: expected N, A..B, A..=B, A.. or ..B with frames 0..{frame_count}"
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
    if range.start >= range.end || range.end > frame_count {
        return Err(bad());
    }
    Ok(range)
}

/// Writes the positions of `frames` (indices into `motion`; for a take without frames, pass
/// `0..1` to get the rest pose).
pub fn write_positions<W: Write>(
    out: &mut W,
    skeleton: &Skeleton,
    motion: &Motion,
    frames: Range<usize>,
    options: &PositionsOptions,
) -> io::Result<()> {
    let points = skeleton.export_points();
    let names: Vec<&String> = points.iter().map(|(name, _)| name).collect();
    let scale = options.scale;
    let mut matrices = Vec::new();
    let mut line = String::new();
    let z_sign = if options.left_handed { -1.0 } else { 1.0 };
    match options.format {
        Format::Csv => writeln!(out, "frame,joint,x,y,z")?,
        Format::Json => {
            write!(out, "{{\"frame_time\":{},\"joints\":[", motion.frame_time)?;
            for (i, name) in names.iter().enumerate() {
                let comma = if i > 0 { "," } else { "" };
                write!(out, "{comma}{}", json_string(name))?;
            }
            write!(out, "],\"frames\":[")?;
        }
    }
    for (n, frame) in frames.enumerate() {
        let values: &[f32] = if motion.frame_count() == 0 {
            &[]
        } else {
            motion.frame(frame)
        };
        world_matrices(skeleton, values, options.offset_mode, &mut matrices);
        line.clear();
        match options.format {
            Format::Csv => {
                for (name, &(_, joint)) in names.iter().zip(&points) {
                    let p = matrices[joint].w_axis * scale;
                    use std::fmt::Write as _;
                    let _ = writeln!(
                        line,
                        "{frame},{},{},{},{}",
                        csv_field(name),
                        p.x,
                        p.y,
                        p.z * z_sign
                    );
                }
            }
            Format::Json => {
                use std::fmt::Write as _;
                let comma = if n > 0 { "," } else { "" };
                let _ = write!(line, "{comma}{{\"frame\":{frame},\"positions\":[");
                for (i, &(_, joint)) in points.iter().enumerate() {
                    let p = matrices[joint].w_axis * scale;
                    let comma = if i > 0 { "," } else { "" };
                    let _ = write!(line, "{comma}[{},{},{}]", p.x, p.y, p.z * z_sign);
                }
                line.push_str("]}");
            }
        }
        out.write_all(line.as_bytes())?;
    }
    if options.format == Format::Json {
        writeln!(out, "]}}")?;
    }
    Ok(())
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
