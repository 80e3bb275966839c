//! Skeleton + Motion back to BVH text. The article has no writer; this one writes what any BVH
//! reader accepts: tab indentation, LF line ends, one frame per line.

use crate::motion::Motion;
use crate::skeleton::Skeleton;
use std::io::{self, Write};

/// Writes `skeleton` and `motion` as BVH. Numbers are written in their shortest form that reads
/// back to the same `f32`, so a load of the output gives exactly the values that were written.
pub fn write_bvh<W: Write>(out: &mut W, skeleton: &Skeleton, motion: &Motion) -> io::Result<()> {
    writeln!(out, "HIERARCHY")?;
    for root in skeleton.roots() {
        write_joint(out, skeleton, root, 0)?;
    }
    writeln!(out, "MOTION")?;
    writeln!(out, "Frames: {}", motion.frame_count())?;
    writeln!(out, "Frame Time: {}", motion.frame_time)?;
    let mut line = String::new();
    for frame in 0..motion.frame_count() {
        line.clear();
        for (i, value) in motion.frame(frame).iter().enumerate() {
            if i > 0 {
                line.push(' ');
            }
            push_number(&mut line, *value);
        }
        line.push('\n');
        out.write_all(line.as_bytes())?;
    }
    Ok(())
}

/// The whole file as a string.
pub fn to_string(skeleton: &Skeleton, motion: &Motion) -> String {
    let mut bytes = Vec::new();
    write_bvh(&mut bytes, skeleton, motion).expect("writing to memory cannot fail");
    String::from_utf8(bytes).expect("the writer only writes UTF-8")
}

fn push_number(line: &mut String, value: f32) {
    use std::fmt::Write as _;
    // Display of a float is its shortest round-trip form; -0 keeps its sign.
    let _ = write!(line, "{value}");
}

fn write_joint<W: Write>(
    out: &mut W,
    skeleton: &Skeleton,
    index: usize,
    depth: usize,
) -> io::Result<()> {
    let joint = &skeleton.joints[index];
    let indent = "\t".repeat(depth);
    if joint.end_site {
        writeln!(out, "{indent}End Site")?;
    } else if joint.parent.is_none() {
        writeln!(out, "{indent}ROOT {}", joint.name)?;
    } else {
        writeln!(out, "{indent}JOINT {}", joint.name)?;
    }
    writeln!(out, "{indent}{{")?;
    let mut offset = String::new();
    for (i, value) in joint.offset.to_array().into_iter().enumerate() {
        if i > 0 {
            offset.push(' ');
        }
        push_number(&mut offset, value);
    }
    writeln!(out, "{indent}\tOFFSET {offset}")?;
    if !joint.end_site {
        write!(out, "{indent}\tCHANNELS {}", joint.channels.len())?;
        for channel in &joint.channels {
            write!(out, " {channel}")?;
        }
        writeln!(out)?;
    }
    for &child in &joint.children {
        write_joint(out, skeleton, child, depth + 1)?;
    }
    writeln!(out, "{indent}}}")
}
