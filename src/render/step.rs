//! The recursion one joint at a time (the window's J key, `snapshot --step K`): the first K
//! joints in the order `drawRecursive` reaches them, the last one highlighted, and beside the
//! picture which joint that is, how deep the matrix stack is, and the GL calls that drew it.

use crate::model::pose::OffsetMode;
use crate::model::skeleton::Skeleton;
use crate::render::draw::{self, Pass, Style};
use crate::render::fixed::FixedFunction;
use crate::render::text;
use crate::render::trace::{Numbers, Recorder};

/// The overlay's lines for the step that has drawn `shown` joints (1 to the joint count), at
/// most `columns` characters each; the spheres are `sphere_radius` as in the picture.
pub fn lines(
    skeleton: &Skeleton,
    frame: Option<&[f32]>,
    (style, mode): (Style, OffsetMode),
    sphere_radius: f64,
    shown: usize,
    columns: usize,
) -> Vec<String> {
    let count = skeleton.joints.len();
    let shown = shown.clamp(1, count.max(1));
    let current = shown - 1;
    let Some(joint) = skeleton.joints.get(current) else {
        return Vec::new();
    };
    let depth = std::iter::successors(joint.parent, |&p| skeleton.joints[p].parent).count();
    let columns_read = if joint.channels.is_empty() {
        "no MOTION columns".to_string()
    } else {
        let last = joint.first_channel + joint.channels.len() - 1;
        format!("MOTION columns [{}]-[{last}]", joint.first_channel)
    };
    let mut out = vec![
        format!("step {shown} of {count}: {}", joint.name),
        format!("tree depth {depth}, matrix stack {}", depth + 1),
        columns_read,
        "its GL calls:".to_string(),
    ];
    // The calls the draw makes for this joint, up to its sphere: recorded, not retold, from
    // the whole picture (the article's calls: its sphere, not the step view's highlight).
    let mut recorder = Recorder::new(Numbers::Short);
    let pass = Pass {
        sphere_radius,
        ..Pass::whole(skeleton, frame, style, mode)
    };
    draw::draw_pass(&mut recorder, &pass);
    if let Some(&(_, start)) = recorder.joint_starts.iter().find(|(j, _)| *j == current) {
        let through_sphere = recorder.lines[start..]
            .iter()
            .position(|l| l.starts_with("glutSolidSphere"))
            .map_or(recorder.lines.len(), |i| start + i + 1);
        for call in recorder.lines[start..through_sphere].iter().take(8) {
            out.push(format!(" {call}"));
        }
    }
    out.push("J next, Shift+J back, Esc all".to_string());
    out.into_iter()
        .map(|line| line.chars().take(columns).collect())
        .collect()
}

/// Draws the overlay of [`lines`], in white, bottom left, in `font` (the picture's:
/// [`text::Font::for_picture`], so that a small picture is not covered by big glyphs).
pub fn draw_overlay<G: FixedFunction>(gl: &mut G, lines: &[String], font: text::Font) {
    text::draw_lines_in(
        gl,
        0,
        text::Corner::BottomLeft,
        lines,
        [1.0, 1.0, 1.0],
        font,
    );
}

/// How many characters of `font` fit across a picture `width` pixels wide.
pub fn columns(width: u32, font: text::Font) -> usize {
    (width as usize).saturating_sub(16) / font.cell as usize
}
