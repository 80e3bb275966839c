//! glTF out (`convert -o X.glb|.gltf`): the file is read back here with the gltf-json crate and
//! its own node tree is evaluated (translation, then the sampled rotation and translation keys),
//! which must give the world positions `bvhview positions` prints, frame by frame. The Khronos
//! validator and Blender check the same files from outside (scripts/test.sh, tests/blender).

use crate::common;
use common::*;
use glam::{Mat4, Quat, Vec3};
use gltf_json as json;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Output;

fn ok(args: &[&str]) -> Output {
    let out = bvhview(args);
    assert!(
        out.status.success(),
        "bvhview {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A fresh path: tests run in parallel, so every call gets its own folder.
fn temp(name: &str) -> PathBuf {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = crate::common::scratch_folder(&format!("gltf-{call}"));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A glTF file read back: its JSON and its binary buffer.
struct Gltf {
    root: json::Root,
    bin: Vec<u8>,
}

impl Gltf {
    fn read(path: &Path) -> Gltf {
        let bytes = std::fs::read(path).unwrap();
        if path.extension().is_some_and(|e| e == "gltf") {
            let root = json::Root::from_slice(&bytes).unwrap();
            let bin = match root.buffers.first().and_then(|b| b.uri.clone()) {
                Some(uri) => {
                    let data = uri
                        .strip_prefix("data:application/octet-stream;base64,")
                        .expect("an inline buffer");
                    unbase64(data)
                }
                None => Vec::new(),
            };
            return Gltf { root, bin };
        }
        let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        assert_eq!(&bytes[0..4], b"glTF");
        assert_eq!(word(4), 2, "version");
        assert_eq!(word(8), bytes.len(), "the header's length is the file's");
        let json_length = word(12);
        assert_eq!(&bytes[16..20], b"JSON");
        assert_eq!(json_length % 4, 0, "chunks are 4-byte aligned");
        let root = json::Root::from_slice(&bytes[20..20 + json_length]).unwrap();
        let mut bin = Vec::new();
        let at = 20 + json_length;
        if at < bytes.len() {
            let length = word(at);
            assert_eq!(&bytes[at + 4..at + 8], b"BIN\0");
            assert_eq!(at + 8 + length, bytes.len());
            bin = bytes[at + 8..].to_vec();
            assert_eq!(root.buffers[0].byte_length.0 as usize, length);
        }
        Gltf { root, bin }
    }

    /// The bytes an accessor reads, and its element count.
    fn accessor_bytes(&self, index: json::Index<json::Accessor>) -> (&[u8], usize) {
        let accessor = &self.root.accessors[index.value()];
        let view = &self.root.buffer_views[accessor.buffer_view.unwrap().value()];
        let start = view.byte_offset.map_or(0, |o| o.0 as usize)
            + accessor.byte_offset.map_or(0, |o| o.0 as usize);
        let end = view.byte_offset.map_or(0, |o| o.0 as usize) + view.byte_length.0 as usize;
        (&self.bin[start..end], accessor.count.0 as usize)
    }

    fn floats(&self, index: json::Index<json::Accessor>) -> Vec<f32> {
        let accessor = &self.root.accessors[index.value()];
        assert!(matches!(
            accessor.component_type,
            json::validation::Checked::Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::F32
            ))
        ));
        let (bytes, count) = self.accessor_bytes(index);
        let width = match accessor.type_.as_ref().unwrap() {
            json::accessor::Type::Scalar => 1,
            json::accessor::Type::Vec3 => 3,
            json::accessor::Type::Vec4 => 4,
            json::accessor::Type::Mat4 => 16,
            other => panic!("unexpected accessor type {other:?}"),
        };
        let values: Vec<f32> = bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(values.len(), count * width);
        values
    }

    fn parents(&self) -> Vec<Option<usize>> {
        let mut parents = vec![None; self.root.nodes.len()];
        for (index, node) in self.root.nodes.iter().enumerate() {
            for child in node.children.iter().flatten() {
                parents[child.value()] = Some(index);
            }
        }
        parents
    }

    /// Each joint node's world matrix at a frame, by the file's own tree and keys.
    fn world(&self, frame: usize) -> Vec<Mat4> {
        let nodes = &self.root.nodes;
        let mut rotation: Vec<Quat> = nodes
            .iter()
            .map(|n| n.rotation.map_or(Quat::IDENTITY, |q| Quat::from_array(q.0)))
            .collect();
        let mut translation: Vec<Vec3> = nodes
            .iter()
            .map(|n| Vec3::from_array(n.translation.unwrap_or([0.0; 3])))
            .collect();
        for animation in &self.root.animations {
            for channel in &animation.channels {
                let sampler = &animation.samplers[channel.sampler.value()];
                let values = self.floats(sampler.output);
                let node = channel.target.node.value();
                match channel.target.path.as_ref().unwrap() {
                    json::animation::Property::Rotation => {
                        let q = Quat::from_slice(&values[frame * 4..frame * 4 + 4]);
                        assert!((q.length() - 1.0).abs() < 1e-6, "unit quaternion");
                        rotation[node] = q;
                    }
                    json::animation::Property::Translation => {
                        translation[node] = Vec3::from_slice(&values[frame * 3..frame * 3 + 3]);
                    }
                    other => panic!("unexpected target {other:?}"),
                }
            }
        }
        let parents = self.parents();
        let mut world: Vec<Mat4> = Vec::with_capacity(nodes.len());
        for index in 0..nodes.len() {
            let local = Mat4::from_rotation_translation(rotation[index], translation[index]);
            // Nodes are written in pre-order: a parent comes before its children.
            world.push(match parents[index] {
                Some(parent) => {
                    assert!(parent < index, "pre-order");
                    world[parent] * local
                }
                None => local,
            });
        }
        world
    }

    fn node_index(&self) -> HashMap<String, usize> {
        self.root
            .nodes
            .iter()
            .enumerate()
            .map(|(i, n)| (n.name.clone().unwrap(), i))
            .collect()
    }
}

fn unbase64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    } as u32;
    let mut out = Vec::new();
    for group in text.as_bytes().chunks(4) {
        let digits: Vec<u32> = group
            .iter()
            .filter(|&&c| c != b'=')
            .map(|&c| value(c))
            .collect();
        let n = digits
            .iter()
            .enumerate()
            .fold(0u32, |n, (k, d)| n | d << (18 - 6 * k));
        out.extend(n.to_be_bytes()[1..digits.len()].iter());
    }
    out
}

/// `positions` CSV rows as frame → joint → position.
fn positions(args: &[&str]) -> Vec<HashMap<String, Vec3>> {
    let csv = temp("positions.csv");
    let mut all = vec!["positions", "-q"];
    all.extend(args);
    all.extend(["-o", csv.to_str().unwrap()]);
    ok(&all);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut frames: Vec<HashMap<String, Vec3>> = Vec::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let frame: usize = f[0].parse().unwrap();
        if frames.len() <= frame {
            frames.resize(frame + 1, HashMap::new());
        }
        let n = |i: usize| f[i].parse::<f32>().unwrap();
        frames[frame].insert(f[1].to_string(), Vec3::new(n(2), n(3), n(4)));
    }
    frames
}

fn convert(args: &[&str], output: &Path) -> Gltf {
    let mut all = vec!["convert", "-q"];
    all.extend(args);
    all.extend(["-o", output.to_str().unwrap()]);
    ok(&all);
    Gltf::read(output)
}

/// The worst distance between the file's own node positions and `positions`, over every frame;
/// `bone_ends`: ASF rows name a bone's end, which is the bone's first child node.
fn worst_distance(gltf: &Gltf, expected: &[HashMap<String, Vec3>], bone_ends: bool) -> f32 {
    let index = gltf.node_index();
    let mut worst = 0.0f32;
    for (frame, rows) in expected.iter().enumerate() {
        let world = gltf.world(frame);
        for (name, position) in rows {
            let mut node = index[name.as_str()];
            if bone_ends && name != "root" {
                node = gltf.root.nodes[node].children.as_ref().unwrap()[0].value();
            }
            worst = worst.max(world[node].w_axis.truncate().distance(*position));
        }
    }
    worst
}

/// The time accessor: one for the whole animation, frame i at i × Frame Time.
fn check_times(gltf: &Gltf, frames: usize, frame_time: f64) {
    let animation = &gltf.root.animations[0];
    let input = animation.samplers[0].input;
    assert!(animation.samplers.iter().all(|s| s.input == input));
    let times = gltf.floats(input);
    assert_eq!(times.len(), frames);
    for (i, t) in times.iter().enumerate() {
        assert_eq!(*t, (i as f64 * frame_time) as f32, "time of frame {i}");
    }
}

#[test]
fn every_node_follows_the_motion_as_positions_prints_it() {
    for (file, frames, frame_time) in [
        ("bvh/opencollar_run.bvh", 31, 0.033333),
        ("bvh/makehuman_walk1.bvh", 14, 0.041667),
        ("bvh/bvhpython_test_freebvh.bvh", 69, 0.0333333),
    ] {
        let path = data(file);
        let path = path.to_str().unwrap();
        let gltf = convert(&[path], &temp("take.glb"));
        let expected = positions(&[path]);
        assert_eq!(expected.len(), frames, "{file}");
        // One node per row of `positions`: every joint and End Site, and nothing else.
        assert_eq!(gltf.root.nodes.len(), expected[0].len(), "{file}");
        check_times(&gltf, frames, frame_time);
        let height = {
            let ys = expected[0].values().map(|p| p.y);
            ys.clone().fold(f32::MIN, f32::max) - ys.fold(f32::MAX, f32::min)
        };
        let worst = worst_distance(&gltf, &expected, false);
        assert!(worst < 1e-5 * height.max(1.0), "{file}: {worst}");
        // Rotation keys for every joint with rotation channels (End Sites have none).
        let rotated = gltf.root.animations[0]
            .channels
            .iter()
            .filter(|c| {
                c.target.path
                    == json::validation::Checked::Valid(json::animation::Property::Rotation)
            })
            .count();
        // Counted from the file's text: CHANNELS lines that name a rotation.
        let expected_rotated = std::fs::read_to_string(path)
            .unwrap()
            .split(['\r', '\n'])
            .filter(|l| l.trim_start().starts_with("CHANNELS") && l.contains("rotation"))
            .count();
        assert_eq!(rotated, expected_rotated, "{file}");
    }
}

#[test]
fn asf_amc_takes_export_with_bone_ends_as_child_nodes() {
    let asf = data("asf_amc/heiden_12.asf");
    let amc = data("asf_amc/heiden_12_02_01.amc");
    let args = [asf.to_str().unwrap(), "--motion", amc.to_str().unwrap()];
    let mut trimmed = args.to_vec();
    trimmed.extend(["--frames", "0..40"]);
    let gltf = convert(&trimmed, &temp("heiden.glb"));
    let mut expected = positions(&args);
    expected.truncate(40);
    check_times(&gltf, 40, 1.0 / 120.0);
    let worst = worst_distance(&gltf, &expected, true);
    assert!(worst < 1e-4, "{worst}");
}

#[test]
fn offset_mode_decides_what_position_channels_translate() {
    let path = data("bvh/makehuman_tpose.bvh");
    let path = path.to_str().unwrap();
    let mut distances = Vec::new();
    for mode in ["replace", "add"] {
        let gltf = convert(
            &[path, "--offset-mode", mode],
            &temp(&format!("tpose-{mode}.glb")),
        );
        let expected = positions(&[path, "--offset-mode", mode]);
        let worst = worst_distance(&gltf, &expected, false);
        assert!(worst < 1e-4, "{mode}: {worst}");
        distances.push(gltf);
    }
    // The two modes give different files for this take (position channels on 144 joints).
    let [replace, add] = &distances[..] else {
        unreachable!()
    };
    assert_ne!(replace.bin, add.bin);
}

#[test]
fn gltf_text_holds_the_same_data_inline() {
    let tiny = oracle("inputs/tiny_crlf.bvh");
    let tiny = tiny.to_str().unwrap();
    let glb = convert(&[tiny], &temp("tiny.glb"));
    let text = convert(&[tiny], &temp("tiny.gltf"));
    assert!(!glb.bin.is_empty());
    assert_eq!(glb.bin, text.bin);
    assert_eq!(glb.root.nodes.len(), text.root.nodes.len());
    assert_eq!(glb.root.buffers[0].uri, None);
}

#[test]
fn a_rest_pose_has_nodes_and_no_animation() {
    let file = temp("rest.bvh");
    std::fs::write(
        &file,
        "HIERARCHY\nROOT Hips\n{\n OFFSET 0 1 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n \
         End Site\n {\n  OFFSET 0 2 0\n }\n}\nMOTION\nFrames: 0\nFrame Time: 0.1\n",
    )
    .unwrap();
    let gltf = convert(&[file.to_str().unwrap()], &temp("rest.glb"));
    assert!(gltf.root.animations.is_empty());
    assert!(gltf.root.buffers.is_empty());
    let names: Vec<_> = gltf
        .root
        .nodes
        .iter()
        .map(|n| n.name.clone().unwrap())
        .collect();
    assert_eq!(names, ["Hips", "Hips_End"]);
    assert_eq!(gltf.root.nodes[1].translation, Some([0.0, 2.0, 0.0]));
}

/// With `--skin`: the mesh is bound to every joint node, the inverse bind matrices undo the rest
/// pose, the weights sum to 1, and the middle rings of each bone's cylinder (moved by that bone
/// alone) stay centred on the bone as the file's own skinning moves them.
#[test]
fn skin_is_bound_to_the_joints_and_follows_them() {
    let path = data("bvh/opencollar_run.bvh");
    let path = path.to_str().unwrap();
    let gltf = convert(&[path, "--skin"], &temp("skin.glb"));
    let expected = positions(&[path]);
    let joints = gltf.root.nodes.len() - 1;
    assert_eq!(expected[0].len(), joints);
    let skin = &gltf.root.skins[0];
    assert_eq!(skin.joints.len(), joints);
    let mesh_node = gltf.root.nodes.last().unwrap();
    assert_eq!(mesh_node.skin, Some(json::Index::new(0)));
    assert!(
        gltf.root.scenes[0]
            .nodes
            .contains(&json::Index::new(joints as u32))
    );
    let inverse = gltf.floats(skin.inverse_bind_matrices.unwrap());

    // The rest pose: nodes' translations only.
    let parents = gltf.parents();
    let mut rest: Vec<Vec3> = Vec::new();
    for (index, node) in gltf.root.nodes[..joints].iter().enumerate() {
        let offset = Vec3::from_array(node.translation.unwrap());
        rest.push(parents[index].map_or(offset, |p| rest[p] + offset));
    }
    for (joint, position) in rest.iter().enumerate() {
        let inverse = Mat4::from_cols_slice(&inverse[joint * 16..joint * 16 + 16]);
        let back = inverse.transform_point3(*position);
        assert!(back.length() < 1e-3, "joint {joint}: {back}");
    }

    let primitive = &gltf.root.meshes[0].primitives[0];
    let attribute = |semantic: json::mesh::Semantic| {
        primitive.attributes[&json::validation::Checked::Valid(semantic)]
    };
    let vertices = gltf.floats(attribute(json::mesh::Semantic::Positions));
    let weights = gltf.floats(attribute(json::mesh::Semantic::Weights(0)));
    let (joint_bytes, count) = gltf.accessor_bytes(attribute(json::mesh::Semantic::Joints(0)));
    assert_eq!(vertices.len(), count * 3);
    let bones: Vec<usize> = joint_bytes
        .chunks_exact(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]) as usize)
        .collect();
    for w in weights.chunks_exact(4) {
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    }

    // Bones with a length: one cylinder each, 7 rings of 10, in joint then child order.
    let (lo, hi) = rest
        .iter()
        .fold((Vec3::MAX, Vec3::MIN), |(l, h), p| (l.min(*p), h.max(*p)));
    let size = (hi - lo).max_element().max(1e-3);
    let mut cylinders = Vec::new();
    for (joint, node) in gltf.root.nodes[..joints].iter().enumerate() {
        for child in node.children.iter().flatten() {
            if rest[joint].distance(rest[child.value()]) >= size * 1e-4 {
                cylinders.push((joint, child.value()));
            }
        }
    }
    assert_eq!(count, cylinders.len() * 70);

    let names: Vec<String> = gltf
        .root
        .nodes
        .iter()
        .map(|n| n.name.clone().unwrap())
        .collect();
    let mut worst = 0.0f32;
    for frame in [0, 15, 30] {
        let world = gltf.world(frame);
        let skinning: Vec<Mat4> = (0..joints)
            .map(|j| world[j] * Mat4::from_cols_slice(&inverse[j * 16..j * 16 + 16]))
            .collect();
        let skinned = |v: usize| -> Vec3 {
            let p = Vec3::from_slice(&vertices[v * 3..v * 3 + 3]);
            (0..4)
                .map(|k| weights[v * 4 + k] * skinning[bones[v * 4 + k]].transform_point3(p))
                .sum()
        };
        for (n, &(joint, child)) in cylinders.iter().enumerate() {
            let (a, b) = (
                expected[frame][&names[joint]],
                expected[frame][&names[child]],
            );
            for ring in 2..=4 {
                let first = n * 70 + ring * 10;
                let centre: Vec3 = (first..first + 10).map(skinned).sum::<Vec3>() / 10.0;
                worst = worst.max(centre.distance(a.lerp(b, ring as f32 / 6.0)));
            }
        }
    }
    assert!(worst < 1e-3, "{worst}");
}

#[test]
fn skin_needs_a_gltf_output() {
    let out = bvhview(&[
        "convert",
        oracle("inputs/tiny_crlf.bvh").to_str().unwrap(),
        "--skin",
        "-o",
        temp("x.bvh").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "bvhview: --skin needs a glTF output (.glb or .gltf); a BVH file has no mesh\n"
    );
}

/// BVH allows `Frame Time: 0`; glTF's keyframe times must rise, so such a take is refused with
/// the option that fixes it, nothing is written, and with `--frame-time` it converts. One frame
/// needs no rate.
#[test]
fn a_zero_frame_time_is_refused_until_given() {
    let file = temp("still.bvh");
    let text = |frames: usize| {
        format!(
            "HIERARCHY\nROOT Hips\n{{\n OFFSET 0 1 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n \
             End Site\n {{\n  OFFSET 0 2 0\n }}\n}}\nMOTION\nFrames: {frames}\nFrame Time: 0\n{}",
            "0 0 0\n".repeat(frames)
        )
    };
    std::fs::write(&file, text(3)).unwrap();
    let output = temp("still.glb");
    let out = bvhview(&[
        "convert",
        file.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "bvhview: cannot write glTF: with a frame time of 0 s frames 0 and 1 fall at the same \
         time (0 s); give the take its rate with --frame-time SECONDS\n"
    );
    assert!(!output.exists());
    let gltf = convert(&[file.to_str().unwrap(), "--frame-time", "0.04"], &output);
    check_times(&gltf, 3, 0.04);
    std::fs::write(&file, text(1)).unwrap();
    let gltf = convert(&[file.to_str().unwrap()], &temp("one.glb"));
    check_times(&gltf, 1, 0.0);
}

/// A take of 0 frames converted to glTF (no animation, no skin) was refused by
/// `bvhview info` ("no skeleton"): bvhview could not read back its own output. A file of bare
/// nodes is its tree: the same joints and End Sites, at the same rest offsets.
#[test]
fn a_take_of_no_frames_converts_to_gltf_and_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/edge/frames_zero.bvh");
    let source = source.to_str().unwrap();
    for name in ["z.glb", "z.gltf"] {
        let out = dir.path().join(name);
        let out = out.to_str().unwrap();
        let made = bvhview(&["convert", source, "-q", "-o", out]);
        assert!(
            made.status.success(),
            "{}",
            String::from_utf8_lossy(&made.stderr)
        );
        let info = bvhview(&["info", out]);
        assert!(
            info.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&info.stderr)
        );
        let tree = |path: &str| {
            let run = bvhview(&["positions", path]);
            assert!(
                run.status.success(),
                "{}",
                String::from_utf8_lossy(&run.stderr)
            );
            String::from_utf8(run.stdout).unwrap()
        };
        let (want, got) = (tree(source), tree(out));
        // The same points at the same places (names and numbers as the CSV writes them).
        assert_eq!(got.lines().count(), want.lines().count(), "{got}\n{want}");
        assert_eq!(got.lines().nth(1), want.lines().nth(1), "{got}\n{want}");
    }
}

/// Two nodes of one name were kept so, and the BVH written had two joints of one
/// name. The later one is read as `name.001`, as Blender names it, and `info` says so.
#[test]
fn two_nodes_of_one_name_are_made_unique_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("twins.gltf");
    std::fs::write(
        &file,
        r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[
            {"name":"root","children":[1,2]},
            {"name":"arm","translation":[1,0,0],"children":[3]},
            {"name":"arm","translation":[-1,0,0],"children":[4]},
            {"name":"hand","translation":[1,0,0]},
            {"name":"hand","translation":[-1,0,0]}]}"#,
    )
    .unwrap();
    let path = file.to_str().unwrap();
    let info = bvhview(&["info", path]);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    assert!(text.contains("'arm.001'"), "{text}");
    let out = dir.path().join("twins.bvh");
    let made = bvhview(&["convert", path, "-q", "-o", out.to_str().unwrap()]);
    assert!(
        made.status.success(),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
    let bvh = std::fs::read_to_string(&out).unwrap();
    assert_eq!(
        bvh.matches("JOINT arm\n").count() + bvh.matches("JOINT arm\r\n").count(),
        1,
        "{bvh}"
    );
    assert!(bvh.contains("JOINT arm.001"), "{bvh}");
}

/// A child turned exactly 90° about the middle axis of ZYX (its 32-bit quaternion a
/// hair off length 1) read as `180 89.99999 180` and stood 25° from where the file has it. The
/// one exact split (src/euler.rs) keeps it in place, at the lock and beside it.
#[test]
fn a_joint_at_the_gimbal_lock_stays_where_the_file_has_it() {
    use bvhview::model::pose::{OffsetMode, world_positions};
    let dir = tempfile::tempdir().unwrap();
    for middle in [90.0f32, -90.0, 89.99] {
        let q =
            Quat::from_rotation_z(25f32.to_radians()) * Quat::from_rotation_y(middle.to_radians());
        let file = dir.path().join("lock.gltf");
        std::fs::write(
            &file,
            format!(
                r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[
                {{"name":"root","children":[1]}},
                {{"name":"turned","rotation":[{},{},{},{}],"children":[2]}},
                {{"name":"tip","translation":[0,0,1]}}]}}"#,
                q.x, q.y, q.z, q.w
            ),
        )
        .unwrap();
        let take = crate::common::load_take(&file, None, None).unwrap();
        let points = world_positions(&take.skeleton, take.motion.frame(0), OffsetMode::Replace);
        let tip = take
            .skeleton
            .joints
            .iter()
            .position(|j| j.end_site)
            .unwrap();
        let want = q * Vec3::Z;
        assert!(
            (points[tip] - want).length() < 1e-5,
            "{middle}°: the tip at {} instead of {want}",
            points[tip]
        );
    }
}

/// glTF is +Y up by its specification: a figure lying along z (a four-legged animal's length)
/// is read standing along y, never guessed Z up from its spread (the fox stood on its tail).
#[test]
fn a_gltf_figure_is_read_y_up_whatever_its_spread() {
    let path = temp("lying_along_z.gltf");
    std::fs::write(
        &path,
        r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
        "nodes":[{"name":"hips","children":[1,3]},
                 {"name":"spine","translation":[0,0.1,40],"children":[2]},
                 {"name":"head","translation":[0,0,30]},
                 {"name":"tail","translation":[0,0,-50]}]}"#,
    )
    .unwrap();
    let info = ok(&["info", path.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&info.stdout);
    let up = text.lines().find(|l| l.starts_with("up axis:")).unwrap();
    assert_eq!(
        up.split_whitespace().collect::<Vec<_>>().join(" "),
        "up axis: y (stated: the file states its axes)"
    );
    // A BVH of the same figure states nothing: its spread decides.
    let bvh = temp("lying_along_z.bvh");
    ok(&[
        "convert",
        path.to_str().unwrap(),
        "-o",
        bvh.to_str().unwrap(),
    ]);
    let info = ok(&["info", bvh.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(text.contains("up axis:          z (sure"), "{text}");
}
