//! A recording implementation of the GL table: the scene and draw code run unchanged and every
//! call becomes one line of C. The window and the snapshots run the same code against real GL,
//! so what the trace shows is what they draw.

use crate::render::fixed::{
    FixedFunction, GL_COLOR_BUFFER_BIT, GL_CULL_FACE, GL_DEPTH_BUFFER_BIT, GL_DEPTH_TEST,
    GL_LIGHT0, GL_LIGHTING, GL_LINE_LOOP, GL_LINE_STRIP, GL_LINES, GL_MODELVIEW, GL_NORMALIZE,
    GL_POSITION, GL_PROJECTION, GL_QUADS, GL_TRIANGLE_STRIP, Note,
};

mod language;
mod verdict;

pub use language::Language;
use language::{Both, axis_letters, both, plain};
pub use verdict::{gl_stack_line, verdict_line};

/// How numbers are written.
///
/// ```
/// use bvhview::model::pose::OffsetMode;
/// use bvhview::render::{draw::{Style, draw}, trace::{Numbers, Recorder}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = bvhview::Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let frame = Some(take.motion.frame(1));
/// let mut printf = Recorder::new(Numbers::Printf);
/// draw(&mut printf, &take.skeleton, frame, Style::Points, OffsetMode::Replace);
/// let mut apitrace = Recorder::new(Numbers::Apitrace);
/// draw(&mut apitrace, &take.skeleton, frame, Style::Points, OffsetMode::Replace);
/// // The root moved to its frame-1 position.
/// assert_eq!(printf.lines[1], "glTranslatef(5.000000, 30.000000, -3.000000);");
/// assert_eq!(apitrace.lines[1], "glTranslatef(5, 30, -3);");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Numbers {
    /// As apitrace dumps them: `%.7g` for floats, `%.16g` for doubles (tests/oracle/trace).
    Apitrace,
    /// As C's `printf("%f")`: six decimals (`glTranslatef(0.000000, 84.730759, 0.000000)`).
    Printf,
    /// As apitrace, but doubles to seven digits as floats are: short enough to read on the
    /// picture (the step view's listing).
    Short,
}

/// What `--explain` says about one joint.
struct JointFacts {
    name: String,
    /// How `info` counts it: the n-th joint (End Sites apart), or the End Site of its parent.
    label: Label,
    /// The column the article's `pFrame` points at when it turns this joint: 3 past the root's
    /// positions, 3 more for each joint before it whose flags are not 0.
    article_column: usize,
    /// The article's flags for it (`getFlags`), and the axes `roateSpace` turns about for them
    /// (none unless they are 1, 2, 3, 5, 6 or 7).
    article_flags: u8,
    article_axes: Option<[usize; 3]>,
    /// Whether it is the root, and what the article translates it by there (columns 0 to 2 as
    /// x, y and z) when that is not what its channels say.
    root_translation: Option<[f32; 3]>,
    /// Its MOTION columns, and which of them are rotations (in file order).
    columns: std::ops::Range<usize>,
    rotation_columns: Vec<(usize, crate::model::skeleton::Channel)>,
    position_columns: Vec<(usize, crate::model::skeleton::Channel)>,
    offset: glam::Vec3,
    /// Where its sphere lands, from `pose` (not from the recorded matrices).
    world: glam::Vec3,
    is_root: bool,
}

impl JointFacts {
    /// What the article's flags make of the joint: the flags `print` shows and the axes
    /// `roateSpace` turns about for them, in order, or that it turns nothing.
    fn flags_note(&self, language: Language) -> String {
        let flags = self.article_flags;
        let zh = language == Language::Chinese;
        match (self.article_axes, flags, zh) {
            (Some(axes), _, false) => format!(
                "the article's flags {flags} ({}): it turns about {}",
                axis_letters(axes, false).replace(", ", "").to_lowercase(),
                axis_letters(axes, false)
            ),
            (Some(axes), _, true) => format!(
                "原文的 flags 是 {flags}（{}）：依序繞 {} 軸旋轉",
                axis_letters(axes, false).replace(", ", "").to_lowercase(),
                axis_letters(axes, true)
            ),
            (None, 0, false) => "the article's flags 0, an End Site's: it turns nothing here and leaves pFrame where it is".to_string(),
            (None, 0, true) => "原文的 flags 是 0，和 End Site 一樣：這裡不旋轉，pFrame 也不前進".to_string(),
            (None, _, false) => format!("the article's flags {flags}: roateSpace has no case {flags}, so it turns nothing here, and pFrame still moves on by 3"),
            (None, _, true) => format!("原文的 flags 是 {flags}：roateSpace 沒有 case {flags}，這裡不旋轉，pFrame 仍前進 3"),
        }
    }
}

/// C++: `BVH::getFlags`, from a joint's channels as if its CHANNELS line were laid out as the
/// article needs: the letters of the three channels from the first rotation on (the root: the
/// article scans to the first `r`) or of the first three (any other joint). End Sites, and joints
/// with fewer than three channels, get 0.
fn channel_flags(joint: &crate::model::skeleton::Joint) -> u8 {
    if joint.end_site || joint.channels.len() < 3 {
        return 0;
    }
    let first = match joint.parent {
        None => joint
            .channels
            .iter()
            .position(|c| c.is_rotation())
            .unwrap_or(0),
        Some(_) => 0,
    };
    let letters = &joint.channels[first..];
    if letters.len() < 3 {
        return 0;
    }
    crate::bvh::article::get_flags([0, 1, 2].map(|i| b"XYZ"[letters[i].axis()]))
}

/// A joint as `info` counts it.
enum Label {
    Joint(usize),
    EndSiteOf(String),
}

/// The notes `--explain` adds: for the joint being drawn, what each call does and reads.
struct Explain {
    language: Language,
    mode: crate::model::pose::OffsetMode,
    joints: Vec<JointFacts>,
    /// Values in a row of the file, and in a row as the article reads it (`jointCount * 3 + 3`).
    widths: (usize, usize),
    /// The joints whose calls are under way, innermost last, with the rotations and the axis
    /// matrices (C, then C⁻¹) issued so far.
    open: Vec<(usize, usize, usize)>,
}

/// Collects the calls as lines, and follows the modelview matrix (so that a draw that saves it,
/// for skeletons deeper than the GL matrix stack, records the right values).
///
/// ```
/// use bvhview::render::{scene, trace::{Numbers, Recorder}};
///
/// let mut recorder = Recorder::new(Numbers::Apitrace);
/// scene::init(&mut recorder); // the article's `init`, one line of C per call
/// assert_eq!(recorder.lines[0], "glClearColor(0, 0, 0, 0);");
/// assert!(recorder.text().ends_with(";\n"));
/// ```
pub struct Recorder {
    /// How the lines write numbers.
    pub numbers: Numbers,
    /// One line of C per call, in order (with `--explain`'s notes between them).
    pub lines: Vec<String>,
    modelview: Vec<glam::DMat4>,
    in_modelview: bool,
    explain: Option<Explain>,
    /// Where each joint's calls start: (joint, index into `lines`).
    pub joint_starts: Vec<(usize, usize)>,
}

impl Recorder {
    /// A recorder with no lines yet, the modelview matrix the identity.
    pub fn new(numbers: Numbers) -> Recorder {
        Recorder {
            numbers,
            lines: Vec::new(),
            modelview: vec![glam::DMat4::IDENTITY],
            in_modelview: true,
            explain: None,
            joint_starts: Vec::new(),
        }
    }

    /// A recorder that also explains the draw of `skeleton` at `frame` (`None`: the rest pose):
    /// first what the article's program does with the file as a whole (`article`, from
    /// [`crate::bvh::article::run_file`]), then each call indented by the depth of the matrix
    /// stack, with a note on what it does, which joint it belongs to, the MOTION columns it reads
    /// (as the article's `pFrame[i]`), what the article's flags make of the joint, and where
    /// each sphere lands in the world.
    pub fn explaining(
        numbers: Numbers,
        skeleton: &crate::model::skeleton::Skeleton,
        frame: Option<&[f32]>,
        mode: crate::model::pose::OffsetMode,
        language: Language,
        article: Option<&crate::bvh::article::Outcome>,
    ) -> Recorder {
        let flags = article_flags(skeleton, article);
        let joints = joint_facts(skeleton, frame, mode, flags);
        let article_joints = skeleton.joints.iter().filter(|j| !j.end_site).count();
        let widths = (skeleton.channel_count(), article_joints * 3 + 3);
        let mut recorder = Recorder {
            explain: Some(Explain {
                language,
                mode,
                joints,
                widths,
                open: Vec::new(),
            }),
            ..Recorder::new(numbers)
        };
        if let Some(outcome) = article {
            recorder.lines.extend(outcome_lines(outcome, language));
        }
        recorder
    }

    /// All lines, each ending in a newline.
    pub fn text(&self) -> String {
        let mut out = String::new();
        for line in &self.lines {
            out.push_str(line);
            out.push('\n');
        }
        out
    }

    fn float(&self, value: f32) -> String {
        match self.numbers {
            Numbers::Apitrace | Numbers::Short => format_g(value as f64, 7),
            Numbers::Printf => format!("{:.6}", value as f64),
        }
    }

    fn double(&self, value: f64) -> String {
        match self.numbers {
            Numbers::Apitrace => format_g(value, 16),
            Numbers::Short => format_g(value, 7),
            Numbers::Printf => format!("{value:.6}"),
        }
    }

    fn floats(&self, values: &[f32]) -> String {
        values
            .iter()
            .map(|&v| self.float(v))
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn doubles(&self, values: &[f64]) -> String {
        values
            .iter()
            .map(|&v| self.double(v))
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn call(&mut self, name: &str, arguments: &str) {
        let line = format!("{name}({arguments});");
        let Some(explain) = &self.explain else {
            self.lines.push(line);
            return;
        };
        // The matrix stack's depth; a push's own line stays out, a pop's comes back first.
        let depth = self.modelview.len() - 1 - usize::from(name == "glPushMatrix");
        let indented = format!("{}{line}", "    ".repeat(depth));
        let note = self.note_for(name, explain.language);
        self.lines.push(match note {
            Some(note) => format!("{indented:<52} // {note}"),
            None => indented,
        });
    }

    /// A number as the trace writes it, for notes.
    fn number(&self, value: f32) -> String {
        match self.numbers {
            Numbers::Apitrace | Numbers::Short => format_g(value as f64, 7),
            Numbers::Printf => format_g(value as f64, 6),
        }
    }

    fn point(&self, p: glam::Vec3) -> String {
        format!(
            "({}, {}, {})",
            self.number(p.x),
            self.number(p.y),
            self.number(p.z)
        )
    }

    /// The note for a call of the joint being drawn, if any.
    fn note_for(&mut self, name: &str, language: Language) -> Option<String> {
        let depth = self.modelview.len() - 1;
        let explain = self.explain.as_ref()?;
        let &(index, rotations_done, axes_done) = explain.open.last()?;
        let joint = &explain.joints[index];
        let [english, chinese] = match name {
            "glPushMatrix" => [
                format!("{}: push, stack depth {depth}", joint.name),
                format!("{}：推入矩陣堆疊，深度 {depth}", joint.name),
            ],
            "glPopMatrix" => [
                format!("{} done: pop, back to depth {depth}", joint.name),
                format!("{} 畫完：彈出，回到深度 {depth}", joint.name),
            ],
            "glTranslatef" => self.translation_note(joint, explain.mode),
            "glRotatef" => {
                let &(column, channel) = joint.rotation_columns.get(rotations_done)?;
                let note = rotation_note(joint, explain.widths, column, channel, rotations_done);
                let last = explain.open.len() - 1;
                self.explain.as_mut()?.open[last].1 += 1;
                note
            }
            "glMultMatrixf" => {
                let last = explain.open.len() - 1;
                self.explain.as_mut()?.open[last].2 += 1;
                match axes_done {
                    0 => both("the bone's own axis C (ASF)", "骨骼自己的軸 C（ASF）"),
                    _ => both("and C⁻¹: the channels turn about C", "C 的反矩陣 C⁻¹"),
                }
            }
            "glutSolidSphere" => {
                let world = self.point(joint.world);
                [
                    format!("{}'s sphere, at {world} in the world", joint.name),
                    format!("{} 的球，世界座標 {world}", joint.name),
                ]
            }
            _ => return None,
        };
        Some(match language {
            Language::English => english,
            Language::Chinese => chinese,
        })
    }

    /// The note on a joint's `glTranslatef`: its OFFSET and the position channels that replace
    /// or add to it, then what the article translates by where that differs.
    fn translation_note(&self, joint: &JointFacts, mode: crate::model::pose::OffsetMode) -> Both {
        let offset = self.point(joint.offset);
        let replaced: Vec<String> = joint
            .position_columns
            .iter()
            .map(|(column, channel)| format!("{channel} = [{column}]"))
            .collect();
        let add = mode == crate::model::pose::OffsetMode::Add;
        let replaced = replaced.join(", ");
        let [ours_en, ours_zh] = match (replaced.is_empty(), add) {
            (true, _) => [format!("OFFSET {offset}"), format!("OFFSET {offset}")],
            (false, false) => [
                format!("OFFSET {offset}, replaced by {replaced}"),
                format!("OFFSET {offset}，位置通道取代其分量：{replaced}"),
            ],
            (false, true) => [
                format!("OFFSET {offset} plus {replaced}"),
                format!("OFFSET {offset}，加上位置通道：{replaced}"),
            ],
        };
        // What the article translates by, where it is not that.
        let article = match joint.root_translation {
            Some(row) => Some([
                format!(
                    "the article translates by columns [0], [1], [2] as x, y, z: {}",
                    plain(&row)
                ),
                format!(
                    "原文把第 [0]、[1]、[2] 欄當作 x、y、z 平移：{}",
                    plain(&row)
                ),
            ]),
            None if joint.is_root || replaced.is_empty() => None,
            None => Some(both(
                "the article translates by the OFFSET alone",
                "原文只用 OFFSET 平移",
            )),
        };
        match article {
            Some([article_en, article_zh]) => [
                format!("{ours_en}; {article_en}"),
                format!("{ours_zh}；{article_zh}"),
            ],
            None => [ours_en, ours_zh],
        }
    }

    /// Applies `m` to the current modelview matrix, if modelview is the current mode.
    fn multiply(&mut self, m: glam::DMat4) {
        if self.in_modelview {
            let top = self.modelview.last_mut().expect("the stack is never empty");
            *top *= m;
        }
    }
}

/// The article's flags for each joint: from its own tree where it loaded one joint for joint
/// like bvhview's, else from the channels as if the file were laid out as the article needs.
fn article_flags(
    skeleton: &crate::model::skeleton::Skeleton,
    article: Option<&crate::bvh::article::Outcome>,
) -> Vec<u8> {
    let loaded = article
        .and_then(|outcome| outcome.joints.as_ref())
        .filter(|joints| {
            joints.len() == skeleton.joints.len()
                && joints
                    .iter()
                    .zip(&skeleton.joints)
                    .all(|(a, j)| (a.depth == 0) == j.parent.is_none())
        });
    match loaded {
        Some(joints) => joints.iter().map(|j| j.flags).collect(),
        None => skeleton.joints.iter().map(channel_flags).collect(),
    }
}

/// What `--explain` says about each joint, in pre-order: a joint's number and the article's
/// `pFrame` follow the joints before it.
fn joint_facts(
    skeleton: &crate::model::skeleton::Skeleton,
    frame: Option<&[f32]>,
    mode: crate::model::pose::OffsetMode,
    flags: Vec<u8>,
) -> Vec<JointFacts> {
    let world = crate::model::pose::world_positions(skeleton, frame.unwrap_or(&[]), mode);
    let mut joints_before = 0;
    let mut turned_before = 0;
    skeleton
        .joints
        .iter()
        .zip(world)
        .zip(flags)
        .map(|((joint, world), article_flags)| {
            // The article's pFrame moves on by 3 after a joint only when its flags are not 0.
            let article_column = 3 + 3 * turned_before;
            if article_flags != 0 {
                turned_before += 1;
            }
            let label = if joint.end_site {
                let parent = joint
                    .parent
                    .map_or("", |p| skeleton.joints[p].name.as_str());
                Label::EndSiteOf(parent.to_string())
            } else {
                joints_before += 1;
                Label::Joint(joints_before - 1)
            };
            JointFacts {
                name: joint.name.clone(),
                label,
                article_column,
                article_flags,
                article_axes: crate::bvh::article::axes_turned(article_flags),
                root_translation: root_translation(joint, frame),
                columns: joint.first_channel..joint.first_channel + joint.channels.len(),
                rotation_columns: columns_of(joint, true),
                position_columns: columns_of(joint, false),
                offset: joint.offset,
                world,
                is_root: joint.parent.is_none(),
            }
        })
        .collect()
}

/// A joint's MOTION columns with their channels: its rotations (`rotation`) or its positions.
fn columns_of(
    joint: &crate::model::skeleton::Joint,
    rotation: bool,
) -> Vec<(usize, crate::model::skeleton::Channel)> {
    joint
        .channels
        .iter()
        .enumerate()
        .filter(|(_, c)| c.is_rotation() == rotation)
        .map(|(i, &c)| (joint.first_channel + i, c))
        .collect()
}

/// What the article translates the root by in `frame`: columns 0, 1 and 2 as x, y and z. Said
/// only where the root's first three channels are not Xposition, Yposition, Zposition.
fn root_translation(
    joint: &crate::model::skeleton::Joint,
    frame: Option<&[f32]>,
) -> Option<[f32; 3]> {
    let xyz_first = joint
        .channels
        .iter()
        .take(3)
        .map(|c| c.is_position().then_some(c.axis()))
        .eq([Some(0), Some(1), Some(2)]);
    match frame {
        Some(row) if joint.parent.is_none() && !xyz_first && row.len() >= 3 => {
            Some([row[0], row[1], row[2]])
        }
        _ => None,
    }
}

/// The lines before the calls: the verdict on the file, what GL's stack says of the article's
/// draw, and whether the article's program got as far as drawing.
fn outcome_lines(outcome: &crate::bvh::article::Outcome, language: Language) -> Vec<String> {
    let mut lines = vec![verdict_line(&outcome.verdict, language)];
    if let Some(stack) = &outcome.gl_stack {
        lines.push(gl_stack_line(stack, language));
    }
    // It never drew: what the notes say of it is what its draw would do.
    if outcome.joints.is_none() {
        lines.push(match language {
            Language::English => "// the article's program stops before it draws: the notes below say what its draw would make of each joint's channels".to_string(),
            Language::Chinese => "// 原文的程式在 draw 之前就停了：以下的註解說明它的 draw 會怎麼處理每個關節的通道".to_string(),
        });
    }
    lines
}

/// The note on the `i`-th `glRotatef` of a joint, for the rotation channel at `column`: the
/// column the article's `pFrame[i]` reads and the axis it turns about, where either differs
/// from the file's (`widths`: values in a row of the file, and in a row as the article reads it).
fn rotation_note(
    joint: &JointFacts,
    (file_width, article_width): (usize, usize),
    column: usize,
    channel: crate::model::skeleton::Channel,
    i: usize,
) -> Both {
    let flags = joint.article_flags;
    let Some(axes) = joint.article_axes else {
        return [
            format!(
                "{channel}: column [{column}]; the article does not turn this joint (its flags are {flags})"
            ),
            format!("{channel}：第 [{column}] 欄；原文不轉這個關節（它的 flags 是 {flags}）"),
        ];
    };
    let Some(&axis) = axes.get(i) else {
        return [
            format!("{channel}: column [{column}]; the article turns this joint three times only"),
            format!("{channel}：第 [{column}] 欄；原文只轉這個關節三次"),
        ];
    };
    let letter = ["X", "Y", "Z"][axis];
    let article = joint.article_column + i;
    // Where the article's value lies: a column of the file, or past the end of the file's rows
    // (its rows are wider).
    let [article_en, article_zh] = if article < file_width {
        [format!("column [{article}]"), format!("第 [{article}] 欄")]
    } else {
        [
            format!(
                "[{article}] of its rows of {article_width} values (jointCount * 3 + 3), past the end of the file's rows of {file_width}"
            ),
            format!(
                "它每列 {article_width} 個值（jointCount * 3 + 3）中的第 [{article}] 個，超過檔案每列 {file_width} 個值的結尾"
            ),
        ]
    };
    let [another_en, another_zh] = if article < file_width {
        both(", another channel's value", "，另一個通道的值")
    } else {
        both("", "")
    };
    match (axis == channel.axis(), article == column) {
        (true, true) => [
            format!("{channel}: column [{column}], the article's pFrame[{i}]"),
            format!("{channel}：第 [{column}] 欄，即 pFrame[{i}]"),
        ],
        (true, false) => [
            format!(
                "{channel}: column [{column}]; the article's pFrame[{i}] is {article_en}{another_en}"
            ),
            format!("{channel}：第 [{column}] 欄；原文的 pFrame[{i}] 卻是{article_zh}{another_zh}"),
        ],
        (false, true) => [
            format!(
                "{channel}: column [{column}]; the article turns about {letter} here, by the same pFrame[{i}]"
            ),
            format!(
                "{channel}：第 [{column}] 欄；原文在這裡繞 {letter} 軸旋轉，用的是同一個 pFrame[{i}]"
            ),
        ],
        (false, false) => [
            format!(
                "{channel}: column [{column}]; the article turns about {letter} here, by pFrame[{i}], {article_en}"
            ),
            format!(
                "{channel}：第 [{column}] 欄；原文在這裡繞 {letter} 軸旋轉，用的是 pFrame[{i}]，即{article_zh}"
            ),
        ],
    }
}

/// C's `%.{precision}g`: `precision` significant digits, trailing zeros dropped, scientific
/// notation when the exponent is below −4 or at least `precision`.
pub fn format_g(value: f64, precision: usize) -> String {
    if value == 0.0 {
        return if value.is_sign_negative() { "-0" } else { "0" }.to_string();
    }
    if !value.is_finite() {
        return format!("{value}");
    }
    let scientific = format!("{:.*e}", precision - 1, value);
    let (mantissa, exponent) = scientific.split_once('e').expect("{:e} has an exponent");
    let exponent: i32 = exponent.parse().expect("{:e} writes an integer exponent");
    let trim = |s: &str| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if exponent < -4 || exponent >= precision as i32 {
        let sign = if exponent < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", trim(mantissa), exponent.abs())
    } else {
        let decimals = (precision as i32 - 1 - exponent).max(0) as usize;
        trim(&format!("{value:.decimals$}"))
    }
}

fn enum_name(value: u32, names: &[(u32, &'static str)]) -> String {
    names
        .iter()
        .find(|(v, _)| *v == value)
        .map_or_else(|| format!("0x{value:04X}"), |(_, n)| n.to_string())
}

const CAPS: &[(u32, &str)] = &[
    (GL_DEPTH_TEST, "GL_DEPTH_TEST"),
    (GL_LIGHTING, "GL_LIGHTING"),
    (GL_LIGHT0, "GL_LIGHT0"),
    (GL_CULL_FACE, "GL_CULL_FACE"),
    (GL_NORMALIZE, "GL_NORMALIZE"),
];
const MODES: &[(u32, &str)] = &[
    (GL_QUADS, "GL_QUADS"),
    (GL_LINES, "GL_LINES"),
    (GL_LINE_LOOP, "GL_LINE_LOOP"),
    (GL_LINE_STRIP, "GL_LINE_STRIP"),
    (GL_TRIANGLE_STRIP, "GL_TRIANGLE_STRIP"),
];
const MATRICES: &[(u32, &str)] = &[
    (GL_MODELVIEW, "GL_MODELVIEW"),
    (GL_PROJECTION, "GL_PROJECTION"),
];

impl FixedFunction for Recorder {
    fn clear_color(&mut self, r: f32, g: f32, b: f32, a: f32) {
        let args = self.floats(&[r, g, b, a]);
        self.call("glClearColor", &args);
    }
    fn clear(&mut self, mask: u32) {
        let mut bits = Vec::new();
        if mask & GL_DEPTH_BUFFER_BIT != 0 {
            bits.push("GL_DEPTH_BUFFER_BIT");
        }
        if mask & GL_COLOR_BUFFER_BIT != 0 {
            bits.push("GL_COLOR_BUFFER_BIT");
        }
        self.call("glClear", &bits.join(" | "));
    }
    fn enable(&mut self, cap: u32) {
        self.call("glEnable", &enum_name(cap, CAPS));
    }
    fn disable(&mut self, cap: u32) {
        self.call("glDisable", &enum_name(cap, CAPS));
    }
    fn lightfv(&mut self, light: u32, pname: u32, params: [f32; 4]) {
        let pname = if pname == GL_POSITION {
            "GL_POSITION".to_string()
        } else {
            format!("0x{pname:04X}")
        };
        let args = format!(
            "{}, {pname}, {{{}}}",
            enum_name(light, CAPS),
            self.floats(&params)
        );
        self.call("glLightfv", &args);
    }
    fn materialfv(&mut self, pname: u32, params: [f32; 4]) {
        let args = format!(
            "GL_FRONT_AND_BACK, 0x{pname:04X}, {{{}}}",
            self.floats(&params)
        );
        self.call("glMaterialfv", &args);
    }
    fn line_width(&mut self, width: f32) {
        let args = self.float(width);
        self.call("glLineWidth", &args);
    }
    fn color3f(&mut self, r: f32, g: f32, b: f32) {
        let args = self.floats(&[r, g, b]);
        self.call("glColor3f", &args);
    }
    fn viewport(&mut self, x: i32, y: i32, width: i32, height: i32) {
        self.call("glViewport", &format!("{x}, {y}, {width}, {height}"));
    }
    fn matrix_mode(&mut self, mode: u32) {
        self.in_modelview = mode == GL_MODELVIEW;
        self.call("glMatrixMode", &enum_name(mode, MATRICES));
    }
    fn load_identity(&mut self) {
        if self.in_modelview {
            *self.modelview.last_mut().expect("never empty") = glam::DMat4::IDENTITY;
        }
        self.call("glLoadIdentity", "");
    }
    fn mult_matrixf(&mut self, m: &[f32; 16]) {
        self.multiply(glam::Mat4::from_cols_array(m).as_dmat4());
        let args = format!("{{{}}}", self.floats(m));
        self.call("glMultMatrixf", &args);
    }
    fn mult_matrixd(&mut self, m: &[f64; 16]) {
        self.multiply(glam::DMat4::from_cols_array(m));
        let args = format!("{{{}}}", self.doubles(m));
        self.call("glMultMatrixd", &args);
    }
    fn push_matrix(&mut self) {
        if self.in_modelview {
            let top = *self.modelview.last().expect("never empty");
            self.modelview.push(top);
        }
        self.call("glPushMatrix", "");
    }
    fn pop_matrix(&mut self) {
        if self.in_modelview && self.modelview.len() > 1 {
            self.modelview.pop();
        }
        self.call("glPopMatrix", "");
    }
    fn translatef(&mut self, x: f32, y: f32, z: f32) {
        self.multiply(glam::DMat4::from_translation(glam::DVec3::new(
            x.into(),
            y.into(),
            z.into(),
        )));
        let args = self.floats(&[x, y, z]);
        self.call("glTranslatef", &args);
    }
    fn translated(&mut self, x: f64, y: f64, z: f64) {
        self.multiply(glam::DMat4::from_translation(glam::DVec3::new(x, y, z)));
        let args = self.doubles(&[x, y, z]);
        self.call("glTranslated", &args);
    }
    fn rotatef(&mut self, angle: f32, x: f32, y: f32, z: f32) {
        let axis = glam::DVec3::new(x.into(), y.into(), z.into());
        if axis.length_squared() > 0.0 {
            self.multiply(glam::DMat4::from_axis_angle(
                axis.normalize(),
                f64::from(angle).to_radians(),
            ));
        }
        let args = self.floats(&[angle, x, y, z]);
        self.call("glRotatef", &args);
    }
    fn draw_triangles(
        &mut self,
        positions: &[glam::Vec3],
        _normals: &[glam::Vec3],
        indices: &[u32],
    ) {
        let args = format!(
            "GL_TRIANGLES, {}, GL_UNSIGNED_INT, skin /* {} vertices */",
            indices.len(),
            positions.len()
        );
        self.call("glDrawElements", &args);
    }
    fn get_modelview(&mut self) -> [f32; 16] {
        self.call("glGetFloatv", "GL_MODELVIEW_MATRIX, m");
        self.modelview
            .last()
            .expect("never empty")
            .as_mat4()
            .to_cols_array()
    }
    fn load_matrix(&mut self, m: &[f32; 16]) {
        if self.in_modelview {
            *self.modelview.last_mut().expect("never empty") =
                glam::Mat4::from_cols_array(m).as_dmat4();
        }
        let args = format!("{{{}}}", self.floats(m));
        self.call("glLoadMatrixf", &args);
    }
    fn begin(&mut self, mode: u32) {
        self.call("glBegin", &enum_name(mode, MODES));
    }
    fn end(&mut self) {
        self.call("glEnd", "");
    }
    fn vertex3f(&mut self, x: f32, y: f32, z: f32) {
        let args = self.floats(&[x, y, z]);
        self.call("glVertex3f", &args);
    }
    fn normal3f(&mut self, x: f32, y: f32, z: f32) {
        let args = self.floats(&[x, y, z]);
        self.call("glNormal3f", &args);
    }
    fn window_pos(&mut self, x: i32, y: i32) {
        self.call("glWindowPos2i", &format!("{x}, {y}"));
    }
    fn raster_pos(&mut self, x: f32, y: f32, z: f32) {
        let args = format!("{}, {}, {}", self.float(x), self.float(y), self.float(z));
        self.call("glRasterPos3f", &args);
    }
    fn bitmap(&mut self, width: i32, height: i32, advance: f32, _bits: &[u8]) {
        let args = format!("{width}, {height}, 0, 0, {}, 0, glyph", self.float(advance));
        self.call("glBitmap", &args);
    }
    fn note(&mut self, note: Note) {
        if let Note::Joint(index) = note {
            self.joint_starts.push((index, self.lines.len()));
        }
        let Some(explain) = &mut self.explain else {
            return;
        };
        match note {
            Note::Joint(index) => {
                explain.open.push((index, 0, 0));
                let depth = self.modelview.len() - 1;
                let joint = &explain.joints[index];
                let columns = if joint.columns.is_empty() {
                    match explain.language {
                        Language::Chinese => "沒有 MOTION 欄位".to_string(),
                        Language::English => "no MOTION columns".to_string(),
                    }
                } else {
                    let (a, b) = (joint.columns.start, joint.columns.end - 1);
                    let range = if a == b {
                        format!("[{a}]")
                    } else {
                        format!("[{a}]–[{b}]")
                    };
                    match explain.language {
                        Language::Chinese => format!("MOTION 第 {range} 欄"),
                        Language::English => format!("MOTION columns {range}"),
                    }
                };
                let flags = joint.flags_note(explain.language);
                let header = match (&joint.label, explain.language) {
                    (Label::Joint(n), Language::Chinese) => {
                        format!("// 關節 {n} {}：{columns}；{flags}", joint.name)
                    }
                    (Label::Joint(n), Language::English) => {
                        format!("// joint {n}, {}: {columns}; {flags}", joint.name)
                    }
                    (Label::EndSiteOf(parent), Language::Chinese) => {
                        format!("// {parent} 的 End Site：{columns}")
                    }
                    (Label::EndSiteOf(parent), Language::English) => {
                        format!("// End Site of {parent}: {columns}")
                    }
                };
                self.lines.push(format!("{}{header}", "    ".repeat(depth)));
            }
            Note::JointEnd => {
                explain.open.pop();
            }
        }
    }
    /// freeglut's inner calls (client arrays, 16 strips) collapse into this one line.
    fn solid_sphere(&mut self, radius: f64, slices: i32, stacks: i32) {
        let args = format!("{}, {slices}, {stacks}", self.double(radius));
        self.call("glutSolidSphere", &args);
    }
}

#[cfg(test)]
mod tests {
    use super::format_g;

    #[test]
    fn format_g_is_c_general_notation() {
        assert_eq!(format_g(-0.5440211, 7), "-0.5440211");
        assert_eq!(format_g(167.81430053710938, 16), "167.8143005371094");
        assert_eq!(format_g(2.414213562373095, 16), "2.414213562373095");
        assert_eq!(format_g(30.0, 7), "30");
        assert_eq!(format_g(-0.0, 7), "-0");
        assert_eq!(format_g(0.0001, 7), "0.0001");
        assert_eq!(format_g(0.00001234, 7), "1.234e-05");
        assert_eq!(format_g(12345678.0, 7), "1.234568e+07");
    }
}
