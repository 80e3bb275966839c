//! Characters: skinned meshes from FBX and glTF moved by linear blend skinning, held
//! to what other programs compute for the same files.

#![cfg(all(feature = "fbx", feature = "gltf"))]

use bvhview::character::Character;
use glam::Vec3;
use std::path::Path;

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

/// A float32 `.npy` array as (shape, values).
fn read_npy(path: &str) -> (Vec<usize>, Vec<f32>) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..6], b"\x93NUMPY");
    let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + header_len]).unwrap();
    assert!(header.contains("'descr': '<f4'"), "{header}");
    let shape_text = header
        .split("'shape': (")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap();
    let shape: Vec<usize> = shape_text
        .split(',')
        .filter(|s| !s.trim().is_empty())
        .map(|s| s.trim().parse().unwrap())
        .collect();
    let values = bytes[10 + header_len..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    (shape, values)
}

/// Blender 5.2's evaluated meshes (tests/blender/evaluated_mesh.py: its own FBX importer, which
/// is ufbx's, and its glTF importer) at four times of each character's own take: bvhview's
/// skinned vertices are within 1e-4 of the figure's height of Blender's, every vertex, every
/// time. Three characters from three tools: Maya (the Kenney character, ufbx's test file),
/// Blender's FBX exporter (capsule man with Mixamo's names, up to eight influences a vertex) and
/// the Khronos glTF Blender I/O exporter (the same figure, JOINTS_0/JOINTS_1).
#[test]
fn characters_agree_with_blender() {
    // (file, reference, our frames at the reference's times)
    let cases = [
        (
            KENNEY,
            "maya_kenney_character_7700_binary.npy",
            [0usize, 6, 12, 20],
        ),
        (
            "tests/data/characters/capsule_mixamo.fbx",
            "capsule_mixamo_fbx.npy",
            [0, 8, 18, 29],
        ),
        (
            "tests/data/characters/capsule_mixamo.glb",
            "capsule_mixamo_glb.npy",
            [0, 8, 18, 29],
        ),
    ];
    for (file, reference, frames) in cases {
        let character = Character::open(file).unwrap();
        let take = &character.take;
        let (shape, values) = read_npy(&format!("tests/data/characters/blender/{reference}"));
        assert_eq!(shape, [4, character.mesh.vertex_count(), 3], "{file}");
        let per_time = shape[1] * 3;
        let mut worst_of_all = 0.0f32;
        let mut height = 0.0f32;
        for (k, &frame) in frames.iter().enumerate() {
            let ours = character.vertices(&take.skeleton, take.frame(frame).unwrap());
            let blender: Vec<Vec3> = values[k * per_time..(k + 1) * per_time]
                .chunks_exact(3)
                .map(Vec3::from_slice)
                .collect();
            let (worst, tall) = worst(&ours, &blender);
            worst_of_all = worst_of_all.max(worst);
            height = height.max(tall);
        }
        eprintln!("{file}: worst {worst_of_all:.3e} m of a height of {height:.3} m");
        assert!(
            worst_of_all <= 1e-4 * height,
            "{file}: {worst_of_all} m, height {height} m"
        );
    }
}

/// `convert --character` writes the character's mesh bound to the take's joints (a glTF skin per
/// mesh of the file): read back as a character, every vertex is where bvhview put it, for each
/// character on itself and for a CMU walk put on each.
#[test]
fn a_character_written_as_gltf_reads_back_the_same() {
    use bvhview::gltf::{Container, to_gltf_character};
    let walk = bvhview::Take::open("tests/data/bvh/bvh11_131_01.bvh")
        .unwrap()
        .trim(0..40);
    let folder = tempfile::tempdir().unwrap();
    for file in [
        KENNEY,
        "tests/data/characters/capsule_mixamo.fbx",
        "tests/data/characters/capsule_mixamo.glb",
    ] {
        let character = Character::open(file).unwrap();
        let on_walk = character
            .dress(&walk, &[], Default::default(), 2)
            .unwrap()
            .0;
        for (label, take) in [("itself", &character.take), ("the walk", &on_walk)] {
            let bytes = to_gltf_character(
                &take.skeleton,
                &take.motion,
                &character.mesh,
                Container::Glb,
            )
            .unwrap();
            let path = folder.path().join("out.glb");
            std::fs::write(&path, bytes).unwrap();
            let back = Character::open(&path).unwrap();
            assert_eq!(back.mesh.vertex_count(), character.mesh.vertex_count());
            assert_eq!(back.take.frame_count(), take.frame_count());
            let mut worst_of_all = (0.0f32, 0.0f32);
            for frame in [0, take.frame_count() / 2, take.frame_count() - 1] {
                let want = character.vertices(&take.skeleton, take.frame(frame).unwrap());
                let got = back.vertices(&back.take.skeleton, back.take.frame(frame).unwrap());
                let (worst, height) = worst(&got, &want);
                worst_of_all = (worst_of_all.0.max(worst), worst_of_all.1.max(height));
            }
            let (worst, height) = worst_of_all;
            eprintln!("{file} on {label}: worst {worst:.3e} m of {height:.3} m");
            assert!(
                worst <= 1e-5 * height,
                "{file} on {label}: {worst} m of {height} m"
            );
        }
    }
}

/// A glTF of two joints and one triangle skinned to them, written beside its buffer into
/// `folder`; `joints`, `weights` per vertex (four each) and the triangle's `indices` as given.
fn tiny_skinned_gltf(
    folder: &std::path::Path,
    name: &str,
    joints: [[u16; 4]; 3],
    weights: [[f32; 4]; 3],
    indices: [u16; 3],
) -> std::path::PathBuf {
    let mut bin: Vec<u8> = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        bin.extend(p.iter().flat_map(|v| v.to_le_bytes()));
    }
    for j in joints {
        bin.extend(j.iter().flat_map(|v| v.to_le_bytes()));
    }
    for w in weights {
        bin.extend(w.iter().flat_map(|v| v.to_le_bytes()));
    }
    bin.extend(indices.iter().flat_map(|v| v.to_le_bytes()));
    bin.extend([0, 0]);
    std::fs::write(folder.join(format!("{name}.bin")), &bin).unwrap();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,2]}}],
        "nodes":[{{"name":"root","children":[1]}},{{"name":"tip","translation":[0,1,0]}},
                 {{"name":"mesh","mesh":0,"skin":0}}],
        "skins":[{{"joints":[0,1]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"JOINTS_0":1,"WEIGHTS_0":2}},"indices":3}}]}}],
        "buffers":[{{"uri":"{name}.bin","byteLength":{}}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":24}},
                       {{"buffer":0,"byteOffset":60,"byteLength":48}},{{"buffer":0,"byteOffset":108,"byteLength":6}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
                     {{"bufferView":1,"componentType":5123,"count":3,"type":"VEC4"}},
                     {{"bufferView":2,"componentType":5126,"count":3,"type":"VEC4"}},
                     {{"bufferView":3,"componentType":5123,"count":3,"type":"SCALAR"}}]}}"#,
        bin.len()
    );
    let path = folder.join(format!("{name}.gltf"));
    std::fs::write(&path, json).unwrap();
    path
}

/// Hostile meshes: weights that do not sum to one are scaled, with one
/// warning for the file; a weight that is not a number, a negative weight, a joint past the
/// skin and a triangle index past the vertices are each refused with what and where.
#[test]
fn hostile_meshes_get_an_exact_refusal_or_one_warning() {
    let folder = tempfile::tempdir().unwrap();
    let ok_joints = [[0, 1, 0, 0]; 3];
    let good = tiny_skinned_gltf(
        folder.path(),
        "good",
        ok_joints,
        [[0.5, 0.5, 0.0, 0.0]; 3],
        [0, 1, 2],
    );
    let character = Character::open(&good).unwrap();
    assert_eq!(character.mesh.vertex_count(), 3);
    assert!(
        character
            .take
            .warnings
            .iter()
            .all(|w| !w.to_string().contains("sum to 1"))
    );

    let scaled = tiny_skinned_gltf(
        folder.path(),
        "scaled",
        ok_joints,
        [
            [1.0, 1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0, 0.0],
            [0.5, 0.5, 0.0, 0.0],
        ],
        [0, 1, 2],
    );
    let character = Character::open(&scaled).unwrap();
    let said: Vec<String> = character
        .take
        .warnings
        .iter()
        .map(ToString::to_string)
        .filter(|w| w.contains("sum to 1"))
        .collect();
    assert_eq!(said.len(), 1, "{:?}", character.take.warnings);
    assert!(said[0].starts_with("2 of 3 mesh vertices"), "{said:?}");
    let first = character.mesh.influences_of(0);
    assert_eq!(first.iter().map(|i| i.weight).sum::<f32>(), 1.0);

    let refused = |name: &str, joints, weights, indices, want: &str| {
        let path = tiny_skinned_gltf(folder.path(), name, joints, weights, indices);
        let error = Character::open(&path).unwrap_err().to_string();
        assert!(error.contains(want), "{name}: {error}");
        assert!(error.contains(&format!("{name}.gltf")), "{name}: {error}");
    };
    let nan = [
        [f32::NAN, 1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
    ];
    refused(
        "nan",
        ok_joints,
        nan,
        [0, 1, 2],
        "vertex 0 has a weight of NaN",
    );
    let negative = [
        [-1.0, 2.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
    ];
    refused(
        "negative",
        ok_joints,
        negative,
        [0, 1, 2],
        "vertex 0 has a weight of -1",
    );
    refused(
        "joint",
        [[0, 7, 0, 0], [0, 1, 0, 0], [0, 1, 0, 0]],
        [[0.5, 0.5, 0.0, 0.0]; 3],
        [0, 1, 2],
        "vertex 0: joint 7 of a skin of 2 joints",
    );
    refused(
        "index",
        ok_joints,
        [[0.5, 0.5, 0.0, 0.0]; 3],
        [0, 1, 9],
        "index 9 of a primitive of 3 vertices",
    );
}

/// Golden pictures of characters (the studio look, 400 × 400): the Kenney figure in its own
/// take, and capsule man (Blender's FBX, and the glTF whose back faces are culled) with the CMU
/// walk on it. At most 0.1 % of the pixels may
/// differ (as for every golden picture); `BVHVIEW_BLESS=1` writes them anew.
#[test]
fn characters_match_their_golden_pictures() {
    use bvhview::render::{Look, Renderer, SnapshotOptions, draw::Style, paint::Shown};
    let walk = bvhview::Take::open("tests/data/bvh/bvh11_131_01.bvh").unwrap();
    let bless = std::env::var_os("BVHVIEW_BLESS").is_some();
    for (name, file, on_walk, frame) in [
        ("character_kenney__f12__studio", KENNEY, false, 12),
        (
            "character_capsule_fbx__walk__f60__studio",
            "tests/data/characters/capsule_mixamo.fbx",
            true,
            60,
        ),
        // glTF's single-sided material: back faces culled (in the shadow too).
        (
            "character_capsule_glb__walk__f90__studio",
            "tests/data/characters/capsule_mixamo.glb",
            true,
            90,
        ),
    ] {
        let character = Character::open(file).unwrap();
        let take = if on_walk {
            character
                .dress(&walk, &[], Default::default(), 2)
                .unwrap()
                .0
        } else {
            character.take.clone()
        };
        let shown = [Shown {
            skeleton: &take.skeleton,
            motion: &take.motion,
            up: Default::default(),
            stance: take.stance(Default::default()),
            mesh: Some(&character.mesh),
        }];
        let options = SnapshotOptions {
            frame,
            width: 400,
            height: 400,
            look: Look::Studio,
            style: Style::Points,
            ..SnapshotOptions::default()
        };
        let ours = Renderer::new(400, 400)
            .unwrap()
            .render_all(&shown, &options, &Default::default())
            .unwrap();
        let golden = std::path::Path::new("tests/snapshots").join(format!("{name}.png"));
        if bless {
            ours.write_png(&golden).unwrap();
            continue;
        }
        let expected = bvhview::render::Image::read_png(&golden).unwrap();
        let differing = ours.differing_pixels(&expected);
        println!("drift {name}: {differing} of 160000 pixels differ (at most 160)");
        assert!(differing <= 160, "{name}: {differing} pixels differ");
    }
}

/// The travel joint is in the body's tree: the Kenney rig's IK controls (`LeftFootCtrl`, a root
/// of its own listed first) are not the body's travel; `HipsCtrl`, the root above the hips, is.
#[test]
fn a_rig_s_controls_are_not_its_travel() {
    let kenney = bvhview::Take::open(KENNEY).unwrap();
    let travel = bvhview::model::body::travel::travel_joint_of_take(
        &kenney.skeleton,
        &kenney.motion,
        Default::default(),
    );
    assert_eq!(kenney.skeleton.joints[0].name, "LeftFootCtrl");
    assert_eq!(kenney.skeleton.joints[travel].name, "HipsCtrl");
}

/// Found by fuzzing (`scripts/fuzz.sh gltf_character`): a primitive whose POSITION names an
/// accessor past the list made gltf-json's own validation panic (it indexes it unchecked); the
/// reader now checks it first and refuses the file, for takes and characters alike.
#[test]
fn a_position_accessor_past_the_list_is_refused_not_a_panic() {
    let json = br#"{"asset":{"version":"2.0"},"nodes":[{"mesh":0}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":5}}]}]}"#;
    let take = bvhview::gltf::load_bytes(json, "bad.gltf", &Default::default())
        .unwrap_err()
        .to_string();
    assert_eq!(take, "bad.gltf: mesh 0: a POSITION accessor 5 of 0");
    let character =
        bvhview::gltf::load_character_bytes(json, "bad.gltf", &Default::default()).unwrap_err();
    assert_eq!(character.to_string(), take);
}

/// A take of no frames (an ASF alone: its rest pose) gives its rest
/// pose's vertices, not a panic; a mesh whose bind mirrors it is not culled (its winding is
/// turned over).
#[test]
fn a_take_without_frames_gives_the_rest_pose_and_mirrors_are_not_culled() {
    use bvhview::character::{VertexFormat, write_vertices};
    let capsule = Character::open("tests/data/characters/capsule_mixamo.glb").unwrap();
    assert!(capsule.mesh.single_sided());
    let asf = bvhview::Take::open("tests/data/asf_amc/heiden_12.asf").unwrap();
    assert_eq!(asf.frame_count(), 0);
    let dressed = capsule.dress(&asf, &[], Default::default(), 1).unwrap().0;
    let mut npy = Vec::new();
    write_vertices(
        &mut npy,
        &capsule,
        &dressed.skeleton,
        &dressed.motion,
        0..1,
        VertexFormat::Npy,
    )
    .unwrap();
    assert_eq!(npy.len(), 128 + capsule.mesh.vertex_count() * 12);
    let mut mirrored = capsule.mesh.clone();
    mirrored.bones[0].bind =
        glam::Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) * mirrored.bones[0].bind;
    assert!(!mirrored.single_sided());
}

/// A take on a character is the character's skeleton, written for the replace mode its mesh is
/// bound in: `--offset-mode add` (meant for the files) once drew its bones and floor a whole
/// hip height above the mesh (42,145 of 360,000 pixels differed in the same picture at 600 ×
/// 600). Now the same picture.
#[test]
fn a_take_on_a_character_ignores_the_files_offset_mode() {
    use bvhview::model::pose::OffsetMode;
    use bvhview::render::{Look, Renderer, SnapshotOptions, draw::Style, paint::Shown};
    let walk = bvhview::Take::open("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
    let character = Character::open("tests/data/characters/capsule_mixamo.glb").unwrap();
    let take = character
        .dress(&walk, &[], Default::default(), 2)
        .unwrap()
        .0;
    let picture = |offset_mode| {
        let shown = [Shown {
            skeleton: &take.skeleton,
            motion: &take.motion,
            up: Default::default(),
            stance: take.stance(OffsetMode::Replace),
            mesh: Some(&character.mesh),
        }];
        let options = SnapshotOptions {
            frame: 20,
            width: 300,
            height: 300,
            look: Look::Studio,
            style: Style::Sticks,
            offset_mode,
            ..SnapshotOptions::default()
        };
        Renderer::new(300, 300)
            .unwrap()
            .render_all(&shown, &options, &Default::default())
            .unwrap()
    };
    let differing = picture(OffsetMode::Add).differing_pixels(&picture(OffsetMode::Replace));
    assert_eq!(differing, 0);
}

/// A `byteStride` shorter than its element (every vertex read from its
/// neighbour's bytes) is refused naming file, mesh and accessor; a last index short of a
/// triangle is left out and said once.
#[test]
fn a_stride_shorter_than_its_element_is_refused_and_a_short_triangle_said() {
    let folder = tempfile::tempdir().unwrap();
    let joints = [[0, 1, 0, 0]; 3];
    let weights = [[0.5, 0.5, 0.0, 0.0]; 3];
    let path = tiny_skinned_gltf(folder.path(), "stride", joints, weights, [0, 1, 2]);
    let json = std::fs::read_to_string(&path).unwrap();
    let strided = json.replacen(
        r#""byteLength":36}"#,
        r#""byteLength":36,"byteStride":4}"#,
        1,
    );
    assert_ne!(strided, json);
    std::fs::write(&path, strided).unwrap();
    let error = Character::open(&path).unwrap_err().to_string();
    assert!(
        error.ends_with(
            "stride.gltf: mesh '0': accessor 0: its buffer view's byteStride 4 is shorter than \
             one element (12 bytes): the elements would overlap"
        ),
        "{error}"
    );

    let path = tiny_skinned_gltf(folder.path(), "short", joints, weights, [0, 1, 2]);
    let json = std::fs::read_to_string(&path).unwrap();
    // The two bytes of padding after the indices become a fourth index.
    let four = json
        .replacen(
            r#""byteOffset":108,"byteLength":6"#,
            r#""byteOffset":108,"byteLength":8"#,
            1,
        )
        .replacen(
            r#""count":3,"type":"SCALAR""#,
            r#""count":4,"type":"SCALAR""#,
            1,
        );
    std::fs::write(&path, four).unwrap();
    let character = Character::open(&path).unwrap();
    assert_eq!(character.mesh.triangles, [0, 1, 2]);
    let said: Vec<String> = character
        .take
        .warnings
        .iter()
        .map(ToString::to_string)
        .filter(|w| w.contains("short of a triangle"))
        .collect();
    assert_eq!(
        said,
        [
            "the last 1 or 2 indices of 1 primitive fall short of a triangle and are left out: \
          mesh '0'"
        ]
    );
}

/// An inverse bind scale of 3e38 skinned every vertex past what a float
/// holds (`snapshot` drew a blank picture, `convert` wrote a GLB bvhview then refused): refused
/// when the character is read, naming the joint and a vertex it moves.
#[test]
fn a_bind_that_skins_vertices_past_a_float_is_refused_when_read() {
    let folder = tempfile::tempdir().unwrap();
    let path = tiny_skinned_gltf(
        folder.path(),
        "huge",
        [[0, 1, 0, 0]; 3],
        [[1.0, 0.0, 0.0, 0.0]; 3],
        [0, 1, 2],
    );
    let bin = folder.path().join("huge.bin");
    let mut bytes = std::fs::read(&bin).unwrap();
    let at = bytes.len();
    for k in 0..2 {
        let s = if k == 0 { 3e38f32 } else { 1.0 };
        let m = [s, 0., 0., 0., 0., s, 0., 0., 0., 0., s, 0., 0., 0., 0., 1.];
        bytes.extend(m.iter().flat_map(|v| v.to_le_bytes()));
    }
    std::fs::write(&bin, &bytes).unwrap();
    let json = std::fs::read_to_string(&path)
        .unwrap()
        .replacen(
            r#""joints":[0,1]"#,
            r#""joints":[0,1],"inverseBindMatrices":4"#,
            1,
        )
        .replacen(
            &format!(r#""byteLength":{at}"#),
            &format!(r#""byteLength":{}"#, bytes.len()),
            1,
        )
        .replacen(
            r#""byteLength":6}]"#,
            &format!(r#""byteLength":6}},{{"buffer":0,"byteOffset":{at},"byteLength":128}}]"#),
            1,
        )
        .replacen(
            r#""type":"SCALAR"}]"#,
            r#""type":"SCALAR"},{"bufferView":4,"componentType":5126,"count":2,"type":"MAT4"}]"#,
            1,
        );
    std::fs::write(&path, json).unwrap();
    let error = Character::open(&path).unwrap_err().to_string();
    assert!(
        error.ends_with(
            "huge.gltf: the bind matrix of joint 'root' (mesh '0', vertex 0 is bound to it) holds \
             3.00e38, past 1e12: its vertices would be skinned past what a float holds (the \
             skin's inverse bind matrix is damaged: export the skin again)"
        ),
        "{error}"
    );
}

/// One vertex of many influences gave every vertex as many glTF sets as
/// it (3.9 GB for 100,000): a vertex is written with its strongest 8, scaled to sum to 1, in
/// two `JOINTS_n`/`WEIGHTS_n` sets.
#[test]
fn a_vertex_of_many_influences_is_written_with_its_strongest_eight() {
    use bvhview::model::mesh::Influence;
    let folder = tempfile::tempdir().unwrap();
    let path = tiny_skinned_gltf(
        folder.path(),
        "many",
        [[0, 1, 0, 0]; 3],
        [[0.5, 0.5, 0.0, 0.0]; 3],
        [0, 1, 2],
    );
    let mut character = Character::open(&path).unwrap();
    let mesh = &mut character.mesh;
    // Vertex 0: 1,000 influences, weights 1 to 1000 alternating between the two joints.
    let many: Vec<Influence> = (1..=1000)
        .map(|k| Influence {
            bone: k % 2,
            weight: k as f32,
        })
        .collect();
    let rest: Vec<Influence> = mesh.influences[mesh.influence_start[1] as usize..].to_vec();
    mesh.influences = many.into_iter().chain(rest).collect();
    let shift = 1000 - mesh.influence_start[1];
    for start in &mut mesh.influence_start[1..] {
        *start += shift;
    }
    mesh.check().unwrap();
    assert_eq!(
        bvhview::model::mesh::vertices_past_written_influences(mesh),
        1
    );
    let take = &character.take;
    let bytes = bvhview::gltf::to_gltf_character(
        &take.skeleton,
        &take.motion,
        &character.mesh,
        bvhview::gltf::Container::Glb,
    )
    .unwrap();
    // Two sets: three vertices × 2 × (8 + 16) bytes, not 250 sets.
    assert!(bytes.len() < 4000, "{} bytes", bytes.len());
    let written = folder.path().join("written.glb");
    std::fs::write(&written, bytes).unwrap();
    let back = Character::open(&written).unwrap();
    let kept: Vec<f32> = back
        .mesh
        .influences_of(0)
        .iter()
        .map(|i| i.weight)
        .collect();
    let total = (993..=1000).sum::<i32>() as f32;
    let want: Vec<f32> = (993..=1000).rev().map(|k| k as f32 / total).collect();
    assert_eq!(kept.len(), 8);
    for (k, w) in kept.iter().zip(&want) {
        assert!((k - w).abs() < 1e-6, "{kept:?} vs {want:?}");
    }
    assert_eq!(back.mesh.influences_of(1).len(), 2);
}

/// An ASCII FBX 7.4 of one mesh (`vertices` as x,y,z…, `polygons` as FBX writes them, the last
/// corner of each negated less one) on two joints, one skin cluster of `indexes` (weight 1
/// each) on the first, written into `folder`.
fn ascii_fbx(
    folder: &std::path::Path,
    name: &str,
    vertices: &[f32],
    polygons: &[i32],
    indexes: &[i32],
) -> std::path::PathBuf {
    let list = |v: &[String]| v.join(",");
    let vertices: Vec<String> = vertices.iter().map(|v| v.to_string()).collect();
    let polygons: Vec<String> = polygons.iter().map(|v| v.to_string()).collect();
    let indexes: Vec<String> = indexes.iter().map(|v| v.to_string()).collect();
    let weights = vec!["1".to_string(); indexes.len()];
    let identity = "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1";
    let text = format!(
        "; FBX 7.4.0 project file\nFBXHeaderExtension:  {{\n FBXHeaderVersion: 1003\n FBXVersion: 7400\n}}\n\
         Objects:  {{\n Geometry: 1000, \"Geometry::body\", \"Mesh\" {{\n  Vertices: *{} {{\n   a: {}\n  }}\n\
         PolygonVertexIndex: *{} {{\n   a: {}\n  }}\n }}\n Model: 2000, \"Model::body\", \"Mesh\" {{\n }}\n\
         Model: 3000, \"Model::Hips\", \"LimbNode\" {{\n }}\n Model: 3001, \"Model::Spine\", \"LimbNode\" {{\n\
         Properties70:  {{\n   P: \"Lcl Translation\", \"Lcl Translation\", \"\", \"A\",0,1,0\n  }}\n }}\n\
         NodeAttribute: 6000, \"NodeAttribute::Hips\", \"LimbNode\" {{\n  TypeFlags: \"Skeleton\"\n }}\n\
         NodeAttribute: 6001, \"NodeAttribute::Spine\", \"LimbNode\" {{\n  TypeFlags: \"Skeleton\"\n }}\n\
         Deformer: 4000, \"Deformer::skin\", \"Skin\" {{\n }}\n Deformer: 5000, \"SubDeformer::c0\", \"Cluster\" {{\n\
         Indexes: *{} {{\n   a: {}\n  }}\n  Weights: *{} {{\n   a: {}\n  }}\n  Transform: *16 {{\n   a: {identity}\n  }}\n\
         TransformLink: *16 {{\n   a: {identity}\n  }}\n }}\n}}\nConnections:  {{\n C: \"OO\",2000,0\n C: \"OO\",3000,0\n\
         C: \"OO\",3001,3000\n C: \"OO\",6000,3000\n C: \"OO\",6001,3001\n C: \"OO\",1000,2000\n C: \"OO\",4000,1000\n\
         C: \"OO\",5000,4000\n C: \"OO\",3000,5000\n}}\n",
        vertices.len(),
        list(&vertices),
        polygons.len(),
        list(&polygons),
        indexes.len(),
        list(&indexes),
        weights.len(),
        list(&weights)
    );
    let path = folder.join(format!("{name}.fbx"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Skin cluster indices past the vertices (or negative), which
/// ufbx drops, are refused naming file, mesh and cluster; a polygon of more corners than ear
/// clipping is given (quadratic: a 1,000,000-corner polygon ran past a minute) is cut into a
/// fan and said once.
#[test]
fn fbx_clusters_past_the_vertices_are_refused_and_huge_polygons_are_fans() {
    let folder = tempfile::tempdir().unwrap();
    let triangle = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    for (name, index, shown) in [("past", 7, "7"), ("negative", -1, "-1")] {
        let path = ascii_fbx(
            folder.path(),
            name,
            &triangle,
            &[0, 1, -3],
            &[0, 1, 2, index],
        );
        let error = Character::open(&path).unwrap_err().to_string();
        assert!(
            error.ends_with(&format!(
                "{name}.fbx: mesh 'body': skin cluster 'c0' names vertex {shown}, past the \
                 mesh's 3 vertices (the skin is damaged: export it again)"
            )),
            "{error}"
        );
    }
    let ok = ascii_fbx(folder.path(), "ok", &triangle, &[0, 1, -3], &[0, 1, 2]);
    assert_eq!(Character::open(&ok).unwrap().mesh.triangles.len(), 3);

    // A convex polygon of 2,000 corners: 1,998 triangles from corner 0.
    let n = 2000;
    let ring: Vec<f32> = (0..n)
        .flat_map(|k| {
            let a = std::f32::consts::TAU * k as f32 / n as f32;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    let mut polygon: Vec<i32> = (0..n).collect();
    polygon[n as usize - 1] = -n;
    let path = ascii_fbx(folder.path(), "huge", &ring, &polygon, &[0]);
    let character = Character::open(&path).unwrap();
    let triangles = &character.mesh.triangles;
    assert_eq!(triangles.len(), 3 * (n as usize - 2));
    assert_eq!(triangles[..6], [0, 1, 2, 0, 2, 3]);
    let said: Vec<String> = character
        .take
        .warnings
        .iter()
        .map(ToString::to_string)
        .filter(|w| w.contains("fans"))
        .collect();
    assert_eq!(
        said,
        [
            "1 polygon of more than 1024 corners cut into fans from their first corner (a concave \
          one may be drawn wrong: cut it into smaller polygons)"
        ]
    );
}

/// `--take` picks the take of the character's own file, and a take of the character's own
/// skeleton is put on as the file has it: on a file whose take 1 is a copy of take 0, the
/// vertices of take 1 were take 0 retargeted onto itself (0.25 m off); now they are equal.
#[test]
fn a_characters_own_takes_are_put_on_exactly() {
    use serde_json::Value;
    let glb = std::fs::read("tests/data/characters/capsule_mixamo.glb").unwrap();
    let chunk = |at: usize| {
        let length = u32::from_le_bytes(glb[at..at + 4].try_into().unwrap()) as usize;
        (&glb[at + 8..at + 8 + length], at + 8 + length)
    };
    let (json, after) = chunk(12);
    let (bin, _) = chunk(after);
    let mut document: Value = serde_json::from_slice(json).unwrap();
    let animations = document["animations"].as_array_mut().unwrap();
    let mut copy = animations[0].clone();
    copy["name"] = Value::from("Copy");
    animations.push(copy);
    let mut json = serde_json::to_vec(&document).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("two_takes.glb");
    std::fs::write(&file, out).unwrap();
    let file = file.to_str().unwrap();
    let vertices = |take: &str| {
        let csv = dir.path().join(format!("take{take}.csv"));
        let run = crate::common::bvhview_command()
            .args([
                "positions",
                file,
                "--character",
                file,
                "--take",
                take,
                "--vertices",
            ])
            .arg("-o")
            .arg(&csv)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        std::fs::read_to_string(csv).unwrap()
    };
    let (first, copy) = (vertices("0"), vertices("1"));
    assert!(first.lines().count() > 1000, "{}", first.lines().count());
    let differ = first.lines().zip(copy.lines()).find(|(a, b)| a != b);
    assert_eq!(differ, None, "the first line that differs");
    assert_eq!(first.len(), copy.len());
    // In the library: the character read with its other take is on the same skeleton.
    let character = Character::open(file).unwrap();
    let other = Character::open_with(
        Path::new(file),
        &bvhview::take::OpenOptions::new()
            .max_size(u64::MAX)
            .take("1")
            .threads(1),
    )
    .unwrap();
    assert!(character.is_own_skeleton(&other.take.skeleton));
    assert_eq!(other.take.take_name.as_deref(), Some("Copy"));
}
