//! `bvhview dataset` and `bvhview::dataset`: the repository's takes compiled into training
//! arrays, read back from the `.npy` files, checked against the loader and FK, merged from
//! pieces, and the command's messages and exit codes.
// Helpers of the tests a build without every feature leaves out.
#![cfg_attr(
    not(all(feature = "window", feature = "fbx", feature = "gltf")),
    allow(dead_code, unused_imports)
)]

use crate::common::bvhview;
use bvhview::dataset::{self, Options, merge, read, store};
use bvhview::model::pose::{self, OffsetMode, RotationKind, Up};
use std::path::{Path, PathBuf};
use std::process::Command;

const DATA: &str = "tests/data";

/// An `.npy` file of ours: its header's dtype and shape, and its data.
struct Npy {
    descr: String,
    shape: Vec<usize>,
    data: Vec<u8>,
}

fn read_npy(path: &Path) -> Npy {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00", "{}", path.display());
    let length = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    assert_eq!((10 + length) % 64, 0, "numpy pads headers to 64 bytes");
    let header = std::str::from_utf8(&bytes[10..10 + length]).unwrap();
    assert!(header.ends_with('\n'));
    let field = |name: &str| {
        let at = header.find(&format!("'{name}': ")).unwrap() + name.len() + 4;
        header[at..].to_string()
    };
    let descr = field("descr")[1..].split('\'').next().unwrap().to_string();
    assert!(field("fortran_order").starts_with("False"));
    let shape = field("shape");
    let shape: Vec<usize> = shape[1..shape.find(')').unwrap()]
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap())
        .collect();
    Npy {
        descr,
        shape,
        data: bytes[10 + length..].to_vec(),
    }
}

impl Npy {
    fn floats(&self) -> Vec<f32> {
        assert_eq!(self.descr, "<f4");
        self.data
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    }
}

fn compile(out: &Path, options: &Options, threads: usize) -> dataset::Summary {
    let items = dataset::takes(Path::new(DATA)).unwrap();
    let takes = dataset::whole_list(Path::new(DATA), &items);
    dataset::compile(
        Path::new(DATA),
        items,
        options,
        threads,
        out,
        takes,
        |_, _, _, _| true,
    )
    .unwrap()
}

/// The repository's takes compiled as `count` pieces cut by [`dataset::piece`] (as a Dask
/// compile cuts them), into `LABEL_K` folders under `dir`.
fn even_pieces(dir: &Path, options: &Options, count: usize, label: &str) -> Vec<PathBuf> {
    let items = dataset::takes(Path::new(DATA)).unwrap();
    (0..count)
        .map(|k| {
            let (run, takes) = dataset::piece(Path::new(DATA), items.clone(), k, count).unwrap();
            let piece = dir.join(format!("{label}_{k}"));
            dataset::compile(
                Path::new(DATA),
                run,
                options,
                1,
                &piece,
                takes,
                |_, _, _, _| true,
            )
            .unwrap();
            piece
        })
        .collect()
}

/// Every file of two dataset folders, byte for byte.
fn same_files(a: &Path, b: &Path) {
    let mut files = Vec::new();
    let mut folders = vec![PathBuf::new()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(a.join(&folder)).unwrap() {
            let entry = entry.unwrap();
            let relative = folder.join(entry.file_name());
            if entry.file_type().unwrap().is_dir() {
                folders.push(relative);
            } else {
                files.push(relative);
            }
        }
    }
    let count = |dir: &Path| walk_count(dir);
    assert_eq!(count(a), count(b), "{} and {}", a.display(), b.display());
    for file in files {
        let (x, y) = (
            std::fs::read(a.join(&file)).unwrap(),
            std::fs::read(b.join(&file)),
        );
        assert!(
            y.as_ref().is_ok_and(|y| *y == x),
            "{} differs",
            file.display()
        );
    }
}

fn walk_count(dir: &Path) -> usize {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            if e.file_type().unwrap().is_dir() {
                walk_count(&e.path())
            } else {
                1
            }
        })
        .sum()
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
#[test]
fn the_repository_compiles_into_groups_whose_arrays_the_manifest_describes() {
    let temp = tempfile::tempdir().unwrap();
    let out = temp.path().join("ds");
    let summary = compile(&out, &Options::default(), 2);
    let manifest = read::read_manifest(&out).unwrap();
    assert_eq!(manifest.clips.len(), summary.clips);
    assert_eq!(manifest.groups.len(), summary.groups);

    // Every take is either a clip or skipped, in path order.
    let items = dataset::takes(Path::new(DATA)).unwrap();
    assert_eq!(manifest.clips.len() + manifest.skipped.len(), items.len());
    let mut clips = manifest.clips.iter();
    let mut skipped = manifest.skipped.iter();
    for item in &items {
        let source = dataset::Source::of(Path::new(DATA), item);
        let loads = crate::common::load_take(&item.path, item.motion.as_deref(), None)
            .is_ok_and(|l| l.motion.frame_count() > 0);
        if loads {
            assert_eq!(clips.next().unwrap().about.source, source);
        } else {
            let entry = skipped.next().unwrap();
            assert_eq!(entry.source, source);
            // A malformed file is named with its line and column.
            if let Err(bvhview::Error::Parse { line, column, .. }) =
                crate::common::load_take(&item.path, None, None)
            {
                // As the manifest keeps it: relative to the folder compiled.
                let at = format!("{}:{line}:{column}: ", source.path);
                assert!(entry.error.starts_with(&at), "{}", entry.error);
            }
        }
    }
    assert_eq!(manifest.skipped.len(), 11, "{:?}", manifest.skipped);
    assert!(
        manifest.skipped[0]
            .error
            .starts_with("bvh_malformed/dali_test-empty.bvh:1:1: expected HIERARCHY")
    );

    for (k, group) in manifest.groups.iter().enumerate() {
        assert_eq!(group.name, format!("group_{k}"));
        let members: Vec<_> = manifest.clips.iter().filter(|c| c.group == k).collect();
        assert_eq!(group.clips, members.len());
        let frames: usize = members.iter().map(|c| c.frames).sum();
        assert_eq!(group.frames, frames);
        let points = group.topology.joints.len();
        let rotated = group.topology.rotated.len();
        let feet = group.topology.feet.len();
        let translated = group.topology.translated.len();
        let expected: [(&str, &str, Vec<usize>); 8] = [
            ("positions", "<f4", vec![frames, points, 3]),
            ("rotations", "<f4", vec![frames, rotated, 6]),
            ("translations", "<f4", vec![frames, translated, 3]),
            ("root_translations", "<f4", vec![frames, 3]),
            ("velocities", "<f4", vec![frames, points, 3]),
            ("foot_contacts", "|u1", vec![frames, feet]),
            ("offsets", "<i8", vec![members.len() + 1]),
            ("rest_offsets", "<f4", vec![members.len(), points, 3]),
        ];
        assert_eq!(group.arrays.len(), expected.len());
        for ((name, descr, shape), entry) in expected.iter().zip(&group.arrays) {
            assert_eq!(entry.name, *name);
            assert_eq!(entry.shape, *shape);
            let npy = read_npy(&out.join(&entry.file));
            assert_eq!(
                (&npy.descr[..], &npy.shape),
                (*descr, shape),
                "{}",
                entry.file
            );
            let size = if *descr == "|u1" {
                1
            } else if *descr == "<i8" {
                8
            } else {
                4
            };
            assert_eq!(npy.data.len(), shape.iter().product::<usize>() * size);
        }
        // Offsets: each clip's start, then the end.
        let offsets = read_npy(&out.join(&group.arrays[6].file));
        let offsets: Vec<i64> = offsets
            .data
            .chunks_exact(8)
            .map(|b| i64::from_le_bytes(b.try_into().unwrap()))
            .collect();
        let starts: Vec<i64> = members.iter().map(|c| c.start as i64).collect();
        assert_eq!(&offsets[..members.len()], &starts[..]);
        assert_eq!(offsets[members.len()], frames as i64);
    }
}

/// Clip `name`'s rows of one array of its group.
fn clip_rows(out: &Path, manifest: &store::Manifest, name: &str, array: &str) -> Vec<f32> {
    let clip = manifest
        .clips
        .iter()
        .find(|c| c.about.source.path.ends_with(name))
        .unwrap_or_else(|| panic!("{name} is a clip"));
    let group = &manifest.groups[clip.group];
    let entry = group.arrays.iter().find(|a| a.name == array).unwrap();
    let npy = read_npy(&out.join(&entry.file));
    let per_row: usize = npy.shape[1..].iter().product();
    npy.floats()[clip.start * per_row..(clip.start + clip.frames) * per_row].to_vec()
}

#[test]
fn positions_are_the_loaders_fk_in_metres_with_y_up() {
    let temp = tempfile::tempdir().unwrap();
    // 24 fps keeps MakeHuman's walk (Z up, decimetres) at its own frames; 30 keeps FreeBVH's
    // (Y up, centimetres).
    for (fps, name, up, metres) in [
        (30.0, "bvhpython_test_freebvh.bvh", Up::Y, 0.01),
        (24.0, "makehuman_walk1.bvh", Up::Z, 0.1),
    ] {
        let out = temp.path().join(format!("at_{fps}"));
        let options = Options {
            fps,
            ..Options::default()
        };
        compile(&out, &options, 1);
        let manifest = read::read_manifest(&out).unwrap();
        let clip = manifest
            .clips
            .iter()
            .find(|c| c.about.source.path.ends_with(name))
            .unwrap();
        assert_eq!(clip.about.up, if up == Up::Z { "z" } else { "y" });
        assert_eq!(clip.about.metres_per_unit, metres);
        let loaded =
            crate::common::load_take(&Path::new(DATA).join("bvh").join(name), None, None).unwrap();
        assert_eq!(clip.frames, loaded.motion.frame_count());
        let positions = clip_rows(&out, &manifest, name, "positions");
        let points = loaded.skeleton.joints.len();
        let mut worst = 0.0f32;
        let mut height = 0.0f32;
        for f in 0..clip.frames {
            let expected = pose::world_positions(
                &loaded.skeleton,
                loaded.motion.frame(f),
                OffsetMode::Replace,
            );
            let (low, high) = expected.iter().fold((f32::MAX, f32::MIN), |(l, h), p| {
                let up_value = if up == Up::Z { p.z } else { p.y };
                (l.min(up_value), h.max(up_value))
            });
            height = height.max((high - low) * metres);
            for (p, point) in expected.iter().enumerate() {
                // Z up turns into Y up: (x, y, z) becomes (x, z, -y).
                let turned = match up {
                    Up::Y => *point,
                    Up::Z => glam::Vec3::new(point.x, point.z, -point.y),
                } * metres;
                let got = &positions[(f * points + p) * 3..][..3];
                worst = worst.max((glam::Vec3::from_slice(got) - turned).abs().max_element());
            }
        }
        assert!(height > 1.4 && height < 2.0, "{name}: {height} m tall");
        assert!(worst <= 1e-5 * height, "{name}: {worst} m off");

        // The clip's OFFSETs, turned and scaled the same way, and each joint's channel order.
        let group = &manifest.groups[clip.group];
        let index = manifest.clips[..]
            .iter()
            .filter(|c| c.group == clip.group)
            .position(|c| c == clip)
            .unwrap();
        let entry = group
            .arrays
            .iter()
            .find(|a| a.name == "rest_offsets")
            .unwrap();
        let rest = read_npy(&out.join(&entry.file)).floats();
        for (p, joint) in loaded.skeleton.joints.iter().enumerate() {
            let o = joint.offset;
            let turned = match up {
                Up::Y => o,
                Up::Z => glam::Vec3::new(o.x, o.z, -o.y),
            } * metres;
            let got = glam::Vec3::from_slice(&rest[(index * points + p) * 3..]);
            assert!((got - turned).abs().max_element() <= 1e-6, "{name} {p}");
        }
        for (slot, &joint) in group.topology.rotated.iter().enumerate() {
            let letters: String = loaded.skeleton.joints[joint as usize]
                .channels
                .iter()
                .filter(|c| c.is_rotation())
                .map(|c| c.name().chars().next().unwrap())
                .collect();
            assert_eq!(group.topology.rotation_orders[slot], letters);
        }
    }
}

#[test]
fn resampling_velocities_contacts_and_root_relative_frames_follow_their_definitions() {
    let temp = tempfile::tempdir().unwrap();
    let plain = temp.path().join("plain");
    compile(&plain, &Options::default(), 2);
    let manifest = read::read_manifest(&plain).unwrap();
    for clip in &manifest.clips {
        // Frames at i / 30 s from the first to the last source frame.
        let span = (clip.about.source_frames - 1) as f64 * clip.about.source_frame_time;
        let expected = if (clip.about.source_frame_time * 30.0 - 1.0).abs() < 1e-4
            || clip.about.source_frames < 2
        {
            clip.about.source_frames
        } else {
            (span * 30.0 + 1e-3).floor() as usize + 1
        };
        assert_eq!(clip.frames, expected, "{}", clip.about.source.path);
    }
    let name = "assimp_01_01.bvh";
    let positions = clip_rows(&plain, &manifest, name, "positions");
    let velocities = clip_rows(&plain, &manifest, name, "velocities");
    let clip = manifest
        .clips
        .iter()
        .find(|c| c.about.source.path.ends_with(name))
        .unwrap();
    let group = &manifest.groups[clip.group];
    let points = group.topology.joints.len();
    let at = |v: &[f32], f: usize, p: usize| glam::Vec3::from_slice(&v[(f * points + p) * 3..]);
    let last = clip.frames - 1;
    for p in 0..points {
        for f in [0, 1, clip.frames / 2, last] {
            let (a, b) = (f.saturating_sub(1), (f + 1).min(last));
            let expected = (at(&positions, b, p) - at(&positions, a, p)) * (30.0 / (b - a) as f32);
            assert!(
                (at(&velocities, f, p) - expected).length() < 1e-4,
                "{p} {f}"
            );
        }
    }
    // Contacts: low (within 5 cm of where the point rests on the ground the feet stand on
    // within a second, 30 frames, either way) and slow (under 0.5 m/s).
    let contacts = {
        let entry = group
            .arrays
            .iter()
            .find(|a| a.name == "foot_contacts")
            .unwrap();
        let npy = read_npy(&plain.join(&entry.file));
        let feet = group.topology.feet.len();
        npy.data[clip.start * feet..(clip.start + clip.frames) * feet].to_vec()
    };
    let feet = &group.topology.feet;
    let names: Vec<&str> = feet
        .iter()
        .map(|&i| group.topology.joints[i as usize].as_str())
        .collect();
    assert_eq!(
        names,
        // The reading of the body: each leg's ankle and toe joint.
        ["LeftFoot", "LeftToeBase", "RightFoot", "RightToeBase"]
    );
    // The ground under a frame: the lowest any foot point comes within 30 frames either way;
    // where each point rests on it: its least height above it over the clip, at most 12 cm.
    let lowest_foot = |g: usize| {
        feet.iter()
            .map(|&p| at(&positions, g, p as usize).y)
            .fold(f32::MAX, f32::min)
    };
    let ground = |f: usize| {
        (f.saturating_sub(30)..=(f + 30).min(last))
            .map(lowest_foot)
            .fold(f32::MAX, f32::min)
    };
    let mut touching = 0;
    for (k, &foot) in feet.iter().enumerate() {
        let height = |f: usize| at(&positions, f, foot as usize).y - ground(f);
        let rests = (0..clip.frames)
            .map(height)
            .fold(f32::MAX, f32::min)
            .min(0.12);
        for f in 0..clip.frames {
            let low = height(f) - rests <= 0.05;
            let slow = at(&velocities, f, foot as usize).length() < 0.5;
            assert_eq!(
                contacts[f * feet.len() + k],
                u8::from(low && slow),
                "{k} {f}"
            );
            touching += usize::from(low && slow);
        }
    }
    // A walk: feet down a good part of the time, not all of it.
    let share = touching as f64 / (clip.frames * feet.len()) as f64;
    assert!(share > 0.2 && share < 0.9, "{share}");

    // Root-relative: x and z minus the root's, height kept; root translations unchanged.
    let relative = temp.path().join("relative");
    compile(
        &relative,
        &Options {
            root_relative: true,
            ..Options::default()
        },
        2,
    );
    let manifest = read::read_manifest(&relative).unwrap();
    let moved = clip_rows(&relative, &manifest, name, "positions");
    let roots = clip_rows(&relative, &manifest, name, "root_translations");
    for f in [0, last] {
        let root = glam::Vec3::from_slice(&roots[f * 3..]);
        assert_eq!(root, at(&positions, f, 0));
        for p in 0..points {
            let expected = at(&positions, f, p) - glam::Vec3::new(root.x, 0.0, root.z);
            assert_eq!(at(&moved, f, p), expected);
        }
    }
}

#[test]
fn threads_and_pieces_merged_give_the_same_bytes_and_rotation_kinds_their_widths() {
    let temp = tempfile::tempdir().unwrap();
    let whole = temp.path().join("whole");
    compile(&whole, &Options::default(), 2);
    let one_thread = temp.path().join("one_thread");
    compile(&one_thread, &Options::default(), 1);
    same_files(&whole, &one_thread);

    let items = dataset::takes(Path::new(DATA)).unwrap();
    let whole_list = dataset::whole_list(Path::new(DATA), &items);
    let mut pieces = Vec::new();
    for (k, range) in [0..7, 7..8, 8..8, 8..items.len()].into_iter().enumerate() {
        let piece = temp.path().join(format!("piece_{k}"));
        let takes = store::Takes {
            first: range.start,
            count: range.len(),
            ..whole_list.clone()
        };
        dataset::compile(
            Path::new(DATA),
            items[range].to_vec(),
            &Options::default(),
            1,
            &piece,
            takes,
            |_, _, _, _| true,
        )
        .unwrap();
        pieces.push(piece);
    }
    let merged = temp.path().join("merged");
    merge::merge(&pieces, &merged, merge::Join::Pieces).unwrap();
    same_files(&whole, &merged);
    // dataset::piece cuts the same runs a Dask compile merges.
    let even = even_pieces(temp.path(), &Options::default(), 3, "even");
    let merged_even = temp.path().join("merged_even");
    merge::merge(&even, &merged_even, merge::Join::Pieces).unwrap();
    same_files(&whole, &merged_even);

    // Pieces out of order, repeated, overlapping, with a gap or short of the end are refused,
    // and nothing is written.
    for (order, why) in [
        (vec![&pieces[3], &pieces[0]], "are in no piece given"),
        (vec![&pieces[0], &pieces[0]], "which an earlier piece holds"),
        (
            vec![&pieces[0], &pieces[3]],
            "takes 7 to 8 are in no piece given",
        ),
        (
            vec![&pieces[0], &pieces[1]],
            "the rest of the list is missing",
        ),
        (vec![&even[0], &pieces[3]], "which an earlier piece holds"),
    ] {
        let target = temp.path().join("misordered");
        let given: Vec<PathBuf> = order.iter().map(|p| p.to_path_buf()).collect();
        let error = merge::merge(&given, &target, merge::Join::Pieces).unwrap_err();
        assert!(error.to_string().contains(why), "{error}");
        assert!(!target.exists());
    }

    // Another spelling of the same folder gives the same bytes (errors name paths relative to it).
    let absolute = temp.path().join("absolute");
    let dir = std::fs::canonicalize(DATA).unwrap();
    let items = dataset::takes(&dir).unwrap();
    let takes = dataset::whole_list(&dir, &items);
    dataset::compile(
        &dir,
        items,
        &Options::default(),
        2,
        &absolute,
        takes,
        |_, _, _, _| true,
    )
    .unwrap();
    same_files(&whole, &absolute);

    // Pieces made with other options are refused.
    let other = temp.path().join("other");
    compile(
        &other,
        &Options {
            fps: 24.0,
            ..Options::default()
        },
        2,
    );
    let error = merge::merge(
        &[whole.clone(), other],
        &temp.path().join("mixed"),
        merge::Join::Pieces,
    )
    .unwrap_err();
    assert!(error.to_string().contains("other options"), "{error}");
    assert!(!temp.path().join("mixed").exists());

    // A piece of another compile is refused unless folders are joined, which groups by
    // topology: the repository twice is every clip twice, in as many groups as once.
    let asf = temp.path().join("asf_only");
    let asf_dir = Path::new(DATA).join("asf_amc");
    let asf_items = dataset::takes(&asf_dir).unwrap();
    let takes = dataset::whole_list(&asf_dir, &asf_items);
    dataset::compile(
        &asf_dir,
        asf_items,
        &Options::default(),
        2,
        &asf,
        takes,
        |_, _, _, _| true,
    )
    .unwrap();
    let error = merge::merge(
        &[whole.clone(), asf.clone()],
        &temp.path().join("joined"),
        merge::Join::Pieces,
    )
    .unwrap_err();
    assert!(error.to_string().contains("another compile"), "{error}");
    let joined = temp.path().join("joined");
    let summary =
        merge::merge(&[whole.clone(), asf.clone()], &joined, merge::Join::Folders).unwrap();
    let once = read::read_manifest(&whole).unwrap();
    let asf_manifest = read::read_manifest(&asf).unwrap();
    assert_eq!(summary.clips, once.clips.len() + asf_manifest.clips.len());
    assert_eq!(summary.groups, once.groups.len());

    for kind in [
        RotationKind::Quat,
        RotationKind::Matrix,
        RotationKind::Euler,
    ] {
        let out = temp.path().join(kind.name());
        compile(
            &out,
            &Options {
                rotations: kind,
                ..Options::default()
            },
            2,
        );
        let manifest = read::read_manifest(&out).unwrap();
        assert_eq!(manifest.options.rotations, kind.name());
        let group = &manifest.groups[0];
        let shape = &group.arrays[1].shape;
        let rotated = group.topology.rotated.len();
        match kind {
            RotationKind::Matrix => assert_eq!(shape[1..], [rotated, 3, 3]),
            _ => assert_eq!(shape[1..], [rotated, kind.width()]),
        }
    }
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
#[test]
fn the_command_lists_what_it_skipped_and_refuses_what_it_cannot_make() {
    let temp = tempfile::tempdir().unwrap();
    let out = temp.path().join("ds");
    let run = bvhview(&[
        "dataset",
        DATA,
        "-o",
        out.to_str().unwrap(),
        "--rotations",
        "quat",
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(
        stderr.contains(
            "skipped tests/data/bvh_malformed/dali_test-invalid-hierarchy1.bvh:3:3: expected '{' after 'root', found 'OFFSET'"
        ),
        "{stderr}"
    );
    // 35 groups: Maya's HumanIK save of its character has the plain save's 49 bones;
    // feet read from the legs give one skeleton's takes the same feet whatever their rest pose;
    // the three characters of tests/data/characters are takes too, and the three AMASS files
    // (SMPL, SMPL-H, SMPL-X: three skeletons).
    assert!(
        stderr.contains("59 clips, 5734 frames at 30 fps in 38 topology groups; 11 skipped"),
        "{stderr}"
    );
    assert_eq!(read::read_manifest(&out).unwrap().options.rotations, "quat");

    // A folder that exists and holds something is not replaced.
    let again = bvhview(&["dataset", DATA, "-o", out.to_str().unwrap()]);
    assert_eq!(again.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&again.stderr).contains("already exists"));
    // Nothing half-made is left beside it.
    let names: Vec<_> = std::fs::read_dir(temp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["ds"]);

    // Only broken takes: nothing to learn from, exit 2.
    let folder = temp.path().join("takes");
    std::fs::create_dir(&folder).unwrap();
    for name in ["dali_test-empty.bvh", "dali_test-invalid-motion0.bvh"] {
        std::fs::copy(
            Path::new(DATA).join("bvh_malformed").join(name),
            folder.join(name),
        )
        .unwrap();
    }
    let broken = bvhview(&[
        "dataset",
        folder.to_str().unwrap(),
        "-o",
        temp.path().join("broken").to_str().unwrap(),
    ]);
    assert_eq!(broken.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&broken.stderr).contains("no take could be compiled"));
    assert!(!temp.path().join("broken").exists());

    for (flag, value) in [
        ("--fps", "0"),
        ("--contact-height", "-1"),
        ("--contact-speed", "nan"),
    ] {
        let refused = bvhview(&[
            "dataset",
            DATA,
            "-o",
            temp.path().join("x").to_str().unwrap(),
            flag,
            value,
        ]);
        assert_eq!(refused.status.code(), Some(2), "{flag} {value}");
        assert!(!temp.path().join("x").exists());
    }
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_take_of_the_whole_corpus_compiles_standing_in_metres() {
    let corpus = Path::new("../shared/data");
    let temp = tempfile::tempdir().unwrap();
    let out = temp.path().join("corpus");
    let items = dataset::takes(corpus).unwrap();
    let list = dataset::whole_list(corpus, &items);
    let summary = dataset::compile(
        corpus,
        items,
        &Options::default(),
        2,
        &out,
        list,
        |_, _, _, _| true,
    )
    .unwrap();
    let manifest = read::read_manifest(&out).unwrap();
    // Only the folder of broken files has takes that fail.
    for skipped in &summary.skipped {
        assert!(
            skipped.source.path.starts_with("bvh_malformed/"),
            "{skipped:?}"
        );
    }
    let real = manifest
        .clips
        .iter()
        .filter(|c| !c.about.source.path.starts_with("bvh_malformed/"))
        .count();
    let files = std::fs::read_dir(corpus.join("bvh")).unwrap().count()
        + std::fs::read_dir(corpus.join("asf_amc"))
            .unwrap()
            .filter(|e| e.as_ref().unwrap().path().extension().unwrap() == "amc")
            .count();
    assert_eq!(real, files);
    // Every figure (but the few toy chains) stands 1.2 to 2.3 m tall at its tallest, Y up (a
    // single rig's spread arms reach past 2 m).
    for clip in &manifest.clips {
        let path = &clip.about.source.path;
        if path.starts_with("bvh_malformed/") || path.contains("simple") {
            continue;
        }
        let positions = clip_rows(&out, &manifest, path, "positions");
        let points = manifest.groups[clip.group].topology.joints.len();
        let tallest = positions
            .chunks(points * 3)
            .map(|frame| {
                let heights = frame.chunks(3).map(|p| p[1]);
                heights.clone().fold(f32::MIN, f32::max) - heights.fold(f32::MAX, f32::min)
            })
            .fold(0.0, f32::max);
        let range = if path.contains("cutie") {
            0.8..2.3
        } else {
            1.2..2.3
        };
        assert!(range.contains(&tallest), "{path}: {tallest} m");
    }
}

#[test]
fn many_skeletons_compile_with_few_files_open() {
    // Forty takes, each on a skeleton of its own: forty groups of six files. With at most 32
    // files open at once the compile still succeeds, as it keeps only the files of the group
    // last written open.
    let temp = tempfile::tempdir().unwrap();
    let takes = temp.path().join("takes");
    std::fs::create_dir(&takes).unwrap();
    for k in 0..40 {
        let text = format!(
            "HIERARCHY\nROOT Hips{k}\n{{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n  JOINT LeftFoot{k}\n  {{\n    OFFSET 0 -90 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {{\n      OFFSET 0 -8 10\n    }}\n  }}\n}}\nMOTION\nFrames: 3\nFrame Time: 0.0333333\n0 98 0 0 0 0 0 0 0\n1 98 0 0 10 0 5 0 0\n2 98 0 0 20 0 10 0 0\n"
        );
        std::fs::write(takes.join(format!("take_{k:02}.bvh")), text).unwrap();
    }
    let out = temp.path().join("ds");
    let run = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -n 32 && exec {} dataset {} -o {}",
            env!("CARGO_BIN_EXE_bvhview"),
            takes.display(),
            out.display()
        ))
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let manifest = read::read_manifest(&out).unwrap();
    assert_eq!((manifest.groups.len(), manifest.clips.len()), (40, 40));
    assert_eq!(
        manifest.groups[39].topology.joints,
        ["Hips39", "LeftFoot39", "LeftFoot39_End"]
    );
    assert_eq!(manifest.groups[0].topology.feet, [1, 2]);
}

#[test]
fn a_group_written_again_after_another_keeps_every_row_and_its_header() {
    // Takes of one skeleton with a take of another between them: the first group's files are
    // closed (their header written) and opened again. Its arrays must be those of the same
    // takes compiled without the other between them, byte for byte.
    let take = |root: &str, lift: u32| {
        format!(
            "HIERARCHY\nROOT {root}\n{{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n  JOINT Foot\n  {{\n    OFFSET 0 -90 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {{\n      OFFSET 0 -8 10\n    }}\n  }}\n}}\nMOTION\nFrames: 3\nFrame Time: 0.0333333\n0 {lift} 0 0 0 0 0 0 0\n1 {lift} 0 0 10 0 5 0 0\n2 {lift} 0 0 20 0 10 0 0\n"
        )
    };
    let temp = tempfile::tempdir().unwrap();
    let (between, alone) = (temp.path().join("between"), temp.path().join("alone"));
    for dir in [&between, &alone] {
        std::fs::create_dir(dir).unwrap();
        std::fs::write(dir.join("a.bvh"), take("Hips", 98)).unwrap();
        std::fs::write(dir.join("c.bvh"), take("Hips", 95)).unwrap();
    }
    std::fs::write(between.join("b.bvh"), take("Pelvis", 90)).unwrap();
    let compiled = |dir: &Path| {
        let out = dir.with_extension("ds");
        let items = dataset::takes(dir).unwrap();
        let takes = dataset::whole_list(dir, &items);
        dataset::compile(
            dir,
            items,
            &Options::default(),
            1,
            &out,
            takes,
            |_, _, _, _| true,
        )
        .unwrap();
        out
    };
    let (with_b, without) = (compiled(&between), compiled(&alone));
    let manifest = read::read_manifest(&with_b).unwrap();
    assert_eq!(manifest.groups.len(), 2);
    assert_eq!(manifest.groups[0].clips, 2);
    assert_eq!(manifest.groups[0].topology.joints[0], "Hips");
    let frames = manifest.groups[0].frames;
    for array in &manifest.groups[0].arrays {
        let file = with_b.join(&array.file);
        assert_eq!(
            std::fs::read(&file).unwrap(),
            std::fs::read(without.join(&array.file)).unwrap(),
            "{}",
            array.file
        );
        if array.name != "offsets" && array.name != "rest_offsets" {
            assert_eq!(read_npy(&file).shape[0], frames, "{}", array.file);
        }
    }
}

#[test]
fn takes_without_a_frame_time_or_a_utf8_name_are_skipped_with_the_reason() {
    use std::os::unix::ffi::OsStrExt;
    let temp = tempfile::tempdir().unwrap();
    let takes = temp.path().join("takes");
    std::fs::create_dir(&takes).unwrap();
    let walk = std::fs::read_to_string("assets/walk.bvh").unwrap();
    std::fs::write(takes.join("a_walk.bvh"), &walk).unwrap();
    let frozen = walk.replacen("Frame Time:", "Frame Time: 0\nX", 1);
    let frozen = frozen
        .lines()
        .filter(|l| !l.starts_with('X'))
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(takes.join("b_frozen.bvh"), frozen).unwrap();
    let latin1 = std::ffi::OsStr::from_bytes(b"c_caf\xe9.bvh");
    std::fs::write(takes.join(latin1), &walk).unwrap();
    let out = temp.path().join("ds");
    let items = dataset::takes(&takes).unwrap();
    let list = dataset::whole_list(&takes, &items);
    let summary = dataset::compile(
        &takes,
        items,
        &Options::default(),
        1,
        &out,
        list,
        |_, _, _, _| true,
    )
    .unwrap();
    assert_eq!(summary.clips, 1);
    let manifest = read::read_manifest(&out).unwrap();
    let reasons: Vec<&str> = manifest.skipped.iter().map(|s| s.error.as_str()).collect();
    assert_eq!(reasons.len(), 2, "{reasons:?}");
    assert!(
        reasons[0].starts_with("b_frozen.bvh: Frame Time 0: no rate"),
        "{reasons:?}"
    );
    assert!(reasons[1].contains("is not UTF-8"), "{reasons:?}");
}

/// `out_units` (`dataset --out-units`): every length of every clip written in those units
/// (positions, translations, root translations, velocities, OFFSETs and each group's
/// `skeleton.bvh`) and everything else as in metres (rotations, contacts, the metrics); the
/// manifest says the units, a merge of pieces in them gives the whole compile's bytes, the
/// dataset reads back, and HumanML3D's metres are not converted but refused.
#[test]
fn out_units_write_every_length_in_them_and_nothing_else_changes() {
    let temp = tempfile::tempdir().unwrap();
    let metres = temp.path().join("metres");
    compile(&metres, &Options::default(), 2);
    let inches = bvhview::model::stance::Units::named("in").unwrap();
    let options = Options {
        out_units: Some(inches),
        ..Options::default()
    };
    let converted = temp.path().join("inches");
    compile(&converted, &options, 2);
    let manifest = |out: &Path| read::read_manifest(out).unwrap();
    let (m, c) = (manifest(&metres), manifest(&converted));
    assert_eq!(
        (c.options.units.as_str(), c.options.metres_per_unit),
        ("inches", 0.0254)
    );
    assert_eq!(
        (m.options.units.as_str(), m.options.metres_per_unit),
        ("metres", 1.0)
    );
    let raw: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(metres.join("manifest.json")).unwrap())
            .unwrap();
    let options_written = raw["options"].as_object().unwrap();
    assert!(
        !options_written.contains_key("metres_per_unit"),
        "a metres manifest stays as it was: {options_written:?}"
    );
    assert_eq!(m.clips.len(), c.clips.len());
    // As the writer computes it: metres per unit, 32-bit, inverted in 64 bits.
    let per_inch = (1.0 / f64::from(0.0254f32)) as f32;
    let mut compared = 0;
    for (a, b) in m.clips.iter().zip(&c.clips) {
        assert_eq!(a.about.metrics, b.about.metrics, "metrics stay in metres");
        assert_eq!(a.about.source, b.about.source);
        let name = a.about.source.path.as_str();
        for array in [
            "positions",
            "translations",
            "root_translations",
            "velocities",
        ] {
            let (before, after) = (
                clip_rows(&metres, &m, name, array),
                clip_rows(&converted, &c, name, array),
            );
            assert_eq!(before.len(), after.len());
            for (x, y) in before.iter().zip(&after) {
                assert_eq!(x * per_inch, *y, "{name} {array}");
                compared += 1;
            }
        }
        for array in ["rotations", "foot_contacts"] {
            let group = |man: &store::Manifest, out: &Path, clip: &store::ClipEntry| {
                let entry = man.groups[clip.group]
                    .arrays
                    .iter()
                    .find(|e| e.name == array)
                    .unwrap();
                let npy = read_npy(&out.join(&entry.file));
                let row = npy.data.len() / npy.shape[0];
                npy.data[clip.start * row..(clip.start + clip.frames) * row].to_vec()
            };
            assert_eq!(
                group(&m, &metres, a),
                group(&c, &converted, b),
                "{name} {array}"
            );
        }
    }
    assert!(compared > 100_000, "{compared} lengths compared");
    // Each group's skeleton and rest OFFSETs: in inches.
    let dataset = read::open(&converted).unwrap();
    let in_metres = read::open(&metres).unwrap();
    for k in 0..m.groups.len() {
        let (a, b) = (in_metres.skeleton(k).unwrap(), dataset.skeleton(k).unwrap());
        for (p, q) in a.joints.iter().zip(&b.joints) {
            let wanted = p.offset * per_inch;
            assert!(
                (wanted - q.offset).abs().max_element()
                    <= 1e-4 * wanted.abs().max_element().max(1.0),
                "{} {:?} {:?}",
                p.name,
                wanted,
                q.offset
            );
        }
        let rest = |out: &Path, man: &store::Manifest| {
            let name = &man.groups[k].name;
            read_npy(&out.join(name).join("rest_offsets.npy")).floats()
        };
        for (x, y) in rest(&metres, &m).iter().zip(rest(&converted, &c)) {
            assert_eq!(x * per_inch, y);
        }
    }
    // Pieces in inches merge into the whole compile's bytes.
    let pieces = even_pieces(temp.path(), &options, 2, "piece");
    let merged = temp.path().join("merged");
    merge::merge(&pieces, &merged, merge::Join::Pieces).unwrap();
    same_files(&converted, &merged);
    // HumanML3D's vectors are metres by their definition.
    let humanml3d = Options {
        features: dataset::FeatureSet::HumanMl3d,
        ..options.clone()
    };
    let refused = humanml3d.check().unwrap_err().to_string();
    assert!(
        refused.contains("out_units inches") && refused.contains("metres by their definition"),
        "{refused}"
    );
}
