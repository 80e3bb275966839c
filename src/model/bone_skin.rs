//! A skin for any skeleton (the closing proposal of the paper on point and stick-figure models): an
//! open cylinder around each bone, made in the rest pose. Along the first quarter of a bone its
//! vertices are shared with the parent bone, along the last quarter with the child, half and half
//! where they meet, so elbows bend smoothly. Every frame, `skin.rs` moves it with the bones' world
//! matrices from `pose`.

use crate::model::pose::{OffsetMode, world_matrices};
use crate::model::skeleton::Skeleton;
use crate::model::skin::{Skin, SkinVertex};
use glam::{Mat4, Vec3};

const SIDES: usize = 10;
const RINGS: usize = 6;

/// The skin of one skeleton, bound to its rest pose (joints are the bones).
#[derive(Clone, Debug)]
pub struct Body {
    pub skin: Skin,
    pub indices: Vec<u32>,
    mode: OffsetMode,
}

/// The skin posed for one frame.
#[derive(Clone, Debug, Default)]
pub struct PosedBody {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub indices: Vec<u32>,
    /// Its back faces are hidden (a character whose file says so); a generated skin shows both.
    pub single_sided: bool,
}

impl Body {
    pub fn new(skeleton: &Skeleton, mode: OffsetMode) -> Body {
        let mut bind = Vec::new();
        world_matrices(skeleton, &[], mode, &mut bind);
        let rest: Vec<Vec3> = bind.iter().map(|m| m.w_axis.truncate()).collect();
        let (lo, hi) = rest.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(l, h), p| (l.min(*p), h.max(*p)),
        );
        let size = (hi - lo).max_element().max(1e-3);
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for (j, joint) in skeleton.joints.iter().enumerate() {
            for &c in &joint.children {
                let (a, b) = (rest[j], rest[c]);
                let length = a.distance(b);
                if length < size * 1e-4 {
                    continue;
                }
                let direction = (b - a) / length;
                let radius = (size * 0.022).min(length * 0.45);
                let (u, v) = direction.any_orthonormal_pair();
                let first = vertices.len() as u32;
                for ring in 0..=RINGS {
                    let t = ring as f32 / RINGS as f32;
                    let centre = a + direction * (length * t);
                    // Share the ends with the neighbouring bones' frames.
                    let with_parent = match joint.parent {
                        Some(_) if t < 0.25 => 0.5 * (1.0 - t / 0.25),
                        _ => 0.0,
                    };
                    let child_moves = !skeleton.joints[c].channels.is_empty();
                    let with_child = if child_moves && t > 0.75 {
                        0.5 * (t - 0.75) / 0.25
                    } else {
                        0.0
                    };
                    let mut influences = vec![(j, 1.0 - with_parent - with_child)];
                    if let Some(parent) = joint.parent {
                        influences.push((parent, with_parent));
                    }
                    influences.push((c, with_child));
                    for side in 0..SIDES {
                        let angle = std::f32::consts::TAU * side as f32 / SIDES as f32;
                        let normal = u * angle.cos() + v * angle.sin();
                        vertices.push(SkinVertex::new(
                            centre + normal * radius,
                            normal,
                            &influences,
                        ));
                    }
                }
                for ring in 0..RINGS {
                    for side in 0..SIDES {
                        let next = (side + 1) % SIDES;
                        let at = |r: usize, s: usize| first + (r * SIDES + s) as u32;
                        indices.extend([at(ring, side), at(ring, next), at(ring + 1, next)]);
                        indices.extend([at(ring, side), at(ring + 1, next), at(ring + 1, side)]);
                    }
                }
            }
        }
        Body {
            skin: Skin::new(vertices, &bind),
            indices,
            mode,
        }
    }

    /// The skin for one MOTION row (`None`: the rest pose), into `posed`.
    pub fn pose(
        &self,
        skeleton: &Skeleton,
        frame: Option<&[f32]>,
        posed: &mut PosedBody,
        scratch: &mut (Vec<Mat4>, Vec<Mat4>),
    ) {
        world_matrices(skeleton, frame.unwrap_or(&[]), self.mode, &mut scratch.0);
        self.skin.bone_matrices(&scratch.0, &mut scratch.1);
        self.skin
            .deform(&scratch.1, &mut posed.positions, &mut posed.normals);
        if posed.indices.len() != self.indices.len() {
            posed.indices.clone_from(&self.indices);
        }
    }
}
