//! Joint positions over frames, what a solve reads, and SMPL's 22 joints: the order an unnamed
//! array of 22 points is read in.

use crate::io::error::{Error, quoted};
use glam::DVec3;

/// SMPL's 22 body joints in SMPL's order (HumanML3D's `new_joints/*.npy`, AMASS, most
/// text-to-motion models), by the names of the built-in `smpl22` skeleton: the layout an
/// unnamed array of 22 joints is read in.
pub const SMPL22_ORDER: [&str; 22] = [
    "pelvis",
    "left_hip",
    "right_hip",
    "spine1",
    "left_knee",
    "right_knee",
    "spine2",
    "left_ankle",
    "right_ankle",
    "spine3",
    "left_foot",
    "right_foot",
    "neck",
    "left_collar",
    "right_collar",
    "head",
    "left_shoulder",
    "right_shoulder",
    "left_elbow",
    "right_elbow",
    "left_wrist",
    "right_wrist",
];

/// Joint positions over frames: what [`solve`](super::solve()) reads.
///
/// ```
/// use bvhview::solve::{Positions, SMPL22_ORDER};
/// use glam::DVec3;
///
/// let positions = Positions::new(
///     SMPL22_ORDER.iter().map(|n| n.to_string()).collect(),
///     vec![DVec3::ZERO; 22 * 3],
///     1.0 / 20.0,
/// ).unwrap();
/// assert_eq!(positions.frames(), 3);
/// assert_eq!(positions.at(2, 21), DVec3::ZERO);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Positions {
    /// Each point's name (a joint of the skeleton solved onto, or of a layout).
    pub names: Vec<String>,
    /// Frame after frame, each point's position.
    pub points: Vec<DVec3>,
    /// Seconds between frames.
    pub frame_time: f64,
}

impl Positions {
    /// Positions of `names.len()` points a frame; refused when `points` is not a whole number
    /// of frames, a name repeats, a value is not finite or the frame time is not positive.
    pub fn new(
        names: Vec<String>,
        points: Vec<DVec3>,
        frame_time: f64,
    ) -> Result<Positions, Error> {
        let refuse = |why: String| Err(Error::usage(format!("positions: {why}")));
        if names.is_empty() || !points.len().is_multiple_of(names.len()) {
            return refuse(format!(
                "{} points are not whole frames of {} joints",
                points.len(),
                names.len()
            ));
        }
        let mut seen = std::collections::HashSet::new();
        if let Some(name) = names.iter().find(|n| !seen.insert(n.as_str())) {
            return refuse(format!("the joint {} is named twice", quoted(name)));
        }
        if let Some(at) = points.iter().position(|p| !p.is_finite()) {
            return refuse(format!(
                "frame {}, joint {}: not a finite position",
                at / names.len(),
                quoted(&names[at % names.len()])
            ));
        }
        // A take holds 32-bit floats: a position past their range (a float64 of 1e300) would
        // solve to infinite offsets and distances, not to a take.
        if let Some(at) = points.iter().position(|p| !p.as_vec3().is_finite()) {
            return refuse(format!(
                "frame {}, joint {}: position ({}, {}, {}) is beyond a 32-bit float's range \
                 (±3.4e38), which bvhview's takes hold",
                at / names.len(),
                quoted(&names[at % names.len()]),
                crate::io::limits::show(points[at].x),
                crate::io::limits::show(points[at].y),
                crate::io::limits::show(points[at].z)
            ));
        }
        if !(frame_time > 0.0 && frame_time.is_finite()) {
            return refuse(format!("frame time {frame_time}: not a positive number"));
        }
        Ok(Positions {
            names,
            points,
            frame_time,
        })
    }

    /// How many frames.
    pub fn frames(&self) -> usize {
        self.points.len() / self.names.len().max(1)
    }

    /// Point `point`'s position in frame `frame`.
    pub fn at(&self, frame: usize, point: usize) -> DVec3 {
        self.points[frame * self.names.len() + point]
    }
}
