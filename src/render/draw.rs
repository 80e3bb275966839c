//! C++: `BVH::draw`, `BVH::drawRecursive`, `BVH::roateSpace`: the skeleton drawn down the tree
//! on the GL matrix stack.

use crate::model::pose::{OffsetMode, joint_translation};
use crate::model::skeleton::{Joint, Skeleton};
use crate::render::fixed::{FixedFunction, GL_LIGHTING, GL_LINES, Note};

/// How joints are drawn. `Points` is the article's picture.
///
/// ```
/// use bvhview::model::pose::OffsetMode;
/// use bvhview::render::{draw::{Style, draw}, trace::{Numbers, Recorder}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = bvhview::Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let calls = |style| {
///     let mut gl = Recorder::new(Numbers::Printf);
///     draw(&mut gl, &take.skeleton, None, style, OffsetMode::Replace);
///     let spheres = gl.lines.iter().filter(|l| l.starts_with("glutSolidSphere")).count();
///     let lines = gl.lines.iter().filter(|l| l.starts_with("glBegin(GL_LINES)")).count();
///     (spheres, lines)
/// };
/// assert_eq!(calls(Style::Points), (12, 0)); // a sphere per joint and End Site
/// assert_eq!(calls(Style::Sticks), (0, 7)); // lines from each of the 7 joints to its children
/// assert_eq!(calls(Style::Both), (12, 7));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Style {
    /// A sphere per joint and End Site (the article).
    #[default]
    Points,
    /// A line from each joint to each child (the paper's stick figure), unlit, green.
    Sticks,
    /// Both.
    Both,
}

/// C++: `BVH::draw`. The article copies the root's first three values into its offset and starts
/// `pFrame` after them, which assumes a root with exactly three position channels first; here
/// every joint reads its own columns, so position channels may be on any joint, in any order.
/// `frame: None` draws the rest pose (every OFFSET, no rotation).
pub fn draw<G: FixedFunction>(
    gl: &mut G,
    skeleton: &Skeleton,
    frame: Option<&[f32]>,
    style: Style,
    mode: OffsetMode,
) {
    draw_pass(gl, &Pass::whole(skeleton, frame, style, mode));
}

/// One draw of a skeleton: what [`draw`] takes, and how much of the tree to show.
///
/// ```
/// use bvhview::model::pose::OffsetMode;
/// use bvhview::render::{draw::{Pass, Style, draw_pass}, trace::{Numbers, Recorder}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = bvhview::Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let whole = Pass::whole(&take.skeleton, None, Style::Points, OffsetMode::Replace);
/// // The window's step view: the first three joints drawn, the third highlighted.
/// let step = Pass { shown: Some(3), ..whole };
/// let mut gl = Recorder::new(Numbers::Printf);
/// draw_pass(&mut gl, &step);
/// assert_eq!(gl.lines.iter().filter(|l| l.starts_with("glutSolidSphere")).count(), 3);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Pass<'a> {
    /// The skeleton drawn.
    pub skeleton: &'a Skeleton,
    /// The MOTION row drawn; `None` draws the rest pose.
    pub frame: Option<&'a [f32]>,
    /// Spheres, sticks or both.
    pub style: Style,
    /// How position channels meet the OFFSET.
    pub mode: OffsetMode,
    /// Only the first `shown` joints in pre-order (the order they are drawn in) are drawn, the
    /// last of them highlighted: the window's step-by-step view of the recursion. `None`: all.
    pub shown: Option<usize>,
    /// The spheres' radius: the article's 1, or in proportion to the skeleton in a view that
    /// frames it.
    pub sphere_radius: f64,
    /// A colour per joint for its sphere and the sticks to its children (the studio look, with
    /// `GL_COLOR_MATERIAL` on); `None`, the article's: no colour calls at all.
    pub colours: Option<&'a [[f32; 3]]>,
}

impl<'a> Pass<'a> {
    /// The whole skeleton, as the article draws it.
    pub fn whole(
        skeleton: &'a Skeleton,
        frame: Option<&'a [f32]>,
        style: Style,
        mode: OffsetMode,
    ) -> Pass<'a> {
        Pass {
            skeleton,
            frame,
            style,
            mode,
            shown: None,
            sphere_radius: 1.0,
            colours: None,
        }
    }
}

/// [`draw`] of a [`Pass`]: every root's tree. The step view's partial tree wraps the call: the
/// recursion runs over a copy of the skeleton cut to the joints shown.
pub fn draw_pass<G: FixedFunction>(gl: &mut G, pass: &Pass) {
    let cut;
    let pass = match pass.shown {
        Some(shown) if shown < pass.skeleton.joints.len() => {
            cut = first_joints(pass.skeleton, shown);
            &Pass {
                skeleton: &cut,
                ..*pass
            }
        }
        _ => pass,
    };
    for root in pass.skeleton.roots() {
        draw_recursive(gl, pass, root, 0);
    }
}

/// The first `shown` joints in pre-order (the order the recursion reaches them), each keeping
/// only its children among them.
fn first_joints(skeleton: &Skeleton, shown: usize) -> Skeleton {
    let mut cut = skeleton.clone();
    cut.joints.truncate(shown);
    for joint in &mut cut.joints {
        joint.children.retain(|&child| child < shown);
    }
    cut
}

/// The joint's translation for this frame (its OFFSET in the rest pose).
fn translation(joint: &Joint, frame: Option<&[f32]>, mode: OffsetMode) -> [f32; 3] {
    match frame {
        Some(frame) => joint_translation(joint, joint.values(frame), mode).to_array(),
        None => joint.offset.to_array(),
    }
}

/// C++: `BVH::drawRecursive`, statement by statement:
///
/// ```c
/// glPushMatrix();
/// glTranslatef(r->x, r->y, r->z);
/// roateSpace(r->flags);
/// glutSolidSphere(1.0f, 20, 16);
/// for (int i = 0; i < r->childNum; i++) drawRecursive(r->getChild(i));
/// glPopMatrix();
/// ```
///
/// The same calls in the same order (the article's "debug 3": translate before rotating). What
/// changed: the translation is `pose::joint_translation` (the OFFSET, with any position channels
/// of this joint), so the matrix at each joint is `pose`'s world matrix times the view; a
/// skeleton deeper than GL's matrix stack saves and restores the matrix itself
/// (`push_matrix_or_save`, `pop_matrix_or_restore`); `rotate_space` also turns an ASF bone about
/// its own axis; and the sphere is `draw_joint`, which is the article's sphere in its picture
/// and where a pass adds colours, the stick figure or the step view's highlight. `depth` is the
/// joint's depth in the tree, 0 at a root. The notes mark each joint's calls for
/// `bvhview trace --explain`; GL ignores them.
pub fn draw_recursive<G: FixedFunction>(gl: &mut G, pass: &Pass, index: usize, depth: usize) {
    let joint = &pass.skeleton.joints[index];
    gl.note(Note::Joint(index));
    let saved = push_matrix_or_save(gl, depth);
    let [x, y, z] = translation(joint, pass.frame, pass.mode);
    gl.translatef(x, y, z);
    rotate_space(gl, joint, pass.frame);
    draw_joint(gl, pass, index);
    for &child in &joint.children {
        draw_recursive(gl, pass, child, depth + 1);
    }
    pop_matrix_or_restore(gl, saved);
    gl.note(Note::JointEnd);
}

/// The article's `glutSolidSphere(1.0f, 20, 16)` at a joint (of the pass's radius), and what a
/// pass draws around it: the joint's colour (the studio look), the step view's highlight
/// instead of the sphere, no sphere for the stick figure alone, the sticks to its children.
fn draw_joint<G: FixedFunction>(gl: &mut G, pass: &Pass, index: usize) {
    if let Some(colours) = pass.colours {
        let [r, g, b] = colours[index];
        gl.color3f(r, g, b);
    }
    if pass.shown == Some(index + 1) {
        highlighted_sphere(gl, pass.sphere_radius);
    } else if pass.style != Style::Sticks {
        gl.solid_sphere(pass.sphere_radius, 20, 16);
    }
    let joint = &pass.skeleton.joints[index];
    if pass.style != Style::Points && !joint.children.is_empty() {
        draw_sticks(gl, pass, joint);
    }
}

/// The joint the step view has just reached: a larger sphere, unlit orange.
fn highlighted_sphere<G: FixedFunction>(gl: &mut G, radius: f64) {
    gl.disable(GL_LIGHTING);
    gl.color3f(1.0, 0.45, 0.1);
    gl.solid_sphere(2.0 * radius, 20, 16);
    gl.color3f(0.0, 1.0, 0.0);
    gl.enable(GL_LIGHTING);
}

/// The GL modelview stack holds at least 32 matrices; below this depth the draw pushes and pops
/// as the article does, deeper it saves and restores the matrix itself (a 1000-joint chain would
/// otherwise overflow the stack and draw garbage).
const GL_STACK_DEPTH: usize = 30;

/// `glPushMatrix()` as the article, or below [`GL_STACK_DEPTH`] the matrix read back to restore.
fn push_matrix_or_save<G: FixedFunction>(gl: &mut G, depth: usize) -> Option<[f32; 16]> {
    if depth < GL_STACK_DEPTH {
        gl.push_matrix();
        None
    } else {
        Some(gl.get_modelview())
    }
}

/// `glPopMatrix()`, or the matrix [`push_matrix_or_save`] saved.
fn pop_matrix_or_restore<G: FixedFunction>(gl: &mut G, saved: Option<[f32; 16]>) {
    match saved {
        None => gl.pop_matrix(),
        Some(matrix) => gl.load_matrix(&matrix),
    }
}

/// The stick figure's lines from a joint to each child shown, unlit.
fn draw_sticks<G: FixedFunction>(gl: &mut G, pass: &Pass, joint: &Joint) {
    gl.disable(GL_LIGHTING);
    gl.begin(GL_LINES);
    for &child in &joint.children {
        if let Some(colours) = pass.colours {
            let [r, g, b] = colours[child];
            gl.color3f(r, g, b);
        }
        let [cx, cy, cz] = translation(&pass.skeleton.joints[child], pass.frame, pass.mode);
        gl.vertex3f(0.0, 0.0, 0.0);
        gl.vertex3f(cx, cy, cz);
    }
    gl.end();
    gl.enable(GL_LIGHTING);
}

/// C++: `BVH::roateSpace` (sic). The article switches over its six flags and issues three
/// `glRotatef` in that order, then advances `pFrame` by three unless the joint is an End Site
/// (its "debug 2"). Here one `glRotatef` per rotation channel in file order gives the same calls
/// for those six orders and also handles any other layout; each joint's columns are its own, so
/// there is no shared cursor to advance. An ASF bone turns about its own axis
/// (`rotate_space_about_axis`); BVH joints have none.
pub fn rotate_space<G: FixedFunction>(gl: &mut G, joint: &Joint, frame: Option<&[f32]>) {
    match joint.axis {
        None => rotate_channels(gl, joint, frame),
        Some(axis) => rotate_space_about_axis(gl, joint, frame, axis),
    }
}

/// An ASF bone turns about its own fixed axis C: its channels' rotations between C and C⁻¹, the
/// GL calls for [`crate::model::pose::local_rotation`].
fn rotate_space_about_axis<G: FixedFunction>(
    gl: &mut G,
    joint: &Joint,
    frame: Option<&[f32]>,
    axis: glam::Quat,
) {
    gl.mult_matrixf(&glam::Mat4::from_quat(axis).to_cols_array());
    rotate_channels(gl, joint, frame);
    gl.mult_matrixf(&glam::Mat4::from_quat(axis.inverse()).to_cols_array());
}

/// One `glRotatef` per rotation channel, in file order.
fn rotate_channels<G: FixedFunction>(gl: &mut G, joint: &Joint, frame: Option<&[f32]>) {
    let values = frame.map(|f| joint.values(f));
    for (i, channel) in joint.channels.iter().enumerate() {
        if !channel.is_rotation() {
            continue;
        }
        let angle = values.map_or(0.0, |v| v[i]);
        match channel.axis() {
            0 => gl.rotatef(angle, 1.0, 0.0, 0.0),
            1 => gl.rotatef(angle, 0.0, 1.0, 0.0),
            _ => gl.rotatef(angle, 0.0, 0.0, 1.0),
        }
    }
}
