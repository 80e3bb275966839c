//! The fake body models of `scripts/make_smpl_models.py`, made again here value for value (the
//! same splitmix64 noise and the same exactly rounded operations), so the tests need neither the
//! models (too large to commit) nor Python: only the script's committed reference, whose rest
//! joints the models are built on.

use super::npz::{f64s, npy, npz};
use bvhview::smpl::ModelType;

const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;
const MIX1: u64 = 0xBF58_476D_1CE4_E5B9;
const MIX2: u64 = 0x94D0_49BB_1331_11EB;

/// An eighth turn's cosine: the script's literal 0.7071067811865476, the same double.
const H: f64 = std::f64::consts::FRAC_1_SQRT_2;

const CORNER_C: [f64; 8] = [1.0, H, 0.0, -H, -1.0, -H, 0.0, H];
const CORNER_S: [f64; 8] = [0.0, H, 1.0, H, 0.0, -H, -1.0, -H];

/// `count` values in [-scale, scale), as the script's `noise`.
pub fn noise(seed: u64, count: usize, scale: f64) -> Vec<f64> {
    (0..count as u64)
        .map(|i| {
            let mut z = i.wrapping_add(seed << 40).wrapping_mul(GOLDEN);
            z = (z ^ (z >> 30)).wrapping_mul(MIX1);
            z = (z ^ (z >> 27)).wrapping_mul(MIX2);
            z ^= z >> 31;
            let unit = (z >> 11) as f64 * 2f64.powi(-53);
            (unit * 2.0 - 1.0) * scale
        })
        .collect()
}

/// Vertices, triangles and shape components of each type's fake model (the published sizes).
pub fn sizes(model: ModelType) -> (usize, usize, usize) {
    match model {
        ModelType::Smpl => (6890, 13776, 10),
        ModelType::Smplh => (6890, 13776, 16),
        ModelType::Smplx => (10475, 20908, 400),
    }
}

/// Triangle `i` of the tubes: two a quad, from step m to m + 1 along a bone, corner a to a + 1
/// around it, in one layer (the script's `tube_faces`).
fn tube_face(i: usize, vertices: usize, nb: usize) -> [usize; 3] {
    let v0 = (i / 2) % vertices;
    let (b0, k) = (v0 % nb, v0 / nb);
    let (m, a, layer) = ((k % 9).min(7), (k / 9) % 8, k / 72);
    // A corner past the last vertex (the last layer is cut short) folds to the quad's first.
    let vid = |m: usize, a: usize| {
        Some(b0 + nb * (m + 9 * a + 72 * layer))
            .filter(|&v| v < vertices)
            .unwrap_or(v0)
    };
    let a1 = (a + 1) % 8;
    if i.is_multiple_of(2) {
        [vid(m, a), vid(m + 1, a), vid(m + 1, a1)]
    } else {
        [vid(m, a), vid(m + 1, a1), vid(m, a1)]
    }
}

/// The `.npz` of the fake model of `model` built on `rest` (its joints at rest, metres).
pub fn model_npz(model: ModelType, rest: &[[f64; 3]]) -> Vec<u8> {
    let parents: Vec<usize> = model
        .parents()
        .iter()
        .map(|p| p.unwrap_or(usize::MAX))
        .collect();
    let joints = parents.len();
    let (vertices, faces, shapes) = sizes(model);
    let nb = joints - 1;
    let mut template = Vec::with_capacity(3 * vertices);
    let mut weights = vec![0.0; vertices * joints];
    for v in 0..vertices {
        let bone = 1 + v % nb;
        let k = v / nb;
        let (m, corner, layer) = (k % 9, (k / 9) % 8, (k / 72) % 4);
        let t = m as f64 / 8.0;
        let radius = (2.0 + layer as f64) / 100.0;
        let par = parents[bone];
        let d: Vec<f64> = (0..3).map(|a| rest[bone][a] - rest[par][a]).collect();
        let (c, s) = (CORNER_C[corner] * radius, CORNER_S[corner] * radius);
        let off = if d[0].abs() > d[1].abs() {
            [0.0, c, s]
        } else {
            [c, 0.0, s]
        };
        for a in 0..3 {
            template.push((rest[par][a] + d[a] * t) + off[a]);
        }
        weights[v * joints + par] = 1.0 - t / 2.0;
        weights[v * joints + bone] = t / 2.0;
    }
    // Noise, and a stretch: component l (of the first ten) moves each vertex of the bones
    // numbered l modulo ten away from the bone's parent joint by 5% a unit.
    let mut shape_dirs = noise(1, vertices * 3 * shapes, 0.002);
    for v in 0..vertices {
        let bone = 1 + v % nb;
        let l = bone % 10;
        if l < shapes.min(10) {
            for a in 0..3 {
                let stretch = 0.05 * (template[3 * v + a] - rest[parents[bone]][a]);
                let at = (3 * v + a) * shapes + l;
                shape_dirs[at] += stretch;
            }
        }
    }
    let mut regressor = vec![0.0; joints * vertices];
    let first_child = (1..joints).find(|&b| parents[b] == 0).unwrap();
    for j in 0..joints {
        for a in [0, 2, 4, 6] {
            let v = if j == 0 {
                (first_child - 1) + nb * (9 * a)
            } else {
                (j - 1) + nb * (8 + 9 * a)
            };
            regressor[j * vertices + v] = 0.25;
        }
    }
    let features = 9 * nb;
    let triangles: Vec<u8> = (0..faces)
        .flat_map(|i| tube_face(i, vertices, nb))
        .flat_map(|v| (v as u32).to_le_bytes())
        .collect();
    let tree: Vec<u8> = parents
        .iter()
        .map(|&p| {
            if p == usize::MAX {
                4294967295
            } else {
                p as i64
            }
        })
        .chain(0..joints as i64)
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let members = vec![
        ("kintree_table.npy", npy("<i8", &[2, joints], &tree)),
        (
            "v_template.npy",
            npy("<f8", &[vertices, 3], &f64s(&template)),
        ),
        (
            "weights.npy",
            npy("<f8", &[vertices, joints], &f64s(&weights)),
        ),
        (
            "J_regressor.npy",
            npy("<f8", &[joints, vertices], &f64s(&regressor)),
        ),
        (
            "shapedirs.npy",
            npy("<f8", &[vertices, 3, shapes], &f64s(&shape_dirs)),
        ),
        (
            "posedirs.npy",
            npy(
                "<f8",
                &[vertices, 3, features],
                &f64s(&noise(2, vertices * 3 * features, 0.001)),
            ),
        ),
        ("f.npy", npy("<u4", &[faces, 3], &triangles)),
    ];
    npz(&members, false)
}
