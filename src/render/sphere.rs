//! C++: `glutSolidSphere(radius, slices, stacks)` as freeglut 3.4 builds it: one vertex at each
//! pole, `stacks - 1` rings of `slices` vertices, drawn as `stacks` triangle strips of
//! `(slices + 1) * 2` indices with `glDrawElements`. The same numbers, in the same order, so the
//! rasteriser sees the same triangles and the pictures match pixel for pixel.
//!
//! What changed: freeglut recomputes the tables and indices on every call; here a [`Sphere`] is
//! built once and drawn as often as needed.

/// Vertex positions, normals and strip indices of one sphere.
///
/// ```
/// use bvhview::render::sphere::Sphere;
///
/// let sphere = Sphere::new(1.0, 20, 16); // the article's glutSolidSphere(1, 20, 16)
/// assert_eq!(sphere.positions.len(), (20 * 15 + 2) * 3); // two poles and 15 rings of 20
/// assert_eq!(sphere.indices.len(), 16 * sphere.strip_len());
/// assert_eq!(&sphere.positions[..3], &[0.0, 0.0, 1.0]); // the north pole first
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    /// The radius.
    pub radius: f32,
    /// Divisions around the Z axis (like lines of longitude).
    pub slices: usize,
    /// Divisions along the Z axis (like lines of latitude).
    pub stacks: usize,
    /// `x, y, z` per vertex.
    pub positions: Vec<f32>,
    /// Unit normals, `x, y, z` per vertex.
    pub normals: Vec<f32>,
    /// `stacks` strips of `strip_len()` indices each.
    pub indices: Vec<u16>,
}

/// C++: freeglut's `fghCircleTable`: sines and cosines of `size + 1` angles around a full circle
/// (or a half circle), in single precision, the last entry closing the circle exactly. A negative
/// `n` walks the circle the other way, as freeglut does for the sphere's slices.
fn circle_table(n: i32, half_circle: bool) -> (Vec<f32>, Vec<f32>) {
    let size = n.unsigned_abs() as usize;
    let turn = if half_circle { 1.0f32 } else { 2.0 };
    let angle = turn * std::f32::consts::PI / (if n == 0 { 1 } else { n }) as f32;
    let mut sin = vec![0.0f32; size + 1];
    let mut cos = vec![0.0f32; size + 1];
    cos[0] = 1.0;
    for i in 1..size {
        // C computes sin((double)(angle * i)) and stores it as a float.
        let a = (angle * i as f32) as f64;
        sin[i] = a.sin() as f32;
        cos[i] = a.cos() as f32;
    }
    if half_circle {
        sin[size] = 0.0;
        cos[size] = -1.0;
    } else {
        sin[size] = sin[0];
        cos[size] = cos[0];
    }
    (sin, cos)
}

impl Sphere {
    /// C++: freeglut's `fghGenerateSphere` and the index loop of `fghSphere`.
    pub fn new(radius: f32, slices: usize, stacks: usize) -> Sphere {
        assert!(
            slices >= 1 && stacks >= 2,
            "a sphere needs a slice and two stacks"
        );
        let (sin1, cos1) = circle_table(-(slices as i32), false);
        let (sin2, cos2) = circle_table(stacks as i32, true);
        let vertex_count = slices * (stacks - 1) + 2;
        let mut positions = Vec::with_capacity(vertex_count * 3);
        let mut normals = Vec::with_capacity(vertex_count * 3);
        positions.extend([0.0, 0.0, radius]);
        normals.extend([0.0, 0.0, 1.0]);
        for i in 1..stacks {
            for j in 0..slices {
                let x = cos1[j] * sin2[i];
                let y = sin1[j] * sin2[i];
                let z = cos2[i];
                positions.extend([x * radius, y * radius, z * radius]);
                normals.extend([x, y, z]);
            }
        }
        positions.extend([0.0, 0.0, -radius]);
        normals.extend([0.0, 0.0, -1.0]);

        let strip = (slices + 1) * 2;
        let mut indices: Vec<u16> = Vec::with_capacity(strip * stacks);
        // Top cap: each ring vertex paired with the north pole (vertex 0).
        for j in 0..slices {
            indices.extend([(j + 1) as u16, 0]);
        }
        indices.extend([1, 0]);
        // Middle stacks: this ring's vertex below, then the one above.
        for i in 0..stacks - 2 {
            let offset = 1 + i * slices;
            for j in 0..slices {
                indices.extend([(offset + j + slices) as u16, (offset + j) as u16]);
            }
            indices.extend([(offset + slices) as u16, offset as u16]);
        }
        // Bottom cap: the south pole paired with each vertex of the last ring.
        let offset = 1 + (stacks - 2) * slices;
        let south = (vertex_count - 1) as u16;
        for j in 0..slices {
            indices.extend([south, (offset + j) as u16]);
        }
        indices.extend([south, offset as u16]);
        Sphere {
            radius,
            slices,
            stacks,
            positions,
            normals,
            indices,
        }
    }

    /// Indices per triangle strip.
    pub fn strip_len(&self) -> usize {
        (self.slices + 1) * 2
    }
}
