//! Skeleton + Motion back to BVH text. The article has no writer; this one writes what any BVH
//! reader accepts: tab indentation, LF line ends, one frame per line.

use crate::io::error::Error;
use crate::limits::{MAX_DEPTH, MAX_NAME_BYTES};
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;
use std::borrow::Cow;
use std::io::{self, Write};

/// A joint name as the writer writes it. A BVH name runs to the end of its line and other
/// readers split it at blanks, so whitespace (line ends included) and the braces that open and
/// close joints become `_`; an empty name becomes `unnamed`. Any other name is kept as it is.
pub fn safe_name(name: &str) -> Cow<'_, str> {
    let unsafe_char = |c: char| c.is_whitespace() || c == '{' || c == '}';
    if name.is_empty() {
        Cow::Borrowed("unnamed")
    } else if name.contains(unsafe_char) {
        Cow::Owned(name.replace(unsafe_char, "_"))
    } else {
        Cow::Borrowed(name)
    }
}

/// Every joint (End Sites aside: they are written `End Site`) whose name the writer changes:
/// (the name, the name written).
pub fn renamed(skeleton: &Skeleton) -> Vec<(String, String)> {
    skeleton
        .joints
        .iter()
        .filter(|joint| !joint.end_site)
        .filter_map(|joint| match safe_name(&joint.name) {
            Cow::Owned(safe) => Some((joint.name.clone(), safe)),
            Cow::Borrowed(safe) if safe != joint.name => Some((joint.name.clone(), safe.into())),
            Cow::Borrowed(_) => None,
        })
        .collect()
}

/// Whether the take can be written as a BVH file that loads back (bvhview's loader and others):
/// every number finite, the frame time one a loader accepts, names and nesting within
/// [`crate::limits`]. Called before anything is written, so a take that cannot be written
/// leaves no file.
pub fn check(skeleton: &Skeleton, motion: &Motion) -> Result<(), Error> {
    let refuse = |why: String| Err(Error::usage(format!("cannot write BVH: {why}")));
    if let Some(joint) = skeleton.joints.iter().find(|j| !j.offset.is_finite()) {
        return refuse(format!("the OFFSET of '{}' is not finite", joint.name));
    }
    if let Some(at) = crate::edit::first_non_finite(&motion.data) {
        let channels = motion.channels.max(1);
        return refuse(format!(
            "frame {}, column {} is not finite",
            at / channels,
            at % channels
        ));
    }
    if !crate::limits::frame_time_in_file(motion.frame_time) {
        return refuse(format!(
            "a frame time of {} s (a loader reads 0 to {} s)",
            motion.frame_time,
            crate::limits::MAX_FRAME_TIME
        ));
    }
    if let Some(joint) = skeleton
        .joints
        .iter()
        .find(|j| safe_name(&j.name).len() > MAX_NAME_BYTES)
    {
        return refuse(format!(
            "a joint name of {} bytes (a loader reads at most {MAX_NAME_BYTES})",
            joint.name.len()
        ));
    }
    // The loader counts the joints open around each new one (the root has none).
    let mut depth = vec![0usize; skeleton.joints.len()];
    for (index, joint) in skeleton.joints.iter().enumerate() {
        if let Some(parent) = joint.parent {
            depth[index] = depth[parent] + 1;
        }
        if depth[index] >= MAX_DEPTH {
            return refuse(format!(
                "'{}' nests {} levels deep; a BVH loader reads at most {MAX_DEPTH}",
                joint.name,
                depth[index] + 1
            ));
        }
    }
    Ok(())
}

/// Writes `skeleton` and `motion` as BVH. Numbers are written in their shortest form that reads
/// back to the same `f32`, so a load of the output gives exactly the values that were written.
/// Names pass through [`safe_name`], so the loader reads back every file this writes. A take
/// that fails [`check`] is refused (`InvalidInput`) before a byte is written.
pub fn write_bvh<W: Write>(out: &mut W, skeleton: &Skeleton, motion: &Motion) -> io::Result<()> {
    check(skeleton, motion)
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e.to_string()))?;
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

/// The whole file as a string, or why it cannot be written ([`check`]).
pub fn to_string(skeleton: &Skeleton, motion: &Motion) -> Result<String, Error> {
    check(skeleton, motion)?;
    let mut bytes = Vec::new();
    write_bvh(&mut bytes, skeleton, motion).expect("writing to memory cannot fail once checked");
    Ok(String::from_utf8(bytes).expect("the writer only writes UTF-8"))
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
        writeln!(out, "{indent}ROOT {}", safe_name(&joint.name))?;
    } else {
        writeln!(out, "{indent}JOINT {}", safe_name(&joint.name))?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::skeleton::{Channel, Joint};

    /// Names the loader would refuse or read differently are written safe, and the file loads.
    #[test]
    fn every_name_is_written_so_that_it_loads_back() {
        let names = ["x{y}", "", "a\nb", "Left Arm\t2", "ok:name.1"];
        let mut skeleton = Skeleton::default();
        for (i, name) in names.iter().enumerate() {
            let mut joint = Joint::new(name.to_string(), i.checked_sub(1));
            joint.channels = vec![Channel::Zrotation];
            joint.first_channel = i;
            if i > 0 {
                skeleton.joints[i - 1].children.push(i);
            }
            skeleton.joints.push(joint);
        }
        let motion = Motion::new(0.5, names.len(), 1, vec![1.0; names.len()]);
        let text = to_string(&skeleton, &motion).unwrap();
        let loaded = crate::bvh::load_bytes(text.as_bytes(), "t.bvh").unwrap();
        let read: Vec<&str> = loaded
            .skeleton
            .joints
            .iter()
            .map(|j| j.name.as_str())
            .collect();
        assert_eq!(read, ["x_y_", "unnamed", "a_b", "Left_Arm_2", "ok:name.1"]);
        assert_eq!(loaded.motion, motion);
        let renamed = renamed(&skeleton);
        assert_eq!(renamed.len(), 4);
        assert_eq!(renamed[0], ("x{y}".to_string(), "x_y_".to_string()));
    }
}
