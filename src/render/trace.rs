//! A recording implementation of the GL table: the scene and draw code run unchanged and every
//! call becomes one line of C. The window and the snapshots run the same code against real GL,
//! so what the trace shows is what they draw.

use crate::render::fixed::*;

/// How numbers are written.
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

/// The language of `--explain`'s notes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Language {
    #[default]
    English,
    /// Traditional Chinese, in the article's terms.
    Chinese,
}

/// What `--explain` says about one joint.
struct JointFacts {
    name: String,
    /// How `info` counts it: the n-th joint (End Sites apart), or the End Site of its parent.
    label: Label,
    /// The column the article's `pFrame` points at when it turns this joint: 3 past the root's
    /// positions, 3 more for each joint before it whose flags are not 0.
    article_column: usize,
    /// Whether the article turns it at all (its flags are not 0).
    article_turns: bool,
    /// Its MOTION columns, and which of them are rotations (in file order).
    columns: std::ops::Range<usize>,
    rotation_columns: Vec<(usize, crate::skeleton::Channel)>,
    position_columns: Vec<(usize, crate::skeleton::Channel)>,
    offset: glam::Vec3,
    /// Where its sphere lands, from `pose` (not from the recorded matrices).
    world: glam::Vec3,
}

/// Why the article's program cannot load a file, as far as its skeleton shows (its bytes, line
/// ends and number widths aside): the cases its `loadFile` and `addChild` fail or misread.
enum ArticleCannot {
    /// `jointCount == 1`: `loadFile` returns false for a skeleton of one joint.
    OneJoint,
    /// More than 16 children: `child[CHILDSIZE]` overflows (the assert checks 24).
    Children(String, usize),
    /// Channels other than the root's three positions and three rotations, or another joint's
    /// three rotations: `pFrame` reads other columns from there on.
    Channels(String),
    /// Rotation letters whose flags sum to 0 (`Yrotation Yrotation Xrotation`): the joint is
    /// taken for an End Site, not turned, and `pFrame` does not move on.
    Flags(String),
}

impl ArticleCannot {
    fn of(skeleton: &crate::skeleton::Skeleton) -> Option<ArticleCannot> {
        let joints: Vec<_> = skeleton.joints.iter().filter(|j| !j.end_site).collect();
        if joints.len() == 1 {
            return Some(ArticleCannot::OneJoint);
        }
        if let Some(joint) = skeleton.joints.iter().find(|j| j.children.len() > 16) {
            return Some(ArticleCannot::Children(
                joint.name.clone(),
                joint.children.len(),
            ));
        }
        let layout = |joint: &&crate::skeleton::Joint| {
            let rotations = joint.channels.iter().filter(|c| c.is_rotation()).count();
            let positions_first = joint.channels.iter().take(3).all(|c| c.is_position());
            match joint.parent {
                None => joint.channels.len() == 6 && positions_first && rotations == 3,
                Some(_) => joint.channels.len() == 3 && rotations == 3,
            }
        };
        // A joint whose letters make flags 0 does not move pFrame on: everything after reads
        // another joint's columns.
        let odd = joints
            .iter()
            .find(|j| !layout(j) || article_flags(j) == 0)?;
        Some(if layout(odd) {
            ArticleCannot::Flags(odd.name.clone())
        } else {
            ArticleCannot::Channels(odd.name.clone())
        })
    }

    fn note(&self, language: Language) -> String {
        match (self, language) {
            (ArticleCannot::OneJoint, Language::English) => "// note: the article's program cannot load this file (a skeleton of one joint: loadFile returns false when jointCount == 1); the calls below are bvhview's".to_string(),
            (ArticleCannot::OneJoint, Language::Chinese) => "// 注意：原文的程式無法載入這個檔案（只有一個關節：jointCount == 1 時 loadFile 傳回 false）；以下是 bvhview 的呼叫".to_string(),
            (ArticleCannot::Children(name, n), Language::English) => format!("// note: the article's program cannot load this file ('{name}' has {n} children; its child array holds 16); the calls below are bvhview's"),
            (ArticleCannot::Children(name, n), Language::Chinese) => format!("// 注意：原文的程式無法載入這個檔案（'{name}' 有 {n} 個子關節，它的陣列只放得下 16 個）；以下是 bvhview 的呼叫"),
            (ArticleCannot::Channels(name), Language::English) => format!("// note: the article's program misreads this file (the channels of '{name}' are not the three positions and three rotations of a root, or the three rotations of a joint: from there its pFrame reads other columns); the calls below are bvhview's"),
            (ArticleCannot::Flags(name), Language::English) => format!("// note: the article's program misreads this file (the rotation letters of '{name}' make its flags 0: it is not turned, and pFrame stays, so every later joint reads other columns); the calls below are bvhview's"),
            (ArticleCannot::Flags(name), Language::Chinese) => format!("// 注意：原文的程式會讀錯這個檔案（'{name}' 的旋轉字母使 flags 為 0：它不轉，pFrame 也不前進，之後每個關節都讀到別的欄）；以下是 bvhview 的呼叫"),
            (ArticleCannot::Channels(name), Language::Chinese) => format!("// 注意：原文的程式會讀錯這個檔案（'{name}' 的通道不是根關節的三個位置加三個旋轉，也不是一般關節的三個旋轉：從那裡起它的 pFrame 讀到別的欄）；以下是 bvhview 的呼叫"),
        }
    }
}

/// C++: `BVH::getFlags`: the article's code for a joint's rotation order, from the letters of
/// its (root: last; others: first) three channels, X = 1, Y = 2, Z = 3, weighted 1, 2 and 4,
/// less 10: `ZYX` is 1 … `XYZ` is 7, and a repeated letter can make 0 (`Y Y X`), which the
/// article takes for an End Site. End Sites have no CHANNELS line: 0.
fn article_flags(joint: &crate::skeleton::Joint) -> i32 {
    if joint.end_site || joint.channels.len() < 3 {
        return 0;
    }
    let letters = match joint.parent {
        None => &joint.channels[joint.channels.len() - 3..],
        Some(_) => &joint.channels[..3],
    };
    letters
        .iter()
        .zip([1, 2, 4])
        .map(|(channel, weight)| (channel.axis() as i32 + 1) * weight)
        .sum::<i32>()
        - 10
}

/// A joint as `info` counts it.
enum Label {
    Joint(usize),
    EndSiteOf(String),
}

/// The notes `--explain` adds: for the joint being drawn, what each call does and reads.
struct Explain {
    language: Language,
    mode: crate::pose::OffsetMode,
    joints: Vec<JointFacts>,
    /// Why the article's program cannot load the file, said once before the first joint.
    article_cannot: Option<ArticleCannot>,
    /// The joints whose calls are under way, innermost last, with the rotations and the axis
    /// matrices (C, then C⁻¹) issued so far.
    open: Vec<(usize, usize, usize)>,
}

/// Collects the calls as lines, and follows the modelview matrix (so that a draw that saves it,
/// for skeletons deeper than the GL matrix stack, records the right values).
pub struct Recorder {
    pub numbers: Numbers,
    pub lines: Vec<String>,
    modelview: Vec<glam::DMat4>,
    in_modelview: bool,
    explain: Option<Explain>,
    /// Where each joint's calls start: (joint, index into `lines`).
    pub joint_starts: Vec<(usize, usize)>,
}

impl Recorder {
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
    /// each call indented by the depth of the matrix stack, and a note on what it does, which
    /// joint it belongs to, the MOTION columns it reads (as the article's `pFrame[i]`) and where
    /// each sphere lands in the world.
    pub fn explaining(
        numbers: Numbers,
        skeleton: &crate::skeleton::Skeleton,
        frame: Option<&[f32]>,
        mode: crate::pose::OffsetMode,
        language: Language,
    ) -> Recorder {
        let world = crate::pose::world_positions(skeleton, frame.unwrap_or(&[]), mode);
        // Pre-order: a joint's number and the article's `pFrame` follow the joints before it.
        let mut joints_before = 0;
        let mut turned_before = 0;
        let joints = skeleton
            .joints
            .iter()
            .zip(world)
            .map(|(joint, world)| {
                // The article's pFrame moves on by 3 after a joint only when its flags are not 0.
                let article_column = 3 + 3 * turned_before;
                if article_flags(joint) != 0 {
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
                let columns_of = |rotation: bool| {
                    joint
                        .channels
                        .iter()
                        .enumerate()
                        .filter(|(_, c)| c.is_rotation() == rotation)
                        .map(|(i, &c)| (joint.first_channel + i, c))
                        .collect()
                };
                JointFacts {
                    name: joint.name.clone(),
                    label,
                    article_column,
                    article_turns: article_flags(joint) != 0,
                    columns: joint.first_channel..joint.first_channel + joint.channels.len(),
                    rotation_columns: columns_of(true),
                    position_columns: columns_of(false),
                    offset: joint.offset,
                    world,
                }
            })
            .collect();
        Recorder {
            explain: Some(Explain {
                language,
                mode,
                joints,
                article_cannot: ArticleCannot::of(skeleton),
                open: Vec::new(),
            }),
            ..Recorder::new(numbers)
        }
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
        let zh = language == Language::Chinese;
        let depth = self.modelview.len() - 1;
        let explain = self.explain.as_ref()?;
        let &(index, rotations_done, axes_done) = explain.open.last()?;
        let joint = &explain.joints[index];
        let note = match name {
            "glPushMatrix" if zh => format!("{}：推入矩陣堆疊，深度 {depth}", joint.name),
            "glPushMatrix" => format!("{}: push, stack depth {depth}", joint.name),
            "glPopMatrix" if zh => format!("{} 畫完：彈出，回到深度 {depth}", joint.name),
            "glPopMatrix" => format!("{} done: pop, back to depth {depth}", joint.name),
            "glTranslatef" => {
                let offset = self.point(joint.offset);
                let replaced: Vec<String> = joint
                    .position_columns
                    .iter()
                    .map(|(column, channel)| format!("{channel} = [{column}]"))
                    .collect();
                let add = explain.mode == crate::pose::OffsetMode::Add;
                let replaced = replaced.join(", ");
                match (replaced.is_empty(), add, zh) {
                    (true, _, true) => format!("OFFSET {offset}"),
                    (true, _, false) => format!("OFFSET {offset}"),
                    (false, false, true) => {
                        format!("OFFSET {offset}，位置通道取代其分量：{replaced}")
                    }
                    (false, true, true) => format!("OFFSET {offset}，加上位置通道：{replaced}"),
                    (false, false, false) => format!("OFFSET {offset}, replaced by {replaced}"),
                    (false, true, false) => format!("OFFSET {offset} plus {replaced}"),
                }
            }
            "glRotatef" => {
                let (column, channel) = *joint.rotation_columns.get(rotations_done)?;
                let article = joint.article_column + rotations_done;
                let turns = joint.article_turns;
                let last = explain.open.len() - 1;
                self.explain.as_mut()?.open[last].1 += 1;
                let i = rotations_done;
                if !turns {
                    return Some(if zh {
                        format!("{channel}：第 [{column}] 欄；原文不轉這個關節（它的 flags 是 0）")
                    } else {
                        format!(
                            "{channel}: column [{column}]; the article does not turn this joint (its flags are 0)"
                        )
                    });
                }
                match (article == column, zh) {
                    (true, true) => format!("{channel}：第 [{column}] 欄，即 pFrame[{i}]"),
                    (true, false) => {
                        format!("{channel}: column [{column}], the article's pFrame[{i}]")
                    }
                    (false, true) => format!(
                        "{channel}：第 [{column}] 欄；原文的 pFrame[{i}] 卻是第 [{article}] 欄，另一個通道的值"
                    ),
                    (false, false) => format!(
                        "{channel}: column [{column}]; the article's pFrame[{i}] is column [{article}], another channel's value"
                    ),
                }
            }
            "glMultMatrixf" => {
                let last = explain.open.len() - 1;
                self.explain.as_mut()?.open[last].2 += 1;
                match (axes_done, zh) {
                    (0, true) => "骨骼自己的軸 C（ASF）".to_string(),
                    (_, true) => "C 的反矩陣 C⁻¹".to_string(),
                    (0, false) => "the bone's own axis C (ASF)".to_string(),
                    (_, false) => "and C⁻¹: the channels turn about C".to_string(),
                }
            }
            "glutSolidSphere" => {
                let world = self.point(joint.world);
                if zh {
                    format!("{} 的球，世界座標 {world}", joint.name)
                } else {
                    format!("{}'s sphere, at {world} in the world", joint.name)
                }
            }
            _ => return None,
        };
        Some(note)
    }

    /// Applies `m` to the current modelview matrix, if modelview is the current mode.
    fn multiply(&mut self, m: glam::DMat4) {
        if self.in_modelview {
            let top = self.modelview.last_mut().expect("the stack is never empty");
            *top *= m;
        }
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
                // Said once, before the first joint.
                if let Some(cannot) = explain.article_cannot.take() {
                    let line = cannot.note(explain.language);
                    self.lines.push(format!("{}{line}", "    ".repeat(depth)));
                }
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
                let header = match (&joint.label, explain.language) {
                    (Label::Joint(n), Language::Chinese) => {
                        format!("// 關節 {n} {}：{columns}", joint.name)
                    }
                    (Label::Joint(n), Language::English) => {
                        format!("// joint {n}, {}: {columns}", joint.name)
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
