//! When each foot touches the floor (the reading of the body's contacts), and a clip put on the
//! floor (`--ground`).

use super::clip::Topology;
use super::options::Options;
use crate::model::body::contact::Planting;
use glam::DVec3;
use glam::Vec3;

/// Foot contacts, per frame and foot point: planted as the reading of the body reads it
/// ([`crate::model::body::contact`]: within `options.contact_height` of where the point rests
/// on the ground the feet stand on within a second each way, and slower than
/// `options.contact_speed`), the same reading foot locking asks.
pub(super) fn contacts(world: &[Vec3], points: usize, feet: &[u32], options: &Options) -> Vec<u8> {
    let frames = world.len() / points.max(1);
    let planting = Planting {
        height: f64::from(options.contact_height),
        speed: f64::from(options.contact_speed),
        ..Planting::default()
    };
    let tracks: Vec<Vec<DVec3>> = feet
        .iter()
        .map(|&p| {
            (0..frames)
                .map(|f| world[f * points + p as usize].as_dvec3())
                .collect()
        })
        .collect();
    let planted = planting.frames_of(&tracks, DVec3::Y, 1.0 / options.fps);
    (0..frames)
        .flat_map(|f| planted.iter().map(move |foot| u8::from(foot[f])))
        .collect()
}

/// Moves a posed clip up or down so that the lowest point of its soles over the whole clip is
/// on y = 0 (each leg's ankle and everything below it, as `convert --ground` stands a take:
/// [`crate::model::body::Body::sole_points`]; the feet `--feet` names, when it names them; its
/// lowest point, without feet): every world position, and the translation of every root (a
/// root's translation is where it is in the world; a child's is relative to its parent).
pub(super) fn ground(
    skeleton: &crate::Skeleton,
    topology: &Topology,
    named_feet: bool,
    world: &mut [Vec3],
    translations: &mut [f32],
) {
    let points = skeleton.joints.len().max(1);
    let soles = crate::model::body::Body::of(skeleton).sole_points(skeleton);
    let standing: Vec<usize> = match (named_feet, soles.is_empty()) {
        (false, false) => soles,
        _ => topology.feet.iter().map(|&p| p as usize).collect(),
    };
    let lowest = world
        .chunks(points)
        .flat_map(|pose| {
            let all = pose.iter().map(|p| p.y);
            if standing.is_empty() {
                all.collect::<Vec<f32>>()
            } else {
                standing.iter().map(|&p| pose[p].y).collect()
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
