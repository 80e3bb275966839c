//! How position channels meet a joint's OFFSET: the one choice every pose is computed with.

/// How a joint's position channels combine with its OFFSET.
///
/// ```
/// use bvhview::{bvh::load_bytes, model::pose::{OffsetMode, world_positions}};
/// use glam::Vec3;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let text = b"HIERARCHY\nROOT Hips\n{\n OFFSET 0 10 0\n CHANNELS 3 Xposition Yposition Zposition\n \
///     End Site\n {\n  OFFSET 0 5 0\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n1 2 3\n";
/// let bvh = load_bytes(text, "inline")?;
/// let frame = bvh.motion.frame(0);
/// let replaced = world_positions(&bvh.skeleton, frame, OffsetMode::Replace);
/// assert_eq!(replaced[0], Vec3::new(1.0, 2.0, 3.0)); // the OFFSET's 10 is replaced
/// let added = world_positions(&bvh.skeleton, frame, OffsetMode::Add);
/// assert_eq!(added[0], Vec3::new(1.0, 12.0, 3.0));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OffsetMode {
    /// Position channels replace the matching OFFSET components (the article's
    /// `root->x = pFrame[0]`; Blender, bvhio).
    #[default]
    Replace,
    /// Position channels are added to the OFFSET (three.js; the paper's "OFFSET + translation").
    Add,
}

impl OffsetMode {
    /// The mode a take's bones are read in: `self`, asked for the files; but a take put on a
    /// character (`on_character`) is the character's skeleton, which the retarget wrote for
    /// the replace mode its mesh is bound in (it reads the source in whichever mode the source
    /// was written for).
    ///
    /// ```
    /// use bvhview::model::pose::OffsetMode;
    /// assert_eq!(OffsetMode::Add.for_take(false), OffsetMode::Add);
    /// assert_eq!(OffsetMode::Add.for_take(true), OffsetMode::Replace);
    /// ```
    pub fn for_take(self, on_character: bool) -> OffsetMode {
        if on_character {
            OffsetMode::Replace
        } else {
            self
        }
    }
}
