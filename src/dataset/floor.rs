//! The floor under a take over a sliding window, when each foot touches it, and a clip put on
//! it (`--ground`).

use super::*;

/// How far (seconds, each way) the floor under a frame is looked for.
pub const FLOOR_WINDOW_S: f64 = 1.0;

/// The floor under each frame: the lowest height of any foot point within [`FLOOR_WINDOW_S`]
/// before or after it. A floor that rises or falls during the take (a ramp, stairs, a drifting
/// capture) is followed; a window that long holds a step of each foot in a walk.
pub(super) fn floor_heights(lowest_foot: &[f32], reach: usize) -> Vec<f32> {
    let frames = lowest_foot.len();
    // A sliding minimum: the queue holds frames whose heights increase, the front the lowest.
    let mut queue = std::collections::VecDeque::new();
    let mut floor = Vec::with_capacity(frames);
    let mut next = 0;
    for f in 0..frames {
        while next < frames && next <= f + reach {
            while queue
                .back()
                .is_some_and(|&b| lowest_foot[b] >= lowest_foot[next])
            {
                queue.pop_back();
            }
            queue.push_back(next);
            next += 1;
        }
        while queue.front().is_some_and(|&front| front + reach < f) {
            queue.pop_front();
        }
        floor.push(queue.front().map_or(f32::INFINITY, |&k| lowest_foot[k]));
    }
    floor
}

/// Foot contacts: a foot point is in contact in a frame when it is within
/// `options.contact_height` of the floor under that frame ([`floor_heights`]) and slower than
/// `options.contact_speed`.
pub(super) fn contacts(
    world: &[Vec3],
    derived: &Derived,
    points: usize,
    feet: &[u32],
    options: &Options,
) -> Vec<u8> {
    let reach = (FLOOR_WINDOW_S * options.fps).round() as usize;
    let floor = floor_heights(&derived.lowest_foot, reach);
    let mut out = Vec::with_capacity(floor.len() * feet.len());
    for (f, &floor) in floor.iter().enumerate() {
        for &p in feet {
            let i = f * points + p as usize;
            let low = world[i].y - floor <= options.contact_height;
            let still = derived.velocities[i].length() < options.contact_speed;
            out.push(u8::from(low && still));
        }
    }
    out
}

/// Moves a posed clip up or down so that its lowest foot point over the whole clip (its lowest
/// point, without feet) is on y = 0: every world position, and the translation of every root
/// (a root's translation is where it is in the world; a child's is relative to its parent).
pub(super) fn ground(
    skeleton: &crate::Skeleton,
    topology: &Topology,
    world: &mut [Vec3],
    translations: &mut [f32],
) {
    let points = skeleton.joints.len().max(1);
    let lowest = world
        .chunks(points)
        .flat_map(|pose| {
            let feet = topology.feet.iter().map(|&p| pose[p as usize].y);
            let all = pose.iter().map(|p| p.y);
            if topology.feet.is_empty() {
                all.collect::<Vec<f32>>()
            } else {
                feet.collect()
            }
        })
        .fold(f32::INFINITY, f32::min);
    if !lowest.is_finite() {
        return;
    }
    for point in world.iter_mut() {
        point.y -= lowest;
    }
    let translated = topology.translated.len().max(1);
    for frame in translations.chunks_mut(translated * 3) {
        for (k, &joint) in topology.translated.iter().enumerate() {
            if skeleton.joints[joint as usize].parent.is_none() {
                frame[k * 3 + 1] -= lowest;
            }
        }
    }
}
