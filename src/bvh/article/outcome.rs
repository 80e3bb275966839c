//! What the article's loader does with a file, as `trace --explain` reports it: the verdict,
//! each step, and the joints it keeps.

/// What the article's program does with a file, as a whole.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// `loadFile` returns 1, and the tree `print` writes and every frame `draw` draws are what
    /// the file says: the same joints, names, offsets, translations and rotations.
    ReadsAsWritten,
    /// `loadFile` returns 1 and nothing crashes, but something differs from what the file says:
    /// a number, a name, a joint, a rotation, without a word.
    Misreads(Misread),
    /// `loadFile` returns 0 (and `init` then prints the null root anyway, which crashes: that is
    /// the one defect every rejected file shares).
    Rejects(Rejection),
    /// It reads or writes memory it does not own, or aborts, in `loadFile`, `print` or `draw`.
    Crashes(Crash),
}

impl Verdict {
    /// The verdict in four words a test can pin: `reads it as written`, `misreads it`,
    /// `rejects it`, `crashes on it`.
    pub fn word(&self) -> &'static str {
        match self {
            Verdict::ReadsAsWritten => "reads it as written",
            Verdict::Misreads(_) => "misreads it",
            Verdict::Rejects(_) => "rejects it",
            Verdict::Crashes(_) => "crashes on it",
        }
    }
}

/// A place in the file, 1-based, as bvhview's errors give it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Place {
    pub line: usize,
    pub column: usize,
}

/// Where in `loadFile` a read runs past the end of the buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// The nine bytes compared with `HIERARCHY`.
    Header,
    /// `newNode` for the root, after `p += 7`.
    RootName,
    /// The scan for the root's `O` and its OFFSET in 5-byte steps.
    RootOffset,
    /// The scan for the first `r` and `getFlags`.
    RootChannels,
    /// The `for (running)` loop over the hierarchy.
    Hierarchy,
    /// The scan for the `F` of `Frames` and its `atoi`.
    Frames,
    /// The scan for the `F` of `Frame Time`, and to the end of its line.
    FrameTime,
    /// The row loop, in this frame (from 0).
    Rows(u32),
}

/// Why `loadFile` returns 0.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Rejection {
    /// The first nine bytes are not `HIERARCHY`.
    NotHierarchy,
    /// The file is empty: `new unsigned char[0]`, and the check of the header reads the byte
    /// after that empty buffer (valgrind reports it; AddressSanitizer does not), which is not
    /// the `H` of `HIERARCHY`.
    Empty,
    /// The dispatcher met a byte it has no case for and printed `_%c_ _%d_ file format error!!`.
    FormatError { byte: u8, at: Place },
    /// The dispatcher met a 0 byte (`if(*p == 0)`, meant for the end of the buffer).
    Nul { at: Place },
    /// `jointCount == 1`: a skeleton of the root alone, with no frames.
    OneJoint,
}

/// How the article's program crashes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Crash {
    /// `int iFileSize` holds the file's length modulo 4 GiB, and it is negative here:
    /// `new unsigned char[iFileSize]` throws `std::bad_alloc`, and the program aborts.
    FileLength { length: u64 },
    /// A read past the end of its buffer.
    ReadPast { step: Step, at: Place },
    /// A 17th child: `child[16]` lands on `childNum` (the assert compares with 24, not 16).
    SeventeenthChild { parent: String },
    /// `jointCount == 1`: `loadFile` calls `clear()`, which deletes `frames` row pointers that
    /// were allocated and never set.
    UnsetRows { frames: u32 },
    /// `new float*[frameCount]` asks for more than any machine the program was measured on has,
    /// before a row is read: `std::bad_alloc`, abort.
    Allocation { frames: u32 },
    /// `Frames: 0` (or no number where it looks): `draw` reads row 0 of an empty array.
    NoFrames,
    /// `draw`'s `pFrame` reads past the end of a row (`width` values) at this joint.
    RowTooShort {
        joint: String,
        column: usize,
        width: usize,
    },
}

/// What the article's program reads differently from what the file says (the first difference,
/// in the order `loadFile`, `print` and `draw` meet them).
#[derive(Clone, Debug, PartialEq)]
pub enum Misread {
    /// It reads only the first `read` bytes of a file of `length` (`int iFileSize` keeps the
    /// length modulo 4 GiB).
    Cut { read: u64, length: u64 },
    /// `atof` reads these words, which are not numbers, as these values (up to three).
    Garbage(Vec<(String, f32, Place)>),
    /// Its tree holds `article` joints and End Sites where the file has `file`.
    Joints { article: usize, file: usize },
    /// It keeps this name as that.
    Name { file: String, article: String },
    /// It reads this joint's OFFSET as that.
    Offset {
        joint: String,
        article: [f32; 3],
        file: [f32; 3],
    },
    /// Its `frameCount` against the rows the file has.
    Frames { article: u32, file: usize },
    /// In this frame it translates the joint by `article` where the file means `file`.
    Translation {
        joint: String,
        frame: usize,
        article: [f32; 3],
        file: [f32; 3],
    },
    /// In this frame it turns the joint by these (axis, degrees), where the file says those
    /// (axes 0, 1, 2 are X, Y, Z).
    Rotations {
        joint: String,
        frame: usize,
        article: Vec<(usize, f32)>,
        file: Vec<(usize, f32)>,
    },
    /// A `JOINT` (or `End`) with no name before its line end: `newNode` copies no byte and
    /// writes its terminator at `name[-1]` (UndefinedBehaviorSanitizer: index -1 out of bounds),
    /// and the joint's name is empty.
    NoName { at: Place },
    /// It loads a file that bvhview refuses, and no more is known.
    Refused,
    /// Its draw pushes one matrix per joint, and GL's modelview stack holds [`GL_STACK_DEPTH`]:
    /// at `overflow` (the first joint that deep) `glPushMatrix` overflows and is ignored, the
    /// pops that follow take matrices of joints above, and `wrong` (a joint, or the floor when
    /// `None`) is drawn from a matrix that is not its own.
    MatrixStack {
        overflow: String,
        wrong: Option<String>,
        /// Where the sphere of `wrong` lands in frame 0 (world coordinates), and where the file
        /// puts it.
        drawn: Option<([f32; 3], [f32; 3])>,
    },
}

/// What GL's modelview stack says of the article's draw when the tree is deeper than it holds:
/// `glGetError` after each push and pop (measured with `bench/glut/run.sh`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GlStack {
    /// The most matrices the draw would hold at once: the view, and one per joint and End Site
    /// on the deepest path.
    pub deepest: usize,
    /// Pushes GL ignores (`GL_STACK_OVERFLOW`), the first of them at `first`.
    pub overflows: usize,
    pub first: String,
    /// Pops GL ignores (`GL_STACK_UNDERFLOW`): the stack is down to its last entry.
    pub underflows: usize,
}

/// The modelview stack depth the article's draw has: GL's minimum, and Mesa's (which drew the
/// reference pictures) exactly; the identity at the bottom is one of them.
pub const GL_STACK_DEPTH: usize = 32;

/// How deep a file `trace --explain` reads again when bvhview refuses it for its depth alone
/// ([`crate::limits::MAX_DEPTH`]), to say what the article's program does with it. Measured: the
/// article's program, plain and with AddressSanitizer, reads a chain this deep as written.
pub const EXPLAIN_MAX_DEPTH: usize = 10_000;

/// A joint of the article's tree, as `print` shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct ArticleJoint {
    /// The bytes of `name` up to its terminator.
    pub name: String,
    pub offset: [f32; 3],
    pub flags: u8,
    /// How deep in the tree (the root is 0).
    pub depth: usize,
}

/// What the run found: the verdict, and the article's tree in pre-order when `loadFile`
/// returned 1.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    pub verdict: Verdict,
    pub joints: Option<Vec<ArticleJoint>>,
    /// Where its draw runs past GL's matrix stack, if it draws and does.
    pub gl_stack: Option<GlStack>,
}
