//! Writes `assets/walk.bvh`, the default motion: one in-place walk cycle on the skeleton printed in
//! the article on what each MOTION number means (an Xsens export: 23 joints, every rotation YXZ, a
//! 6-channel root).
//!
//! `cargo run --example make_walk [OUT]` (default OUT: assets/walk.bvh). The cycle is made from
//! sines: legs swing ±24°, knees bend in the swing, arms swing against the legs, hips bob and
//! twist. It loops seamlessly, so W (next frame, wrapping) plays it for ever.

use bvhview::bvh::writer::write_bvh;
use bvhview::{Channel, Joint, Motion, RotationOrder, Skeleton};
use glam::Vec3;
use std::f32::consts::TAU;
use std::io::BufWriter;

const FRAMES: usize = 40;
const FRAME_TIME: f64 = 0.033333;
const HIPS_HEIGHT: f32 = 84.73076;

/// (name, parent name, offset); End Sites are named "Site".
const BONES: &[(&str, &str, [f32; 3])] = &[
    ("Hips", "", [0.0, 0.0, 0.0]),
    ("Chest", "Hips", [0.0, 9.085309, -0.011154]),
    ("Chest2", "Chest", [0.0, 8.950749, 0.022763]),
    ("Chest3", "Chest2", [0.0, 8.911174, 0.0]),
    ("Chest4", "Chest3", [0.0, 8.90207, 0.0]),
    ("Neck", "Chest4", [0.0, 13.422772, 0.0]),
    ("Head", "Neck", [0.0, 8.338636, 0.048151]),
    ("Site", "Head", [0.0, 15.778614, 0.02543]),
    ("RightCollar", "Chest4", [-2.767708, 8.920939, 0.0]),
    ("RightShoulder", "RightCollar", [-13.35898, 0.0, 0.0]),
    ("RightElbow", "RightShoulder", [0.0, -29.360726, 0.0]),
    ("RightWrist", "RightElbow", [0.0, -23.72838, 0.0]),
    ("Site", "RightWrist", [0.0, -17.517202, 0.0]),
    ("LeftCollar", "Chest4", [2.767708, 8.920939, 0.0]),
    ("LeftShoulder", "LeftCollar", [13.35898, 0.0, 0.0]),
    ("LeftElbow", "LeftShoulder", [0.0, -29.360726, 0.0]),
    ("LeftWrist", "LeftElbow", [0.0, -23.72838, 0.0]),
    ("Site", "LeftWrist", [0.0, -17.517202, 0.0]),
    ("RightHip", "Hips", [-7.475494, 0.055214, 0.005577]),
    ("RightKnee", "RightHip", [0.0, -38.197352, -0.005333]),
    ("RightAnkle", "RightKnee", [0.0, -37.10085, -0.009018]),
    ("RightToe", "RightAnkle", [0.0, -9.65566, 22.225547]),
    ("Site", "RightToe", [0.0, -1.495764, 7.116721]),
    ("LeftHip", "Hips", [7.475494, 0.055214, 0.005577]),
    ("LeftKnee", "LeftHip", [0.0, -38.197352, -0.005333]),
    ("LeftAnkle", "LeftKnee", [0.0, -37.10085, -0.009018]),
    ("LeftToe", "LeftAnkle", [0.0, -9.65566, 22.225547]),
    ("Site", "LeftToe", [0.0, -1.495764, 7.116721]),
];

fn skeleton() -> Skeleton {
    let mut joints: Vec<Joint> = Vec::new();
    let mut channel_count = 0;
    for &(name, parent, offset) in BONES {
        // The last joint of that name before this one is the parent (BONES is in pre-order).
        let parent = joints.iter().rposition(|j| j.name == parent && !j.end_site);
        let mut joint = Joint::new(name.to_string(), parent);
        joint.offset = Vec3::from_array(offset);
        joint.first_channel = channel_count;
        if name == "Site" {
            joint.end_site = true;
        } else {
            let rotations = [Channel::Yrotation, Channel::Xrotation, Channel::Zrotation];
            if parent.is_none() {
                joint.channels = vec![Channel::Xposition, Channel::Yposition, Channel::Zposition];
            }
            joint.channels.extend(rotations);
            joint.rotation_order = RotationOrder::get_flags(&joint.channels);
        }
        channel_count += joint.channels.len();
        let index = joints.len();
        if let Some(parent) = parent {
            joints[parent].children.push(index);
        }
        joints.push(joint);
    }
    Skeleton {
        joints,
        ..Skeleton::default()
    }
}

/// Rotation (Y, X, Z degrees) of a joint at phase `phase` (radians over one cycle).
fn rotation(name: &str, phase: f32) -> [f32; 3] {
    let swing = phase.sin();
    // The skeleton faces +Z; a negative X rotation swings a hanging limb forward.
    match name {
        "Hips" => [6.0 * swing, 2.0, 0.0],
        "Chest" | "Chest2" => [-3.0 * swing, 1.0, 0.0],
        "Neck" => [0.0, -2.0, 0.0],
        "Head" => [0.0, 2.0 * (2.0 * phase).sin(), 0.0],
        "RightHip" => [0.0, -24.0 * swing, 0.0],
        "LeftHip" => [0.0, 24.0 * swing, 0.0],
        // Knees bend while their leg swings forward (hip angle rising).
        "RightKnee" => [0.0, 5.0 + 40.0 * (phase.cos().max(0.0)).powi(2), 0.0],
        "LeftKnee" => [0.0, 5.0 + 40.0 * ((-phase.cos()).max(0.0)).powi(2), 0.0],
        "RightAnkle" => [0.0, -8.0 * (phase + 0.6).sin(), 0.0],
        "LeftAnkle" => [0.0, 8.0 * (phase + 0.6).sin(), 0.0],
        "RightShoulder" => [0.0, 20.0 * swing, -4.0],
        "LeftShoulder" => [0.0, -20.0 * swing, 4.0],
        "RightElbow" => [0.0, -12.0 + 8.0 * swing, 0.0],
        "LeftElbow" => [0.0, -12.0 - 8.0 * swing, 0.0],
        _ => [0.0, 0.0, 0.0],
    }
}

fn motion(skeleton: &Skeleton) -> Motion {
    let channels = skeleton.channel_count();
    let mut data = Vec::with_capacity(FRAMES * channels);
    for frame in 0..FRAMES {
        let phase = TAU * frame as f32 / FRAMES as f32;
        for joint in skeleton.joints.iter().filter(|j| !j.end_site) {
            if joint.parent.is_none() {
                // Lowest at heel strike, twice per cycle.
                let bob = -1.5 * (2.0 * phase).cos();
                data.extend([0.0, HIPS_HEIGHT + bob, 0.0]);
            }
            data.extend(rotation(&joint.name, phase).map(|v| (v * 1000.0).round() / 1000.0));
        }
    }
    Motion::new(FRAME_TIME, channels, FRAMES, data)
}

fn main() -> std::io::Result<()> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "assets/walk.bvh".to_string());
    let skeleton = skeleton();
    let motion = motion(&skeleton);
    let mut file = BufWriter::new(std::fs::File::create(&out)?);
    write_bvh(&mut file, &skeleton, &motion)?;
    eprintln!(
        "wrote {out}: {} joints, {} frames",
        skeleton.joints.len(),
        motion.frame_count()
    );
    Ok(())
}
