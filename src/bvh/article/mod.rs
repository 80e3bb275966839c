//! The article's program, run on a file's bytes: what its `loadFile`, `print` and `draw` do with
//! the file, as a whole, in one of four words (`bvhview trace --explain` says it first).
//!
//! C++: `BVH::loadFile` and the functions it calls (`newNode`, `getFlags`, `processJoint`,
//! `processOffset`, `processChannels`, `processEnd`, the braces), then `BVH::print` and
//! `BVH::draw`, step by step as the article wrote them: its fixed strides (`p += 7`, `p += 5`,
//! `p += 8`, `p += 30`, `p += 2`), its scans (`while(*p != 'F') p++`), `atof` and `atoi`, its
//! 16-child array and 24-byte names. Nothing here is bvhview's loader: this module repeats the
//! article's mistakes on purpose, to say what they do to a given file.
//!
//! Where the C++ would read or write memory it does not own, the run stops there: that is a
//! crash. The program rebuilt with AddressSanitizer stops at exactly such a read; the plain build
//! may die there (SIGSEGV) or run on with whatever bytes lie beyond. `tests/edge/README.md`
//! records what the rebuilt program does with every input of `tests/edge` and
//! `tests/oracle/inputs` and with the repository's files, and `tests/cli/trace_gl_calls.rs` requires this
//! module to give the same word for each.

use crate::io::lines::line_column;
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;
use std::path::Path;

mod c_library;
mod outcome;

use c_library::{c_strtod, is_c_space};
pub use outcome::*;

/// The axes `roateSpace` turns about for `flags`, in order (0, 1, 2 are X, Y, Z), or none: it
/// has cases for 1, 2, 3, 5, 6 and 7 only. Every flags but 0 moves `pFrame` on by three.
pub fn axes_turned(flags: u8) -> Option<[usize; 3]> {
    match flags {
        1 => Some([2, 1, 0]),
        2 => Some([1, 2, 0]),
        3 => Some([2, 0, 1]),
        5 => Some([0, 2, 1]),
        6 => Some([1, 0, 2]),
        7 => Some([0, 1, 2]),
        _ => None,
    }
}

/// C++: `BVH::getFlags` of three letters (`X`, `Y`, `Z`, or any other byte), as it computes
/// them: each letter less `'X'` plus 1, weighted 1, 2 and 4, less 10, cut to a byte.
pub fn get_flags(letters: [u8; 3]) -> u8 {
    let sum: i32 = letters
        .iter()
        .zip([1, 2, 4])
        .map(|(&letter, weight)| (i32::from(letter) - i32::from(b'X') + 1) * weight)
        .sum();
    (sum - 10) as u8
}

/// The largest `new float*[frameCount]` taken to succeed: 4 GiB of row pointers. Measured: 32 GiB
/// (`Frames: -1`) throws `std::bad_alloc` on a machine with 23 GB of memory and no swap.
const LARGEST_ALLOCATION: u64 = 4 << 30;

/// Runs the article's program on the file at `path`: its length as `ftell` gives it, then as
/// much of it as `int iFileSize` says, read whole as `fread` does. `written` is what bvhview
/// loads from the same file, if it loads it.
pub fn run_file(path: &Path, written: Option<(&Skeleton, &Motion)>) -> std::io::Result<Outcome> {
    use std::io::Read;
    let file = std::fs::File::open(path)?;
    let length = file.metadata()?.len();
    let size = i_file_size(length);
    let mut bytes = Vec::new();
    if size > 0 {
        file.take(size as u64).read_to_end(&mut bytes)?;
    }
    Ok(run(&bytes, length, written))
}

/// `int iFileSize = iEnd - iStart`: the length `ftell` returns, kept in 32 bits.
fn i_file_size(length: u64) -> i32 {
    length as u32 as i32
}

/// Runs the article's program on `bytes`, the start of a file `length` bytes long (all of it, or
/// at least the first `iFileSize` bytes). `written` is what bvhview loads from the same file.
pub fn run(bytes: &[u8], length: u64, written: Option<(&Skeleton, &Motion)>) -> Outcome {
    let size = i_file_size(length);
    if size < 0 {
        return Outcome {
            verdict: Verdict::Crashes(Crash::FileLength { length }),
            joints: None,
            gl_stack: None,
        };
    }
    let buffer = &bytes[..(size as usize).min(bytes.len())];
    let mut article = Article {
        buffer,
        p: 0,
        nodes: Vec::new(),
        father: Vec::new(),
        current: 0,
        joint_count: 1,
        garbage: Vec::new(),
        unnamed: None,
    };
    let loaded = match article.load_file() {
        Ok(loaded) => loaded,
        Err(Stop::Crash(crash)) => {
            return Outcome {
                verdict: Verdict::Crashes(crash),
                joints: None,
                gl_stack: None,
            };
        }
        Err(Stop::Reject(rejection)) => {
            return Outcome {
                verdict: Verdict::Rejects(rejection),
                joints: None,
                gl_stack: None,
            };
        }
    };
    let joints = article.pre_order();
    let (verdict, gl_stack) = match article.draw(&loaded) {
        Err(crash) => (Verdict::Crashes(crash), None),
        Ok(()) => {
            let walk = article.stack_walk(&loaded);
            let verdict = match article.misread(
                &loaded,
                &joints,
                buffer.len() as u64,
                length,
                written,
                &walk,
            ) {
                Some(misread) => Verdict::Misreads(misread),
                None => Verdict::ReadsAsWritten,
            };
            (verdict, walk.errors)
        }
    };
    Outcome {
        verdict,
        joints: Some(joints),
        gl_stack,
    }
}

/// `class BVHJoint`: what the article keeps of a joint.
struct Node {
    name: Vec<u8>,
    offset: [f32; 3],
    children: Vec<usize>,
    flags: u8,
}

/// Why a run stopped.
enum Stop {
    Crash(Crash),
    Reject(Rejection),
}

/// The motion `loadFile` read.
struct Loaded {
    frames: u32,
    /// `dataCount`: `jointCount * 3 + 3` values a row.
    width: usize,
    rows: Vec<f32>,
}

/// The article's `BVH` during `loadFile`: the buffer, `p`, the tree, `father`, `currentNode`,
/// `jointCount`; and the words `atof` read that are not numbers.
struct Article<'a> {
    buffer: &'a [u8],
    p: usize,
    nodes: Vec<Node>,
    father: Vec<usize>,
    current: usize,
    joint_count: u32,
    garbage: Vec<(String, f32, Place)>,
    /// Where the first `newNode` that copied no byte was called: it writes `name[-1]`.
    unnamed: Option<Place>,
}

/// What GL's stack does to the article's draw of frame 0 (see [`Article::stack_walk`]).
struct StackWalk {
    /// The first joint whose push GL ignores.
    overflow: Option<usize>,
    /// The first joint drawn from a matrix that is not its own (`Some(None)`: the floor).
    wrong: Option<Option<usize>>,
    /// Where that joint's sphere lands in frame 0, and where the file puts it.
    drawn: Option<([f32; 3], [f32; 3])>,
    errors: Option<GlStack>,
}

impl Article<'_> {
    fn place(&self, offset: usize) -> Place {
        let (line, column) = line_column(self.buffer, offset);
        Place { line, column }
    }

    /// `*p` in `step`; past the end of the buffer, a crash.
    fn byte(&self, step: Step) -> Result<u8, Stop> {
        self.at(self.p, step)
    }

    fn at(&self, offset: usize, step: Step) -> Result<u8, Stop> {
        self.buffer.get(offset).copied().ok_or_else(|| {
            Stop::Crash(Crash::ReadPast {
                step,
                at: self.place(self.buffer.len()),
            })
        })
    }

    /// `while(*p != byte) p++;`
    fn scan_to(&mut self, byte: u8, step: Step) -> Result<(), Stop> {
        while self.byte(step)? != byte {
            self.p += 1;
        }
        Ok(())
    }

    /// `while(*p != ' ' && *p != '\t') p++; p++;`
    fn past_blank(&mut self, step: Step) -> Result<(), Stop> {
        while !matches!(self.byte(step)?, b' ' | b'\t') {
            self.p += 1;
        }
        self.p += 1;
        Ok(())
    }

    /// `while(*p++ != '\n');`
    fn past_line_end(&mut self, step: Step) -> Result<(), Stop> {
        self.scan_to(b'\n', step)?;
        self.p += 1;
        Ok(())
    }

    /// `(float)atof((char*)p)`: the longest number at `p` (after any white space), 0 if there is
    /// none. A word that is not all number is noted: the article reads it without a word.
    fn atof(&mut self, step: Step) -> Result<f32, Stop> {
        // atof's reads are not checked by AddressSanitizer, but every caller reads on from here.
        self.byte(step)?;
        let text = &self.buffer[self.p..];
        let (value, used) = c_strtod(text);
        let value = value as f32;
        // The word atof starts in: from the first byte that is not white space to the next one
        // that is.
        let start = text
            .iter()
            .position(|&b| !is_c_space(b))
            .unwrap_or(text.len());
        let end = text[start..]
            .iter()
            .position(|&b| is_c_space(b))
            .map_or(text.len(), |n| start + n);
        if used < end && self.garbage.len() < 3 {
            let word = String::from_utf8_lossy(&text[start..end]).into_owned();
            let at = self.place(self.p + start);
            self.garbage.push((word, value, at));
        }
        Ok(value)
    }

    /// `(unsigned)atoi((char*)p)`: `strtol` in base 10, kept in an `int`. AddressSanitizer checks
    /// atoi's reads, up to the byte after the number.
    fn atoi(&self, step: Step) -> Result<u32, Stop> {
        let text = &self.buffer[self.p.min(self.buffer.len())..];
        let mut i = 0;
        while text.get(i).is_some_and(|&b| is_c_space(b)) {
            i += 1;
        }
        let negative = text.get(i) == Some(&b'-');
        if matches!(text.get(i), Some(b'-' | b'+')) {
            i += 1;
        }
        let mut value: i64 = 0;
        let mut saturated = false;
        while let Some(&digit) = text.get(i).filter(|b| b.is_ascii_digit()) {
            let digit = i64::from(digit - b'0');
            match value.checked_mul(10).and_then(|v| v.checked_add(digit)) {
                Some(v) => value = v,
                None => saturated = true,
            }
            i += 1;
        }
        // The byte after the number is read too.
        self.at(self.p + i, step)?;
        let long = match (saturated, negative) {
            (true, false) => i64::MAX,
            (true, true) => i64::MIN,
            (false, false) => value,
            (false, true) => -value,
        };
        Ok(long as i32 as u32)
    }

    /// C++: `BVH::newNode`: up to 24 bytes until the line feed; the terminator goes one byte
    /// before the last byte copied (meant to drop the CR), and `p` skips one more byte.
    fn new_node(&mut self, step: Step) -> Result<usize, Stop> {
        let called_at = self.p;
        let mut name = Vec::new();
        while name.len() < 24 && self.byte(step)? != b'\n' {
            name.push(self.buffer[self.p]);
            self.p += 1;
        }
        let copied = name.len().min(23);
        if copied == 0 && self.unnamed.is_none() {
            // `node->name[i-1] = 0` with i = 0.
            self.unnamed = Some(self.place(called_at));
        }
        name.truncate(copied.saturating_sub(1));
        // printf("%s") stops at the first 0.
        if let Some(zero) = name.iter().position(|&b| b == 0) {
            name.truncate(zero);
        }
        self.p += 1;
        self.nodes.push(Node {
            name,
            offset: [0.0; 3],
            children: Vec::new(),
            flags: 0,
        });
        Ok(self.nodes.len() - 1)
    }

    /// C++: `BVHJoint::addChild`: room for 16 (its assert compares with 24).
    fn add_child(&mut self, parent: usize, child: usize) -> Result<(), Stop> {
        if self.nodes[parent].children.len() == 16 {
            let parent = String::from_utf8_lossy(&self.nodes[parent].name).into_owned();
            return Err(Stop::Crash(Crash::SeventeenthChild { parent }));
        }
        self.nodes[parent].children.push(child);
        Ok(())
    }

    /// C++: `BVH::getFlags`: the letters at `p`, `p + 10` and `p + 20`.
    fn get_flags(&self, step: Step) -> Result<u8, Stop> {
        Ok(get_flags([
            self.at(self.p, step)?,
            self.at(self.p + 10, step)?,
            self.at(self.p + 20, step)?,
        ]))
    }

    /// C++: `BVH::loadFile`, from the header check to the last row. Kept whole past a screen:
    /// it follows the article's `loadFile` line by line, for a student reading the two together.
    fn load_file(&mut self) -> Result<Loaded, Stop> {
        // `new unsigned char[0]` for an empty file: the first byte compared lies past it.
        // Measured: valgrind reports that read, AddressSanitizer does not, and the byte is not
        // `H`, so loadFile returns 0 (and init's print of the null root is what crashes).
        if self.buffer.is_empty() {
            return Err(Stop::Reject(Rejection::Empty));
        }
        for &expected in b"HIERARCHY" {
            if self.byte(Step::Header)? != expected {
                return Err(Stop::Reject(Rejection::NotHierarchy));
            }
            self.p += 1;
        }
        // The root: its name 7 bytes on, its OFFSET in 5-byte steps, its rotation letters at the
        // first `r` less one.
        self.p += 7;
        let root = self.new_node(Step::RootName)?;
        self.father.push(root);
        self.current = root;
        self.scan_to(b'O', Step::RootOffset)?;
        self.p += 7;
        let x = self.atof(Step::RootOffset)?;
        self.p += 5;
        if self.byte(Step::RootOffset)? == b' ' {
            self.p += 1;
        }
        let y = self.atof(Step::RootOffset)?;
        self.p += 5;
        if self.byte(Step::RootOffset)? == b' ' {
            self.p += 1;
        }
        let z = self.atof(Step::RootOffset)?;
        self.p += 5;
        self.nodes[root].offset = [x, y, z];
        self.scan_to(b'r', Step::RootChannels)?;
        self.p -= 1;
        self.nodes[root].flags = self.get_flags(Step::RootChannels)?;
        self.p += 30;
        // The hierarchy, dispatched on each byte until the braces balance.
        let mut counter = 1;
        loop {
            let byte = self.byte(Step::Hierarchy)?;
            match byte {
                0 => {
                    return Err(Stop::Reject(Rejection::Nul {
                        at: self.place(self.p),
                    }));
                }
                b'\r' | b'\n' | b' ' | b'\t' => self.p += 1,
                b'{' => {
                    self.father.push(self.current);
                    self.p += 1;
                    counter += 1;
                }
                b'}' => {
                    // The counter and the stack go together: it never pops an empty stack.
                    self.father.pop();
                    if let Some(&top) = self.father.last() {
                        self.current = top;
                    }
                    self.p += 1;
                    counter -= 1;
                    if counter == 0 {
                        break;
                    }
                }
                b'J' => {
                    self.joint_count += 1;
                    self.p += 6;
                    let node = self.new_node(Step::Hierarchy)?;
                    self.add_child(self.current, node)?;
                    self.current = node;
                }
                b'O' => self.process_offset()?,
                b'C' => {
                    self.p += 11;
                    self.nodes[self.current].flags = self.get_flags(Step::Hierarchy)?;
                    self.p += 30;
                }
                b'E' => {
                    self.p += 4;
                    let node = self.new_node(Step::Hierarchy)?;
                    self.add_child(self.current, node)?;
                    self.current = node;
                }
                _ => {
                    return Err(Stop::Reject(Rejection::FormatError {
                        byte,
                        at: self.place(self.p),
                    }));
                }
            }
        }
        // Frames: and Frame Time:, found by their F.
        self.scan_to(b'F', Step::Frames)?;
        self.p += 8;
        let frames = self.atoi(Step::Frames)?;
        self.scan_to(b'F', Step::FrameTime)?;
        self.p += 12;
        self.atof(Step::FrameTime)?;
        self.past_line_end(Step::FrameTime)?;
        // frameData = new float*[frameCount], then the check of jointCount.
        if u64::from(frames) * 8 > LARGEST_ALLOCATION {
            return Err(Stop::Crash(Crash::Allocation { frames }));
        }
        if self.joint_count == 1 {
            return Err(if frames > 0 {
                Stop::Crash(Crash::UnsetRows { frames })
            } else {
                Stop::Reject(Rejection::OneJoint)
            });
        }
        let width = self.joint_count as usize * 3 + 3;
        // The row loop. Each value moves p on by at least 9 bytes, so a count larger than the
        // buffer holds ends in a read past it long before the loop would.
        let mut rows = Vec::new();
        for frame in 0..frames {
            for _ in 0..width {
                rows.push(self.atof(Step::Rows(frame))?);
                self.p += 8;
                self.past_blank(Step::Rows(frame))?;
            }
            self.p += 2;
        }
        Ok(Loaded {
            frames,
            width,
            rows,
        })
    }

    /// C++: `BVH::processOffset`: `p += 7`, then each number 8 bytes on and past the next blank,
    /// then to the end of the line.
    fn process_offset(&mut self) -> Result<(), Stop> {
        let step = Step::Hierarchy;
        self.p += 7;
        let x = self.atof(step)?;
        self.p += 8;
        self.past_blank(step)?;
        let y = self.atof(step)?;
        self.p += 8;
        self.past_blank(step)?;
        let z = self.atof(step)?;
        self.past_line_end(step)?;
        self.nodes[self.current].offset = [x, y, z];
        Ok(())
    }

    /// The tree from the root, in the order `printRecursive` and `drawRecursive` meet it.
    fn pre_order(&self) -> Vec<ArticleJoint> {
        let mut out = Vec::new();
        let mut stack = vec![(0, 0)];
        while let Some((node, depth)) = stack.pop() {
            let n = &self.nodes[node];
            out.push(ArticleJoint {
                name: String::from_utf8_lossy(&n.name).into_owned(),
                offset: n.offset,
                flags: n.flags,
                depth,
            });
            stack.extend(n.children.iter().rev().map(|&c| (c, depth + 1)));
        }
        out
    }

    /// The nodes in pre-order, as indices.
    fn order(&self) -> Vec<usize> {
        let mut out = Vec::new();
        let mut stack = vec![0];
        while let Some(node) = stack.pop() {
            out.push(node);
            stack.extend(self.nodes[node].children.iter().rev());
        }
        out
    }

    /// C++: `BVH::draw` of any frame (every row has the same width): row 0 of no rows is a
    /// crash, and so is a `pFrame` past the end of the row.
    fn draw(&self, loaded: &Loaded) -> Result<(), Crash> {
        if loaded.frames == 0 {
            return Err(Crash::NoFrames);
        }
        let mut p_frame = 3;
        for node in self.order() {
            let flags = self.nodes[node].flags;
            if axes_turned(flags).is_some() && p_frame + 2 >= loaded.width {
                return Err(Crash::RowTooShort {
                    joint: String::from_utf8_lossy(&self.nodes[node].name).into_owned(),
                    column: p_frame,
                    width: loaded.width,
                });
            }
            if flags != 0 {
                p_frame += 3;
            }
        }
        Ok(())
    }

    /// The first thing the article reads or draws otherwise than the file says, if any: the
    /// file cut short, a joint without a name, then (where bvhview reads the file) the tree,
    /// the frame count and every frame as draw draws it, then words `atof` took for numbers,
    /// and last GL's matrix stack.
    fn misread(
        &self,
        loaded: &Loaded,
        joints: &[ArticleJoint],
        read: u64,
        length: u64,
        written: Option<(&Skeleton, &Motion)>,
        walk: &StackWalk,
    ) -> Option<Misread> {
        if read < length {
            return Some(Misread::Cut { read, length });
        }
        if let Some(at) = self.unnamed {
            return Some(Misread::NoName { at });
        }
        let garbage = (!self.garbage.is_empty()).then(|| Misread::Garbage(self.garbage.clone()));
        let Some((skeleton, motion)) = written else {
            return Some(garbage.unwrap_or(Misread::Refused));
        };
        if let Some(misread) = tree_misread(joints, skeleton) {
            return Some(misread);
        }
        if loaded.frames as usize != motion.frame_count() {
            return Some(Misread::Frames {
                article: loaded.frames,
                file: motion.frame_count(),
            });
        }
        if let Some(misread) = self.drawn_misread(loaded, skeleton, motion) {
            return Some(misread);
        }
        garbage.or_else(|| {
            let name = |node: usize| String::from_utf8_lossy(&self.nodes[node].name).into_owned();
            Some(Misread::MatrixStack {
                overflow: name(walk.overflow?),
                wrong: walk.wrong?.map(name),
                drawn: walk.drawn,
            })
        })
    }

    /// Every frame as draw draws it, against the file's translations and rotations: the first
    /// joint the article translates or turns otherwise.
    fn drawn_misread(
        &self,
        loaded: &Loaded,
        skeleton: &Skeleton,
        motion: &Motion,
    ) -> Option<Misread> {
        let order = self.order();
        for frame in 0..motion.frame_count() {
            let row = &loaded.rows[frame * loaded.width..(frame + 1) * loaded.width];
            let values = motion.frame(frame);
            let mut p_frame = 3;
            for (&node, (index, file)) in order.iter().zip(skeleton.joints.iter().enumerate()) {
                let own = &values[file.first_channel..file.first_channel + file.channels.len()];
                let translation = if index == 0 {
                    [row[0], row[1], row[2]]
                } else {
                    self.nodes[node].offset
                };
                let meant = crate::model::pose::joint_translation(
                    file,
                    own,
                    crate::model::pose::OffsetMode::Replace,
                )
                .to_array();
                if translation != meant {
                    return Some(Misread::Translation {
                        joint: file.name.clone(),
                        frame,
                        article: translation,
                        file: meant,
                    });
                }
                let flags = self.nodes[node].flags;
                let turned: Vec<(usize, f32)> = axes_turned(flags)
                    .map(|axes| (0..3).map(|i| (axes[i], row[p_frame + i])).collect())
                    .unwrap_or_default();
                let said: Vec<(usize, f32)> = file
                    .channels
                    .iter()
                    .zip(own)
                    .filter(|(channel, _)| channel.is_rotation())
                    .map(|(channel, &value)| (channel.axis(), value))
                    .collect();
                if turned != said {
                    return Some(Misread::Rotations {
                        joint: file.name.clone(),
                        frame,
                        article: turned,
                        file: said,
                    });
                }
                if flags != 0 {
                    p_frame += 3;
                }
            }
        }
        None
    }

    /// C++: `drawRecursive`'s `glPushMatrix` / `glPopMatrix` against GL's stack of
    /// [`GL_STACK_DEPTH`] matrices, then `display`'s floor: which matrix each draw uses, and what
    /// `glGetError` says. A stack entry is the matrix of a joint (as `Some(node)`: what its
    /// translate and rotate make of its parent's), the view (`View`), or one that is no joint's
    /// (`Wrong`). Beside it runs the same stack of numbers for frame 0 (the view taken as the
    /// identity, so that a sphere's place is in the world), and each joint's own matrix.
    fn stack_walk(&self, loaded: &Loaded) -> StackWalk {
        use glam::{Mat4, Vec3};
        #[derive(Clone, Copy, PartialEq)]
        enum Matrix {
            View,
            Joint(usize),
            Wrong,
        }
        let row = &loaded.rows[..loaded.width.min(loaded.rows.len())];
        let value = |column: usize| row.get(column).copied().unwrap_or(0.0);
        let mut stack = vec![(Matrix::View, Mat4::IDENTITY)];
        // Each joint's own matrix: its parent's, translated and turned.
        let mut own = vec![Mat4::IDENTITY; self.nodes.len()];
        let (mut overflow, mut wrong, mut drawn) = (None, None, None);
        let (mut overflows, mut underflows, mut deepest) = (0, 0, 1);
        let mut p_frame = 3;
        // (node, its parent's matrix, entering, how many matrices the draw holds there) in draw
        // order, without recursion: a tree as deep as the file allows.
        let mut events = vec![(0, Matrix::View, true, 1)];
        while let Some((node, parent, entering, held)) = events.pop() {
            if !entering {
                // glPopMatrix: GL ignores a pop of the last entry (a stack underflow).
                if stack.len() > 1 {
                    stack.pop();
                } else {
                    underflows += 1;
                }
                continue;
            }
            let held = held + 1;
            deepest = deepest.max(held);
            let top = *stack.last().expect("the stack keeps its bottom entry");
            if stack.len() < GL_STACK_DEPTH {
                stack.push(top);
            } else {
                overflows += 1;
                overflow.get_or_insert(node);
            }
            // glTranslatef (the root by columns 0 to 2, as draw copies them), then roateSpace.
            let n = &self.nodes[node];
            let mut local = if node == 0 {
                Mat4::from_translation(Vec3::new(value(0), value(1), value(2)))
            } else {
                Mat4::from_translation(Vec3::from(n.offset))
            };
            if let Some(axes) = axes_turned(n.flags) {
                for (i, axis) in axes.into_iter().enumerate() {
                    let about = [Vec3::X, Vec3::Y, Vec3::Z][axis];
                    local *= Mat4::from_axis_angle(about, value(p_frame + i).to_radians());
                }
            }
            if n.flags != 0 {
                p_frame += 3;
            }
            let parents = match parent {
                Matrix::Joint(p) => own[p],
                _ => Mat4::IDENTITY,
            };
            own[node] = parents * local;
            let entry = stack.last_mut().expect("the stack keeps its bottom entry");
            let matrix = if entry.0 == parent {
                Matrix::Joint(node)
            } else {
                Matrix::Wrong
            };
            *entry = (matrix, entry.1 * local);
            if matrix == Matrix::Wrong && wrong.is_none() {
                wrong = Some(Some(node));
                let place = |m: Mat4| m.w_axis.truncate().to_array();
                drawn = Some((place(entry.1), place(own[node])));
            }
            events.push((node, parent, false, held));
            for &child in n.children.iter().rev() {
                events.push((child, Matrix::Joint(node), true, held));
            }
        }
        if wrong.is_none() && stack.last().map(|entry| entry.0) != Some(Matrix::View) {
            wrong = Some(None);
        }
        let name = |node: usize| String::from_utf8_lossy(&self.nodes[node].name).into_owned();
        StackWalk {
            overflow,
            wrong,
            drawn,
            errors: overflow.map(|first| GlStack {
                deepest,
                overflows,
                first: name(first),
                underflows,
            }),
        }
    }
}

/// The tree the article loaded against the file's: the same joints and End Sites, at the same
/// depths, in the same order, then the same names, then the same OFFSETs. The first that
/// differs, if any.
fn tree_misread(joints: &[ArticleJoint], skeleton: &Skeleton) -> Option<Misread> {
    // A parent comes before its children in the file, so each depth is its parent's plus one.
    let mut depths: Vec<usize> = Vec::with_capacity(skeleton.joints.len());
    for joint in &skeleton.joints {
        let depth = joint
            .parent
            .and_then(|parent| depths.get(parent))
            .map_or(0, |depth| depth + 1);
        depths.push(depth);
    }
    let same_shape = joints.len() == skeleton.joints.len()
        && joints
            .iter()
            .zip(&depths)
            .all(|(j, &depth)| j.depth == depth);
    if !same_shape {
        return Some(Misread::Joints {
            article: joints.len(),
            file: skeleton.joints.len(),
        });
    }
    for (article, file) in joints.iter().zip(&skeleton.joints) {
        if article.name != file.name {
            return Some(Misread::Name {
                file: file.name.clone(),
                article: article.name.clone(),
            });
        }
    }
    for (article, file) in joints.iter().zip(&skeleton.joints) {
        if article.offset != file.offset.to_array() {
            return Some(Misread::Offset {
                joint: file.name.clone(),
                article: article.offset,
                file: file.offset.to_array(),
            });
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strtod_reads_the_longest_number_and_stops() {
        assert_eq!(c_strtod(b"  -1.#IND00 "), (-1.0, 5));
        assert_eq!(c_strtod(b"nonsense!"), (0.0, 0));
        assert_eq!(c_strtod(b"0.00 0.00"), (0.0, 4));
        assert_eq!(c_strtod(b".5e3x"), (500.0, 4));
        assert_eq!(c_strtod(b"1e"), (1.0, 1));
        assert_eq!(c_strtod(b"-.25"), (-0.25, 4));
        assert_eq!(c_strtod(b"0x1p4"), (16.0, 5));
        assert_eq!(c_strtod(b"INF"), (f64::INFINITY, 3));
        assert!(c_strtod(b"nan(1)").0.is_nan());
        assert_eq!(c_strtod(b"nan(1)").1, 6);
    }

    #[test]
    fn get_flags_gives_the_articles_numbers() {
        assert_eq!(get_flags(*b"ZXY"), 3);
        assert_eq!(get_flags(*b"YYX"), 0);
        assert_eq!(get_flags(*b"YYY"), 4);
        assert_eq!(get_flags(*b"XXX"), 253);
        assert_eq!(get_flags(*b"\n\tl"), 97);
        assert_eq!(axes_turned(get_flags(*b"XXY")), Some([2, 1, 0]));
    }

    /// The file's length as `int`: negative from 2 GiB on, and modulo 4 GiB.
    #[test]
    fn the_length_is_kept_in_an_int() {
        assert_eq!(i_file_size(507), 507);
        assert_eq!(i_file_size(2_500_000_000), -1_794_967_296);
        assert_eq!(i_file_size((4 << 30) + 507), 507);
        let control = b"HIERARCHY\r\nROOT Hips\r\n{";
        let outcome = run(control, 2_500_000_000, None);
        assert_eq!(
            outcome.verdict,
            Verdict::Crashes(Crash::FileLength {
                length: 2_500_000_000
            })
        );
    }
}
