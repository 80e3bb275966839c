//! Property tests: random skeletons and motions survive the writer and the loader unchanged, and
//! random damage to the real files never makes a loader panic.

use crate::common;
use bvhview::{Channel, Joint, Motion, RotationOrder, Skeleton};
use common::*;
use glam::Vec3;
use proptest::prelude::*;

const CHANNELS: [Channel; 6] = [
    Channel::Xposition,
    Channel::Yposition,
    Channel::Zposition,
    Channel::Xrotation,
    Channel::Yrotation,
    Channel::Zrotation,
];

/// Any finite float, including -0, subnormals and the extremes.
fn finite() -> impl Strategy<Value = f32> {
    prop_oneof![
        any::<f32>().prop_filter("finite", |v| v.is_finite()),
        (-1000.0f32..1000.0),
        Just(-0.0f32),
        Just(f32::MAX),
        Just(f32::MIN_POSITIVE),
    ]
}

/// A joint's shape: parent choice, name, offset, channels (a subset in some order), End Site.
fn joint_shape() -> impl Strategy<Value = (usize, String, [f32; 3], Vec<usize>, bool)> {
    (
        any::<usize>(),
        "[A-Za-z_][A-Za-z0-9_:.]{0,10}( [A-Za-z0-9]{1,4})?",
        [finite(), finite(), finite()],
        proptest::sample::subsequence((0..6).collect::<Vec<usize>>(), 0..=6).prop_shuffle(),
        any::<bool>(),
    )
}

/// A random skeleton in pre-order (each joint's parent is on the path from the root to the joint
/// before it, and is not an End Site) and a motion for it.
fn skeleton_and_motion() -> impl Strategy<Value = (Skeleton, Motion)> {
    (
        proptest::collection::vec(joint_shape(), 1..12),
        0usize..5,
        (0.001f64..1.0),
        proptest::collection::vec(finite(), 0..400),
    )
        .prop_map(|(shapes, frames, frame_time, pool)| {
            let mut joints: Vec<Joint> = Vec::new();
            let mut path: Vec<usize> = Vec::new();
            let mut column = 0;
            for (i, (parent_pick, name, offset, channels, end_site)) in
                shapes.into_iter().enumerate()
            {
                // In pre-order a new joint hangs off the path from the root to the joint before it.
                let parents: Vec<usize> = path
                    .iter()
                    .copied()
                    .filter(|&j| !joints[j].end_site)
                    .collect();
                let parent = if i == 0 {
                    None
                } else {
                    Some(parents[parent_pick % parents.len()])
                };
                if let Some(parent) = parent {
                    let keep = path
                        .iter()
                        .position(|&j| j == parent)
                        .expect("the parent is on the path")
                        + 1;
                    path.truncate(keep);
                }
                path.push(i);
                let name = if name.eq_ignore_ascii_case("site") {
                    format!("{name}x")
                } else {
                    name
                };
                let mut joint = Joint::new(name, parent);
                joint.offset = Vec3::from_array(offset);
                joint.end_site = end_site && parent.is_some();
                if joint.end_site {
                    // As the loader names them: the rest of the `End Site` line.
                    joint.name = "Site".into();
                } else {
                    joint.channels = channels.iter().map(|&c| CHANNELS[c]).collect();
                }
                joint.rotation_order = RotationOrder::get_flags(&joint.channels);
                joint.first_channel = column;
                column += joint.channels.len();
                if let Some(parent) = parent {
                    joints[parent].children.push(i);
                }
                joints.push(joint);
            }
            let skeleton = Skeleton {
                joints,
                ..Skeleton::default()
            };
            let data: Vec<f32> = (0..frames * column)
                .map(|i| pool.get(i % pool.len().max(1)).copied().unwrap_or(0.5))
                .collect();
            (skeleton, Motion::new(frame_time, column, frames, data))
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn written_files_load_back_identically((skeleton, motion) in skeleton_and_motion()) {
        let text = bvhview::bvh::writer::to_string(&skeleton, &motion).unwrap();
        let loaded = bvhview::bvh::load_bytes(text.as_bytes(), "random.bvh")
            .map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert_eq!(loaded.motion.frame_count(), motion.frame_count());
        prop_assert_eq!(loaded.motion.frame_time, motion.frame_time);
        let bits = |m: &Motion| m.data.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        prop_assert_eq!(bits(&loaded.motion), bits(&motion));
        prop_assert_eq!(loaded.skeleton.joints.len(), skeleton.joints.len());
        for (a, b) in loaded.skeleton.joints.iter().zip(&skeleton.joints) {
            // Names with blanks are written with `_` (the writer's safe names).
            prop_assert_eq!(&a.name, &bvhview::bvh::writer::safe_name(&b.name));
            prop_assert_eq!(a.parent, b.parent);
            prop_assert_eq!(&a.children, &b.children);
            prop_assert_eq!(a.offset.to_array().map(f32::to_bits), b.offset.to_array().map(f32::to_bits));
            prop_assert_eq!(&a.channels, &b.channels);
            prop_assert_eq!(a.first_channel, b.first_channel);
            prop_assert_eq!(a.end_site, b.end_site);
        }
    }
}

/// The contents of several files.
type Files = Vec<Vec<u8>>;

/// The start of each real file (the loaders must survive their damage; the start keeps the
/// debug build fast).
fn samples(folder: &str, ext: &str) -> Vec<Vec<u8>> {
    files_in(&data(folder), ext)
        .into_iter()
        .map(|path| {
            let mut bytes = std::fs::read(path).unwrap();
            bytes.truncate(24 * 1024);
            bytes
        })
        .collect()
}

/// Damage to a file: flip a byte, insert bytes, delete a stretch, or cut it short.
#[derive(Clone, Debug)]
enum Damage {
    Flip(usize, u8),
    Insert(usize, Vec<u8>),
    Delete(usize, usize),
    Truncate(usize),
}

fn damage() -> impl Strategy<Value = Vec<Damage>> {
    let one = prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(at, b)| Damage::Flip(at, b)),
        (
            any::<usize>(),
            proptest::collection::vec(
                prop_oneof![
                    any::<u8>(),
                    Just(b'{'),
                    Just(b'}'),
                    Just(b'\n'),
                    Just(b'\r'),
                    Just(b' ')
                ],
                1..8
            )
        )
            .prop_map(|(at, bytes)| Damage::Insert(at, bytes)),
        (any::<usize>(), 1usize..64).prop_map(|(at, n)| Damage::Delete(at, n)),
        any::<usize>().prop_map(Damage::Truncate),
    ];
    proptest::collection::vec(one, 1..6)
}

fn apply(mut bytes: Vec<u8>, damage: &[Damage]) -> Vec<u8> {
    for d in damage {
        let len = bytes.len().max(1);
        match d {
            Damage::Flip(at, b) => {
                if !bytes.is_empty() {
                    bytes[at % len] = *b;
                }
            }
            Damage::Insert(at, new) => {
                let at = at % (bytes.len() + 1);
                bytes.splice(at..at, new.iter().copied());
            }
            Damage::Delete(at, n) => {
                let at = at % len;
                let end = (at + n).min(bytes.len());
                if at < end {
                    bytes.drain(at..end);
                }
            }
            Damage::Truncate(at) => bytes.truncate(at % len),
        }
    }
    bytes
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn damaged_bvh_files_never_panic(pick in any::<usize>(), damage in damage()) {
        static FILES: std::sync::OnceLock<Vec<Vec<u8>>> = std::sync::OnceLock::new();
        let files = FILES.get_or_init(|| samples("bvh", "bvh"));
        let bytes = apply(files[pick % files.len()].clone(), &damage);
        // An error is fine; a panic fails the test.
        if let Ok(bvh) = bvhview::bvh::load_bytes(&bytes, "damaged.bvh") {
            let _ = bvhview::bvh::print::print(&bvh.skeleton);
            let _ = bvhview::bvh::writer::to_string(&bvh.skeleton, &bvh.motion);
        }
    }

    #[test]
    fn damaged_asf_and_amc_files_never_panic(pick in any::<usize>(), damage in damage(), amc_damage in damage()) {
        static FILES: std::sync::OnceLock<(Files, Files)> = std::sync::OnceLock::new();
        let (asfs, amcs) = FILES.get_or_init(|| (samples("asf_amc", "asf"), samples("asf_amc", "amc")));
        let asf_text = String::from_utf8_lossy(&apply(asfs[pick % asfs.len()].clone(), &damage)).into_owned();
        if let Ok(asf) = bvhview::acclaim::asf::parse_asf(&asf_text, "damaged.asf") {
            let (skeleton, maps) = asf.to_skeleton();
            let amc_text = String::from_utf8_lossy(&apply(amcs[pick % amcs.len()].clone(), &amc_damage)).into_owned();
            let _ = bvhview::acclaim::amc::parse_amc(&amc_text, "damaged.amc", &maps, skeleton.channel_count(), true, 0.01);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// `bvhview solve`'s readers: an `.npy` or a positions CSV with any bytes
    /// changed, cut or added never panics; what reads is solved onto smpl22 without a panic.
    #[test]
    fn damaged_positions_never_panic(damage in damage(), csv in any::<bool>()) {
        static FILES: std::sync::OnceLock<(Vec<u8>, Vec<u8>)> = std::sync::OnceLock::new();
        let (npy, text) = FILES.get_or_init(|| {
            let npy = std::fs::read("tests/solve/walk_smpl22.npy").unwrap();
            let mut text = String::from("frame,joint,x,y,z\n");
            for f in 0..3 {
                for (j, name) in bvhview::solve::SMPL22_ORDER.iter().enumerate() {
                    text += &format!("{f},{name},{j},{}.5,-{f}\n", j % 7);
                }
            }
            (npy, text.into_bytes())
        });
        let bytes = apply(if csv { text.clone() } else { npy.clone() }, &damage);
        let read = if csv {
            std::str::from_utf8(&bytes)
                .ok()
                .and_then(|t| bvhview::solve::read_csv(t, "damaged.csv").ok())
        } else {
            bvhview::solve::read_npy(&bytes, "damaged.npy")
                .ok()
                .map(|(joints, points)| {
                    let names = (0..joints).map(|j| {
                        bvhview::solve::SMPL22_ORDER.get(j).map_or(format!("j{j}"), |n| n.to_string())
                    });
                    (names.collect(), points)
                })
        };
        if let Some((names, points)) = read
            && let Ok(positions) = bvhview::solve::Positions::new(names, points, 0.05)
        {
            let (smpl, _) = bvhview::retarget::built_in("smpl22").unwrap();
            let _ = bvhview::solve::solve(&smpl, bvhview::model::pose::Up::Y, &positions, None);
        }
    }
}
