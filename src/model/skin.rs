//! Linear blend skinning, as the skinning tutorial has it: each vertex of a skin moves with the
//! bones that influence it, `v' = Σ wᵢ · (Bᵢ · Aᵢ⁻¹) · v`, where `Aᵢ` is bone i's world matrix in
//! the pose the skin was made in (the bind pose) and `Bᵢ` its world matrix now. Nothing here knows
//! about GL.

use glam::{Mat4, Vec3};

/// Most influences a vertex keeps (the strongest, if more are given).
pub const MAX_INFLUENCES: usize = 4;

/// A vertex in the bind pose and the bones that move it.
///
/// ```
/// use bvhview::model::skin::SkinVertex;
/// use glam::Vec3;
///
/// // Weights are scaled to sum to 1, strongest first; a weight of 0 is dropped.
/// let vertex = SkinVertex::new(Vec3::X, Vec3::Y, &[(0, 1.0), (3, 3.0), (5, 0.0)]);
/// assert_eq!(vertex.influences, [(3, 0.75), (0, 0.25), (0, 0.0), (0, 0.0)]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SkinVertex {
    /// Where the vertex is in the bind pose.
    pub position: Vec3,
    /// Its unit normal in the bind pose.
    pub normal: Vec3,
    /// (bone, weight), weights summing to 1; unused slots have weight 0.
    pub influences: [(u32, f32); MAX_INFLUENCES],
}

impl SkinVertex {
    /// Keeps the `MAX_INFLUENCES` strongest influences and scales their weights to sum to 1.
    /// Influences with no weight at all fall back to the first bone given (or bone 0).
    pub fn new(position: Vec3, normal: Vec3, influences: &[(usize, f32)]) -> SkinVertex {
        let mut sorted: Vec<(usize, f32)> = influences
            .iter()
            .copied()
            .filter(|(_, w)| w.is_finite() && *w > 0.0)
            .collect();
        sorted.sort_by(|a, b| b.1.total_cmp(&a.1));
        sorted.truncate(MAX_INFLUENCES);
        let total: f32 = sorted.iter().map(|(_, w)| w).sum();
        let mut slots = [(0u32, 0.0f32); MAX_INFLUENCES];
        if total > 0.0 {
            for (slot, (bone, weight)) in slots.iter_mut().zip(&sorted) {
                *slot = (*bone as u32, weight / total);
            }
        } else {
            slots[0] = (influences.first().map_or(0, |i| i.0) as u32, 1.0);
        }
        SkinVertex {
            position,
            normal,
            influences: slots,
        }
    }
}

/// A skin bound to a set of bones.
///
/// ```
/// use bvhview::model::skin::{Skin, SkinVertex};
/// use glam::{Mat4, Vec3};
///
/// // One vertex on bone 0, bound where the bone stands at x = 1.
/// let vertex = SkinVertex::new(Vec3::new(1.0, 1.0, 0.0), Vec3::Y, &[(0, 1.0)]);
/// let skin = Skin::new(vec![vertex], &[Mat4::from_translation(Vec3::X)]);
/// // The bone moves up by 2: the vertex follows.
/// let (mut bones, mut positions, mut normals) = (Vec::new(), Vec::new(), Vec::new());
/// skin.bone_matrices(&[Mat4::from_translation(Vec3::new(1.0, 2.0, 0.0))], &mut bones);
/// skin.deform(&bones, &mut positions, &mut normals);
/// assert_eq!((positions[0], normals[0]), (Vec3::new(1.0, 3.0, 0.0), Vec3::Y));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Skin {
    /// The skin's vertices in the bind pose.
    pub vertices: Vec<SkinVertex>,
    /// Aᵢ⁻¹ for every bone.
    pub inverse_bind: Vec<Mat4>,
}

impl Skin {
    /// Binds `vertices` to bones whose world matrices in the bind pose are `bind`.
    pub fn new(vertices: Vec<SkinVertex>, bind: &[Mat4]) -> Skin {
        Skin {
            vertices,
            inverse_bind: bind.iter().map(Mat4::inverse).collect(),
        }
    }

    /// Bᵢ · Aᵢ⁻¹ for every bone, from the bones' world matrices now.
    pub fn bone_matrices(&self, current: &[Mat4], out: &mut Vec<Mat4>) {
        out.clear();
        out.extend(current.iter().zip(&self.inverse_bind).map(|(b, a)| *b * *a));
    }

    /// The skinned positions and normals (normals unit length), into `positions` and `normals`.
    /// Bones are rigid, so a normal turns with the blended matrix's rotation part.
    pub fn deform(
        &self,
        bone_matrices: &[Mat4],
        positions: &mut Vec<Vec3>,
        normals: &mut Vec<Vec3>,
    ) {
        positions.clear();
        normals.clear();
        for vertex in &self.vertices {
            let mut position = Vec3::ZERO;
            let mut normal = Vec3::ZERO;
            for &(bone, weight) in &vertex.influences {
                if weight == 0.0 {
                    continue;
                }
                let m = &bone_matrices[bone as usize];
                position += m.transform_point3(vertex.position) * weight;
                normal += m.transform_vector3(vertex.normal) * weight;
            }
            positions.push(position);
            normals.push(normal.normalize_or_zero());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bone 0 stays put; bone 1 turns 90° about Z around the joint at (0, 3, 0), as in the demo.
    fn bones() -> (Vec<Mat4>, Vec<Mat4>) {
        let bind = vec![
            Mat4::IDENTITY,
            Mat4::from_translation(Vec3::new(0.0, 3.0, 0.0)),
        ];
        let now = vec![
            Mat4::IDENTITY,
            Mat4::from_translation(Vec3::new(0.0, 3.0, 0.0))
                * Mat4::from_rotation_z(90f32.to_radians()),
        ];
        (bind, now)
    }

    fn skin_one(position: Vec3, influences: &[(usize, f32)]) -> (Vec3, Vec3) {
        let (bind, now) = bones();
        let skin = Skin::new(vec![SkinVertex::new(position, Vec3::X, influences)], &bind);
        let mut matrices = Vec::new();
        skin.bone_matrices(&now, &mut matrices);
        let (mut p, mut n) = (Vec::new(), Vec::new());
        skin.deform(&matrices, &mut p, &mut n);
        (p[0], n[0])
    }

    /// (1, 3, 0): bone 0 leaves it there; bone 1 takes its offset (1, 0, 0) from the joint to
    /// (0, 1, 0), so (0, 4, 0). Half and half: (0.5, 3.5, 0). The normal X becomes (X + Y)/√2.
    #[test]
    fn half_and_half_lands_between_the_bones() {
        let (p, n) = skin_one(Vec3::new(1.0, 3.0, 0.0), &[(0, 0.5), (1, 0.5)]);
        assert!(p.abs_diff_eq(Vec3::new(0.5, 3.5, 0.0), 1e-6), "{p}");
        let d = std::f32::consts::FRAC_1_SQRT_2;
        assert!(n.abs_diff_eq(Vec3::new(d, d, 0.0), 1e-6), "{n}");
    }

    /// One influence moves the vertex rigidly: (2, 3, 0) on bone 1 goes to (0, 5, 0).
    #[test]
    fn one_influence_moves_rigidly() {
        let (p, n) = skin_one(Vec3::new(2.0, 3.0, 0.0), &[(1, 1.0)]);
        assert!(p.abs_diff_eq(Vec3::new(0.0, 5.0, 0.0), 1e-6), "{p}");
        assert!(n.abs_diff_eq(Vec3::Y, 1e-6), "{n}");
    }

    /// Weights are scaled to sum to 1 and only the four strongest are kept.
    #[test]
    fn weights_are_normalised_and_limited_to_four() {
        let v = SkinVertex::new(
            Vec3::ZERO,
            Vec3::Y,
            &[
                (0, 2.0),
                (1, 1.0),
                (2, 0.5),
                (3, 0.25),
                (4, 0.25),
                (5, f32::NAN),
            ],
        );
        let total: f32 = v.influences.iter().map(|i| i.1).sum();
        assert!((total - 1.0).abs() < 1e-6);
        assert_eq!(v.influences.map(|i| i.0), [0, 1, 2, 3]);
        assert!((v.influences[0].1 - 2.0 / 3.75).abs() < 1e-6);
        let none = SkinVertex::new(Vec3::ZERO, Vec3::Y, &[(7, 0.0)]);
        assert_eq!(none.influences[0], (7, 1.0));
    }
}
