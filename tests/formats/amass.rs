//! AMASS's `.npz` files (SMPL, SMPL-H and SMPL-X parameters) as takes: the synthetic files of
//! `tests/data/smpl` (made by `scripts/make_amass_samples.py` in AMASS's layout; AMASS's own
//! motion is licensed), each joint's rotation the axis-angle's exactly, and hostile archives
//! refused by name.

use crate::common::data;
use crate::common::npz::{f64s, npy, npz};
use bvhview::Take;
use bvhview::smpl::{ModelType, amass, npz};
use glam::{DQuat, DVec3};

/// Every joint of every frame: the channels' rotation is the file's axis-angle (the root's
/// turned from Z up to Y up), within what 32-bit channels hold; the pelvis is where `trans`
/// puts it, turned.
#[test]
fn each_axis_angle_becomes_its_joints_rotation() {
    for (file, model, fps) in [
        ("smpl/amass_smplh_walk.npz", ModelType::Smplh, 120.0),
        ("smpl/amass_smplx_walk.npz", ModelType::Smplx, 30.0),
        ("smpl/smpl_walk_compressed.npz", ModelType::Smpl, 60.0),
    ] {
        let path = data(file);
        let take = Take::open(&path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let params = amass::read(&npz::read(&bytes, file).unwrap(), file, None).unwrap();
        assert_eq!(params.model, model, "{file}");
        assert_eq!(take.frame_count(), 60, "{file}");
        assert!((take.fps() - fps).abs() < 1e-9, "{file}: {}", take.fps());
        assert_eq!(take.stated_units.map(|u| u.metres), Some(1.0));
        let names = model.joint_names();
        let joints = &take.skeleton.joints;
        let moving: Vec<_> = joints.iter().filter(|j| !j.end_site).collect();
        assert_eq!(moving.len(), model.joint_count(), "{file}");
        let turn = DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2);
        let width = model.pose_width();
        let mut worst = 0.0f64;
        for f in 0..take.frame_count() {
            let row = take.motion.frame(f);
            for joint in moving.iter() {
                let k = names.iter().position(|n| *n == joint.name).unwrap();
                let axis_angle = &params.poses[f * width + 3 * k..f * width + 3 * k + 3];
                let mut want = DQuat::from_scaled_axis(DVec3::from_slice(axis_angle));
                if joint.parent.is_none() {
                    want = turn * want;
                    let place = turn * DVec3::from_slice(&params.trans[3 * f..3 * f + 3]);
                    let got = DVec3::from_slice(
                        &joint.values(row)[..3]
                            .iter()
                            .map(|&v| f64::from(v))
                            .collect::<Vec<_>>(),
                    );
                    assert!((got - place).abs().max_element() < 1e-6, "{file} frame {f}");
                }
                let got = bvhview::model::pose::local_rotation_f64(joint, joint.values(row));
                worst = worst.max(1.0 - got.dot(want).abs());
            }
        }
        // 32-bit degrees: about 1e-7 of a degree each.
        assert!(worst < 1e-12, "{file}: {worst:e}");
    }
}

/// `info` says what the file is and what it was read on.
#[test]
fn a_file_says_its_model_and_the_figure_it_was_read_on() {
    let take = Take::open(data("smpl/amass_smplx_walk.npz")).unwrap();
    let said: Vec<String> = take.warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        said.iter().any(|w| w
            .starts_with("SMPL-X parameters read on bvhview's built-in smplx55 figure")
            && w.ends_with("AMASS's Z up turned to Y up")),
        "{said:?}"
    );
    let stance = take.stance(take.offset_mode);
    assert_eq!(stance.up, bvhview::model::pose::Up::Y);
    assert!((1.5..1.9).contains(&stance.height), "{}", stance.height);
}

/// An archive's members: each one's name and bytes.
type Members = Vec<(&'static str, Vec<u8>)>;

/// A small valid SMPL take: two frames of poses, trans and a rate.
fn smpl_members() -> Members {
    vec![
        ("poses.npy", npy("<f8", &[2, 72], &f64s(&[0.1; 144]))),
        ("trans.npy", npy("<f8", &[2, 3], &f64s(&[0.0; 6]))),
        ("mocap_framerate.npy", npy("<f8", &[], &f64s(&[30.0]))),
    ]
}

fn opened(bytes: &[u8]) -> Result<Take, String> {
    bvhview::OpenOptions::new()
        .format(bvhview::take::Format::Amass)
        .open_bytes(bytes, "hostile.npz")
        .map_err(|e| e.to_string())
}

#[test]
fn a_small_archive_made_here_reads() {
    let take = opened(&npz(&smpl_members(), false)).unwrap();
    assert_eq!(take.frame_count(), 2);
    let take = opened(&npz(&smpl_members(), true)).unwrap();
    assert_eq!(take.frame_count(), 2);
}

/// Each hostile archive gets one exact refusal that names what is wrong.
#[test]
fn hostile_archives_are_refused_by_name() {
    let with = |change: &dyn Fn(&mut Members)| {
        let mut members = smpl_members();
        change(&mut members);
        opened(&npz(&members, false)).unwrap_err()
    };
    let cases: Vec<(String, &str)> = vec![
        (
            with(&|m| m[0] = ("poses.npy", npy("|O", &[2], b"\x80\x04pickle"))),
            "'poses' is an array of dtype |O (an object array is a pickle, which bvhview never loads)",
        ),
        (
            with(&|m| m.push(("notes.txt", b"hello".to_vec()))),
            "member 'notes.txt': not an .npy array",
        ),
        (
            with(&|m| m.push(("deep/poses.npy", npy("<f8", &[1], &f64s(&[1.0]))))),
            "member 'deep/poses.npy': a folder, a link or a path",
        ),
        (
            with(&|m| {
                m[0] = (
                    "poses.npy",
                    npy("<f8", &[1_000_000, 72], &f64s(&[0.0; 144])),
                )
            }),
            "shape [1000000, 72] of 8-byte values: more than the file's 1152 bytes of data hold",
        ),
        (
            with(&|m| m[0] = ("poses.npy", npy("<f8", &[2, 70], &f64s(&[0.0; 140])))),
            "'poses' has shape [2, 70]; expected frames × 72 (SMPL), 156 (SMPL-H) or 165 (SMPL-X)",
        ),
        (
            with(&|m| {
                m.remove(0);
            }),
            "no poses: an AMASS file holds 'poses'",
        ),
        (
            with(&|m| {
                let mut values = vec![0.1; 144];
                values[80] = f64::NAN;
                m[0] = ("poses.npy", npy("<f8", &[2, 72], &f64s(&values)));
            }),
            "'poses', frame 1: a value that is not finite",
        ),
        (
            with(&|m| {
                m.remove(2);
            }),
            "no rate ('mocap_framerate' or 'mocap_frame_rate'); give it with frame_time SECONDS",
        ),
        (
            with(&|m| {
                m.push((
                    "surface_model_type.npy",
                    npy(
                        "<U5",
                        &[],
                        &"smplx"
                            .chars()
                            .flat_map(|c| (c as u32).to_le_bytes())
                            .collect::<Vec<u8>>(),
                    ),
                ))
            }),
            "'poses' has 72 values a frame, SMPL's, and surface_model_type says SMPL-X",
        ),
        (
            with(&|m| m[1] = ("trans.npy", npy("<f8", &[3, 3], &f64s(&[0.0; 9])))),
            "'trans' has 3 frames and the poses 2",
        ),
    ];
    for (said, expected) in cases {
        assert!(said.contains(expected), "{said}\n  expected: {expected}");
        assert!(said.starts_with("hostile.npz"), "{said}");
    }
    let not_zip = opened(b"PK\x03\x04 and nothing else").unwrap_err();
    assert!(
        not_zip.contains("not a zip archive bvhview reads"),
        "{not_zip}"
    );
}

/// A member that inflates past what a file of its size is read for is refused before it is
/// inflated (40 MB of zeros deflate to about 40 KB).
#[test]
fn an_archive_that_inflates_past_its_budget_is_refused() {
    let zeros = vec![0u8; 40 << 20];
    let mut members = smpl_members();
    members.push(("bomb.npy", npy("<f8", &[5 << 20], &zeros)));
    let bytes = npz(&members, true);
    assert!(bytes.len() < 200_000, "{}", bytes.len());
    let said = opened(&bytes).unwrap_err();
    assert!(
        said.contains("its members inflate to") && said.contains("refused as damaged or hostile"),
        "{said}"
    );
}

/// An AMASS file read and written again: the same poses and translations (within what the
/// take's 32-bit channels hold), the same rate; SMPL-X's split keys too.
#[test]
fn an_amass_file_read_and_written_gives_the_same_arrays() {
    for file in [
        "smpl/amass_smplh_walk.npz",
        "smpl/amass_smplx_walk.npz",
        "smpl/smpl_walk_compressed.npz",
    ] {
        let path = data(file);
        let before = npz::read(&std::fs::read(&path).unwrap(), file).unwrap();
        let take = Take::open(&path).unwrap();
        let (bytes, said) = take.amass().unwrap();
        assert!(said.is_empty(), "{file}: {said:?}");
        let after = npz::read(&bytes, "after.npz").unwrap();
        let (a, b) = (
            amass::read(&before, file, None).unwrap(),
            amass::read(&after, "after.npz", None).unwrap(),
        );
        assert_eq!((a.model, a.fps), (b.model, b.fps), "{file}");
        let worst = |x: &[f64], y: &[f64]| {
            assert_eq!(x.len(), y.len());
            x.iter()
                .zip(y)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max)
        };
        assert!(
            worst(&a.poses, &b.poses) < 1e-6,
            "{file}: {}",
            worst(&a.poses, &b.poses)
        );
        assert!(worst(&a.trans, &b.trans) < 1e-6, "{file}");
        if a.model == ModelType::Smplx {
            for key in [
                "root_orient",
                "pose_body",
                "pose_hand",
                "pose_jaw",
                "pose_eye",
            ] {
                assert!(after.names().any(|n| n == key), "{key}");
            }
        }
    }
}

/// Any take, retargeted onto a SMPL-family skeleton and written as AMASS's `.npz`, reads back
/// with every joint the model has within 1e-4 of the figure's height of where it was.
#[test]
fn a_take_written_as_amass_reads_back_where_it_was() {
    let walk = Take::open(data("bvh/bvh11_131_01.bvh")).unwrap();
    for target in ["smpl24", "smplh52", "smplx55", "smpl22"] {
        let take = bvhview::retarget::onto(&walk, target).unwrap();
        let (bytes, _) = take.amass().unwrap();
        let back = bvhview::OpenOptions::new()
            .format(bvhview::take::Format::Amass)
            .open_bytes(&bytes, "back.npz")
            .unwrap();
        let stance = take.stance(take.offset_mode);
        let metres = stance.units.metres;
        let height = stance.height * metres;
        let mut worst = 0.0f32;
        for f in (0..take.frame_count()).step_by(7) {
            let want = take.positions(f).unwrap();
            let got = back.positions(f).unwrap();
            for (name, p) in take.point_names().iter().zip(&want) {
                let Some(k) = back.point_names().iter().position(|n| n == name) else {
                    continue;
                };
                worst = worst.max((*p * metres - got[k]).length() / height);
            }
        }
        // The built-in figures share the body's lengths: every joint comes back in place.
        assert!(worst < 1e-4, "{target}: {worst:e} of the height");
    }
}

/// A take on another skeleton is refused, saying how to put it on one; nothing is written.
#[test]
fn a_take_on_another_skeleton_is_not_written_as_amass() {
    let walk = Take::open(data("bvh/bvh11_131_01.bvh")).unwrap();
    let said = walk.amass().unwrap_err().to_string();
    assert!(
        said.contains("an AMASS file is written from a take on a SMPL-family skeleton")
            && said.ends_with("put the take on one first with retarget's onto smplh"),
        "{said}"
    );
    let folder = crate::common::scratch_folder("amass-refused");
    let out = folder.join("walk.npz");
    let run = crate::common::bvhview(&[
        "convert",
        data("bvh/bvh11_131_01.bvh").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("retarget's --onto smplh"));
    assert!(!out.exists());
}

/// A directory that lies about a member's size, or where a member starts, is refused by name:
/// no read past what the archive holds, no panic.
#[test]
fn an_archive_whose_directory_lies_is_refused() {
    let honest = npz(&smpl_members(), true);
    let patched = |field: usize, value: u32| {
        let mut bytes = honest.clone();
        let at = bytes
            .windows(4)
            .position(|w| w == b"PK\x01\x02")
            .expect("a central directory");
        bytes[at + field..at + field + 4].copy_from_slice(&value.to_le_bytes());
        opened(&bytes).unwrap_err()
    };
    // The uncompressed size (offset 24), much larger and smaller than the member; where the
    // member's local header is (offset 42).
    let huge = patched(24, 0x7fff_ffff);
    assert!(huge.contains("its members inflate to 2147483"), "{huge}");
    let small = patched(24, 10);
    assert!(small.contains("member 'poses.npy': damaged"), "{small}");
    let moved = patched(42, 0x00ff_ffff);
    assert!(moved.starts_with("hostile.npz: member 0:"), "{moved}");
}

/// An AMASS file converted to AMASS again keeps its betas and gender through edits that keep
/// its bones (a turn to Z up), and loses them, said, through one that changes them (a scale).
#[test]
fn convert_keeps_the_body_while_the_bones_are_the_files() {
    let folder = crate::common::scratch_folder("convert-body");
    // Its betas are not zero, and it says male.
    let source = data("smpl/amass_smplh_walk.npz");
    let before = amass::read(
        &npz::read(&std::fs::read(&source).unwrap(), "walk").unwrap(),
        "walk",
        None,
    )
    .unwrap();
    for (edit, kept) in [
        (&["--out-up", "z"][..], true),
        (&["--scale", "2"][..], false),
    ] {
        let out = folder.join(format!("{}.npz", edit[0].trim_start_matches('-')));
        let mut args = vec!["convert".to_string(), source.display().to_string()];
        args.extend(edit.iter().map(|s| s.to_string()));
        args.extend(["-o".to_string(), out.display().to_string()]);
        let run = crate::common::bvhview(&args);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let after = amass::read(
            &npz::read(&std::fs::read(&out).unwrap(), "out").unwrap(),
            "out",
            None,
        )
        .unwrap();
        assert_eq!(
            after.betas == before.betas,
            kept,
            "{edit:?}: {:?}",
            after.betas
        );
        assert_eq!(after.gender == before.gender, kept, "{edit:?}");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(
            stderr.contains("betas zero and gender neutral"),
            !kept,
            "{stderr}"
        );
    }
}
