//! Characters (issue 49): skinned meshes from FBX and glTF moved by linear blend skinning, held
//! to what other programs compute for the same files.

#![cfg(all(feature = "fbx", feature = "gltf"))]

use bvhview::character::Character;
use glam::Vec3;

const KENNEY: &str = "tests/data/characters/maya_kenney_character_7700_binary.fbx";

/// The `v` lines of an OBJ file.
fn obj_vertices(path: &str) -> Vec<Vec3> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f32> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            Vec3::new(v[0], v[1], v[2])
        })
        .collect()
}

/// The largest distance between matching points, and the figure's height (the points' extent
/// along y).
fn worst(a: &[Vec3], b: &[Vec3]) -> (f32, f32) {
    assert_eq!(a.len(), b.len());
    let worst = a
        .iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max);
    let (lo, hi) = b
        .iter()
        .fold((f32::MAX, f32::MIN), |(l, h), p| (l.min(p.y), h.max(p.y)));
    (worst, hi - lo)
}

/// ufbx's test files carry the Kenney character (Maya 2020) and, beside it, the mesh Maya
/// evaluated at frames 4 and 9 (OBJ, centimetres). bvhview's skinning of its own reading of the
/// file lands every vertex within 1e-4 of the figure's height of Maya's.
#[test]
fn the_kenney_character_lands_where_maya_put_it() {
    let kenney = Character::open(KENNEY).unwrap();
    let take = &kenney.take;
    for frame in [4usize, 9] {
        let ours = kenney.vertices(&take.skeleton, take.frame(frame).unwrap());
        let maya: Vec<Vec3> = obj_vertices(&format!(
            "tests/data/characters/maya_kenney_character_{frame}.obj"
        ))
        .into_iter()
        .map(|v| v * 0.01)
        .collect();
        let (worst, height) = worst(&ours, &maya);
        eprintln!("frame {frame}: worst {worst} m of a height of {height} m");
        assert!(
            worst <= 1e-4 * height,
            "frame {frame}: {worst} m, height {height} m"
        );
    }
}
