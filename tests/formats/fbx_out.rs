//! FBX out, read back by bvhview's own reader (ufbx): every take of the repository's corpus
//! written and read again, every joint where it was on every frame; written again, the same
//! bytes; and the exact reading of a plain take equal to the baked one.

use crate::common::{data, files_in, shared_data};
use bvhview::Take;
use bvhview::model::pose::{Up, world_positions};
use std::path::Path;

/// Every joint of `source` (by the name `positions` gives it) against the joint of that name
/// read back from its FBX, on every frame, in metres (each take in the units its stance reads):
/// the largest distance over the figure's height.
fn worst_error(source: &Take, back: &Take) -> (f32, String) {
    let stance = source.stance(source.offset_mode);
    let metres = stance.units.metres;
    let back_metres = back.stance(back.offset_mode).units.metres;
    let names: Vec<String> = (0..source.skeleton.joints.len())
        .map(|i| bvhview::model::skeleton::export_name(&source.skeleton, i))
        .collect();
    let back_names: Vec<String> = (0..back.skeleton.joints.len())
        .map(|i| bvhview::model::skeleton::export_name(&back.skeleton, i))
        .collect();
    let height = (stance.height * metres).max(1e-6);
    let frames = source.motion.frame_count().max(1);
    assert_eq!(back.motion.frame_count().max(1), frames, "{}", source.name);
    let (mut worst, mut at) = (0.0f32, String::new());
    for f in 0..frames {
        let row = |take: &Take| {
            if take.motion.frame_count() == 0 {
                Vec::new()
            } else {
                take.motion.frame(f).to_vec()
            }
        };
        let want = world_positions(&source.skeleton, &row(source), source.offset_mode);
        let got = world_positions(&back.skeleton, &row(back), back.offset_mode);
        // The same joints in the same order (End Sites of one joint share their name).
        assert_eq!(names, back_names, "{}", source.name);
        for (i, name) in names.iter().enumerate() {
            let j = i;
            let mut p = want[i] * metres;
            if stance.up == Up::Z {
                p = glam::Vec3::new(p.x, p.z, -p.y);
            }
            let got = got[j] * back_metres;
            let error = (p - got).length() / height;
            if error > worst {
                worst = error;
                at = format!("frame {f}, {name}: {p} vs {got}");
            }
        }
    }
    (worst, at)
}

fn round_trip(path: &Path, motion: Option<&Path>) {
    let mut options = bvhview::OpenOptions::new();
    if let Some(motion) = motion {
        options = options.motion(motion);
    }
    let source = Take::open_with(path, &options).unwrap();
    let written = source.fbx().unwrap();
    let folder = tempfile::tempdir().unwrap();
    let out = folder.path().join("out.fbx");
    std::fs::write(&out, &written.bytes).unwrap();
    let back = Take::open(&out).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (worst, at) = worst_error(&source, &back);
    assert!(
        worst <= 1e-5,
        "{}: {worst:e} of the height at {at}",
        path.display()
    );
}

#[test]
fn every_bvh_take_reads_back_where_it_was() {
    for path in files_in(&data("bvh"), "bvh") {
        round_trip(&path, None);
    }
}

#[test]
fn asf_amc_fbx_and_gltf_takes_read_back_where_they_were() {
    for amc in files_in(&data("asf_amc"), "amc") {
        round_trip(&crate::common::asf_of(&amc), Some(&amc));
    }
    for path in files_in(&data("fbx"), "fbx") {
        round_trip(&path, None);
    }
    #[cfg(feature = "gltf")]
    for path in files_in(&data("gltf"), "glb") {
        round_trip(&path, None);
    }
}

/// `path` (with `motion`, an ASF's AMC) written as FBX, read back and written again: the same
/// bytes. The take read back is the file's own channels in its own units (stated: centimetres),
/// and every joint of it is, on every frame, where the baked reading (every frame evaluated by
/// ufbx, in metres, split into 32-bit ZYX channels) puts it, within 1e-5 of the figure's height
/// (the readers' figure: the baked channels carry their split's 32-bit rounding).
fn written_twice(path: &Path, motion: Option<&Path>) {
    let mut options = bvhview::OpenOptions::new();
    if let Some(motion) = motion {
        options = options.motion(motion);
    }
    let source = Take::open_with(path, &options).unwrap();
    let first = source.fbx().unwrap().bytes;
    let fbx = bvhview::OpenOptions::new().format(bvhview::take::Format::Fbx);
    let back = fbx.open_bytes(&first, "first.fbx").unwrap();
    let shown = path.display();
    let units = back.stance(back.offset_mode).units;
    assert_eq!(
        (back.stated_units.map(|u| u.name), units.name),
        (Some("centimetres"), "centimetres"),
        "{shown}: read back exactly, in the file's units"
    );
    let second = back.fbx().unwrap().bytes;
    if first != second {
        let at = first.iter().zip(&second).position(|(a, b)| a != b);
        panic!(
            "{shown}: written again, {} bytes against {}, first different at byte {at:?}",
            second.len(),
            first.len()
        );
    }
    let baked =
        bvhview::fbx::read::load_bytes_baked(&first, "first.fbx", &bvhview::OpenOptions::new())
            .unwrap();
    let height = back.stance(back.offset_mode).height * units.metres;
    let frames = back.motion.frame_count();
    assert_eq!(baked.motion.frame_count(), frames, "{shown}");
    let mut worst = 0.0f32;
    for f in 0..frames {
        let exact = world_positions(&back.skeleton, back.motion.frame(f), back.offset_mode);
        let mode = bvhview::model::pose::OffsetMode::Replace;
        let evaluated = world_positions(&baked.skeleton, baked.motion.frame(f), mode);
        assert_eq!(exact.len(), evaluated.len(), "{shown}");
        for (p, q) in exact.iter().zip(&evaluated) {
            worst = worst.max((*p * units.metres - *q).length() / height);
        }
    }
    assert!(
        worst <= 1e-5,
        "{shown}: read exactly and baked, {worst:e} of the height apart"
    );
}

#[test]
fn every_take_written_read_and_written_again_gives_the_same_bytes() {
    for path in files_in(&data("bvh"), "bvh") {
        written_twice(&path, None);
    }
    for amc in files_in(&data("asf_amc"), "amc") {
        written_twice(&crate::common::asf_of(&amc), Some(&amc));
    }
    for path in files_in(&data("fbx"), "fbx") {
        written_twice(&path, None);
    }
    #[cfg(feature = "gltf")]
    for path in files_in(&data("gltf"), "glb") {
        written_twice(&path, None);
    }
}

/// Blender's exports (each bone's rest orientation in its `Lcl Rotation`, pre-rotations in some
/// ufbx files) are not plain: they are baked (in metres, their units guessed from the figure as
/// before), every joint in ZYX channels.
#[test]
fn a_take_that_is_not_plain_is_baked() {
    for path in [
        data("fbx/bvh11_131_01.fbx"),
        data("fbx/ufbx/maya_human_ik_7400_binary.fbx"),
    ] {
        let take = Take::open(&path).unwrap();
        assert_eq!(take.stated_units, None, "{}", path.display());
        let orders = take.skeleton.joints.iter().filter_map(|j| j.rotation_order);
        assert!(orders.into_iter().all(|o| o == bvhview::RotationOrder::Zyx));
    }
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_whole_corpus_take_written_read_and_written_again_gives_the_same_bytes() {
    for path in files_in(&shared_data("bvh"), "bvh") {
        written_twice(&path, None);
    }
    for amc in files_in(&shared_data("asf_amc"), "amc") {
        written_twice(&crate::common::asf_of(&amc), Some(&amc));
    }
}

/// Every vertex of `character`'s mesh skinned by `take` (on its skeleton), every frame.
fn skinned(character: &bvhview::character::Character, take: &Take) -> Vec<Vec<glam::Vec3>> {
    (0..take.motion.frame_count().max(1))
        .map(|f| {
            let row = if take.motion.frame_count() == 0 {
                &[][..]
            } else {
                take.motion.frame(f)
            };
            character.vertices(&take.skeleton, row)
        })
        .collect()
}

/// A character's mesh written into FBX (skin, clusters, every influence) and read back: every
/// vertex where bvhview's own skinning put it, on every frame, within 1e-5 of the mesh's
/// height; the file's own take as it is (`convert CHAR -o copy.fbx`), and a walk put on it.
#[test]
fn a_character_reads_back_with_every_vertex_where_it_was() {
    use bvhview::character::Character;
    let mut characters = vec![
        data("characters/capsule_mixamo.fbx"),
        data("characters/maya_kenney_character_7700_binary.fbx"),
    ];
    if cfg!(feature = "gltf") {
        characters.push(data("characters/capsule_mixamo.glb"));
    }
    let walk = Take::open(data("bvh/bvh11_131_01.bvh"))
        .unwrap()
        .trim(0..12);
    let folder = tempfile::tempdir().unwrap();
    for path in characters {
        let character = Character::open(&path).unwrap();
        let (dressed, _) = character.dress(&walk, &[], Default::default(), 1).unwrap();
        for (label, take) in [("own take", &character.take), ("walk", &dressed)] {
            let out = folder.path().join("character.fbx");
            std::fs::write(&out, take.fbx_character(&character.mesh).unwrap().bytes).unwrap();
            let back = Character::open(&out).unwrap();
            assert_eq!(back.mesh.vertex_count(), character.mesh.vertex_count());
            assert_eq!(back.mesh.triangles, character.mesh.triangles);
            let (want, got) = (skinned(&character, take), skinned(&back, &back.take));
            assert_eq!(want.len(), got.len(), "{}: {label}", path.display());
            let rest = &want[0];
            let height = rest.iter().map(|p| p.y).fold(f32::MIN, f32::max)
                - rest.iter().map(|p| p.y).fold(f32::MAX, f32::min);
            let worst = want
                .iter()
                .flatten()
                .zip(got.iter().flatten())
                .map(|(a, b)| a.distance(*b))
                .fold(0.0f32, f32::max);
            assert!(
                worst <= 1e-5 * height,
                "{} ({label}): a vertex {worst} off, height {height}",
                path.display()
            );
        }
    }
}

/// A rate bvhview could not read back from FBX (slower than a frame every 100 s, faster than
/// 1000 a second) is refused before a byte is written, with the limit named.
#[test]
fn a_rate_the_reader_refuses_is_not_written() {
    for (frame_time, what, limit, found) in [
        ("1110", "seconds a frame", 100, 1110),
        ("0.0001", "frames per second", 1000, 10_000),
    ] {
        let text = format!(
            "HIERARCHY\nROOT Hips\n{{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation \
             Yrotation\n End Site\n {{\n OFFSET 0 10 0\n }}\n}}\nMOTION\nFrames: 2\nFrame Time: \
             {frame_time}\n0 0 0\n10 0 0\n"
        );
        let take = bvhview::OpenOptions::new()
            .open_bytes(text.as_bytes(), "slow.bvh")
            .unwrap();
        match take.fbx() {
            Err(bvhview::Error::Limit {
                what: w,
                limit: l,
                found: f,
                ..
            }) => assert_eq!((w, l, f), (what, limit, found), "{frame_time}"),
            other => panic!("{frame_time}: {other:?}"),
        }
    }
}
