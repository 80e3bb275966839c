//! How much the article's 32-bit reading (`(float)atof`) and bvhview's 32-bit forward kinematics
//! lose against the same file read and posed in 64 bits: the README's precision figures.
//!
//! `cargo run --release --example precision -- FILE.bvh…` prints, per file and in all:
//! - values: how many MOTION values change when read as f32 (their shortest f32 form is not the
//!   text's number), and the largest relative change;
//! - positions: the largest distance between bvhview's world positions and a double-precision
//!   FK of the text's own numbers, as a fraction of the skeleton's size (the diagonal of the
//!   box around its joints in frame 0).
//!
//! With `--chain N` it also measures a generated chain of N joints, each turned by every axis.

use bvhview::model::pose::{OffsetMode, world_positions};
use glam::{DMat4, DVec3};

fn main() {
    let mut args = std::env::args().skip(1).peekable();
    let (mut values, mut changed, mut worst_value, mut worst_position) = (0u64, 0u64, 0f64, 0f64);
    while let Some(arg) = args.next() {
        let text = if arg == "--chain" {
            let joints: usize = args.next().and_then(|n| n.parse().ok()).expect("--chain N");
            chain(joints)
        } else {
            match std::fs::read_to_string(&arg) {
                Ok(text) => text,
                Err(e) => {
                    eprintln!("{arg}: {e}");
                    continue;
                }
            }
        };
        let Ok(bvh) = bvhview::bvh::load_bytes(text.as_bytes(), &arg) else {
            eprintln!("{arg}: does not load; skipped");
            continue;
        };
        let (offsets, rows) = numbers(&text);
        if offsets.len() != bvh.skeleton.joints.len() || rows.len() != bvh.motion.data.len() {
            eprintln!("{arg}: not read the simple way (numbers do not line up); skipped");
            continue;
        }
        let (mut file_changed, mut file_worst) = (0u64, 0f64);
        for (&exact, &read) in rows.iter().zip(&bvh.motion.data) {
            if f64::from(read) != exact {
                // Changed in its digits when the f32's shortest form is another number.
                if read.to_string().parse::<f64>().ok() != Some(exact) {
                    file_changed += 1;
                }
                if exact != 0.0 {
                    file_worst = file_worst.max(((f64::from(read) - exact) / exact).abs());
                }
            }
        }
        let channels = bvh.motion.channels.max(1);
        let frames = bvh.motion.frame_count();
        let mut position_worst = 0f64;
        let mut size = 0f64;
        for frame in 0..frames {
            let single =
                world_positions(&bvh.skeleton, bvh.motion.frame(frame), OffsetMode::Replace);
            let double = fk64(
                &bvh.skeleton,
                &offsets,
                &rows[frame * channels..][..channels],
            );
            if frame == 0 {
                let (lo, hi) = double.iter().fold(
                    (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
                    |(lo, hi), p| (lo.min(*p), hi.max(*p)),
                );
                size = (hi - lo).length().max(f64::MIN_POSITIVE);
            }
            for (a, b) in single.iter().zip(&double) {
                position_worst = position_worst.max((a.as_dvec3() - *b).length() / size);
            }
        }
        println!(
            "{arg}: {} of {} values change ({:.1} %), worst {:.2e} relative; positions within {:.2e} of its size",
            file_changed,
            rows.len(),
            100.0 * file_changed as f64 / rows.len().max(1) as f64,
            file_worst,
            position_worst
        );
        values += rows.len() as u64;
        changed += file_changed;
        worst_value = worst_value.max(file_worst);
        worst_position = worst_position.max(position_worst);
    }
    println!(
        "all: {changed} of {values} values change ({:.1} %), worst {worst_value:.2e} relative; positions within {worst_position:.2e} of the size",
        100.0 * changed as f64 / values.max(1) as f64
    );
}

/// The OFFSETs (one per joint and End Site, in file order) and the MOTION values, read as f64.
fn numbers(text: &str) -> (Vec<DVec3>, Vec<f64>) {
    let (head, motion) = text.split_once("MOTION").unwrap_or((text, ""));
    let mut words = head.split_ascii_whitespace();
    let mut offsets = Vec::new();
    while let Some(word) = words.next() {
        if word == "OFFSET" {
            let mut next = || {
                words
                    .next()
                    .and_then(|w| w.parse::<f64>().ok())
                    .unwrap_or(f64::NAN)
            };
            offsets.push(DVec3::new(next(), next(), next()));
        }
    }
    let rows = motion
        .split_once("Time:")
        .map(|(_, rest)| rest)
        .unwrap_or("")
        .split_ascii_whitespace()
        .skip(1)
        .filter_map(|w| w.parse::<f64>().ok())
        .collect();
    (offsets, rows)
}

/// World positions in f64: each joint's OFFSET with its position channels replacing it, then
/// its rotation channels in file order (what `pose` computes in f32).
fn fk64(skeleton: &bvhview::Skeleton, offsets: &[DVec3], row: &[f64]) -> Vec<DVec3> {
    let mut world: Vec<DMat4> = Vec::with_capacity(skeleton.joints.len());
    for (joint, offset) in skeleton.joints.iter().zip(offsets) {
        let values = &row[joint.first_channel..][..joint.channels.len()];
        let mut t = *offset;
        let mut r = DMat4::IDENTITY;
        for (channel, &value) in joint.channels.iter().zip(values) {
            if channel.is_position() {
                t[channel.axis()] = value;
            } else {
                let radians = value.to_radians();
                r *= match channel.axis() {
                    0 => DMat4::from_rotation_x(radians),
                    1 => DMat4::from_rotation_y(radians),
                    _ => DMat4::from_rotation_z(radians),
                };
            }
        }
        let local = DMat4::from_translation(t) * r;
        let matrix = match joint.parent {
            Some(parent) => world[parent] * local,
            None => local,
        };
        world.push(matrix);
    }
    world.iter().map(|m| m.w_axis.truncate()).collect()
}

/// A chain of `joints` joints, 1.5 units apart, each with three rotation channels, over 20
/// frames of angles that no two joints share.
fn chain(joints: usize) -> String {
    let mut text = String::from("HIERARCHY\n");
    for i in 0..joints {
        let keyword = if i == 0 { "ROOT" } else { "JOINT" };
        text.push_str(&format!(
            "{keyword} j{i}\n{{\nOFFSET 0.3 1.5 -0.2\nCHANNELS 3 Zrotation Xrotation Yrotation\n"
        ));
    }
    text.push_str("End Site\n{\nOFFSET 0 1 0\n}\n");
    text.push_str(&"}\n".repeat(joints));
    text.push_str("MOTION\nFrames: 20\nFrame Time: 0.033333\n");
    for frame in 0..20 {
        let row: Vec<String> = (0..joints * 3)
            .map(|k| format!("{:.4}", ((k * 7 + frame * 13) % 23) as f64 * 0.37 - 4.1))
            .collect();
        text.push_str(&row.join(" "));
        text.push('\n');
    }
    text
}
