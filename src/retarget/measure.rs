//! Measures of a retarget: how far limb directions are from the source's, how far the
//! followable joints are, and how far planted feet slide.

use super::*;

/// The angle in degrees between each bone's world direction in the source and in the
/// retargeted take: per bone of [`bones`] (in its order), one per frame. The check of
/// rest alignment; [`quantile`] of them all gives the figures in the guide.
pub fn direction_errors(
    source: &Skeleton,
    source_motion: &Motion,
    target: &Skeleton,
    target_motion: &Motion,
    map: &Map,
    ups: Ups,
) -> Vec<Vec<f64>> {
    let (us, ut) = (to_y_up(ups.source), to_y_up(ups.target));
    let pairs = bones(source, target, map);
    let source_mode = source_offset_mode(source, source_motion);
    let mut errors = vec![Vec::new(); pairs.len()];
    let (mut ws, mut wt) = (Vec::new(), Vec::new());
    let frames = source_motion.frame_count().min(target_motion.frame_count());
    for frame in 0..frames {
        world_transforms_f64(source, source_motion.frame(frame), source_mode, &mut ws);
        world_transforms_f64(
            target,
            target_motion.frame(frame),
            OffsetMode::Replace,
            &mut wt,
        );
        for (bone, &(t, d)) in pairs.iter().enumerate() {
            let (Some(s), Some(sd)) = (map.source_of[t], map.source_of[d]) else {
                continue;
            };
            let a = us * (ws[sd].1 - ws[s].1);
            let b = ut * (wt[d].1 - wt[t].1);
            if a.length() > 1e-9 && b.length() > 1e-9 {
                errors[bone].push(a.angle_between(b).to_degrees());
            }
        }
    }
    errors
}

/// [`direction_errors`] of the part of each bone's direction its target joint can follow: the
/// whole direction where the joint has three rotation channels; where it has one or two (an ASF
/// hinge knee `dof rx`, a foot `dof rx rz`), the direction across its first channel's axis, in
/// the plane that axis turns the bone in (what is along the axis comes from the parent's
/// rotation and the rest pose, which the hinge cannot change); `None` for a bone whose joint has
/// no rotation channel (CMU's `lhipjoint`), which follows nothing.
pub fn followable_errors(
    source: &Skeleton,
    source_motion: &Motion,
    target: &Skeleton,
    target_motion: &Motion,
    map: &Map,
    ups: Ups,
) -> Vec<Option<Vec<f64>>> {
    let (us, ut) = (to_y_up(ups.source), to_y_up(ups.target));
    let pairs = bones(source, target, map);
    let source_mode = source_offset_mode(source, source_motion);
    // Per bone: the first rotation channel's axis in the joint's frame, for joints with fewer
    // than three; `Some(None)` for three.
    let axes: Vec<Option<Option<DVec3>>> = pairs
        .iter()
        .map(|&(t, _)| {
            let joint = &target.joints[t];
            if joint.rotation_order.is_some() {
                return Some(None);
            }
            let first = joint.channels.iter().find(|c| c.is_rotation())?;
            let c = joint
                .axis
                .map_or(DQuat::IDENTITY, |c| c.as_dquat().normalize());
            Some(Some(c * DVec3::AXES[first.axis()]))
        })
        .collect();
    let mut errors: Vec<Option<Vec<f64>>> = axes.iter().map(|a| a.map(|_| Vec::new())).collect();
    let (mut ws, mut wt) = (Vec::new(), Vec::new());
    let frames = source_motion.frame_count().min(target_motion.frame_count());
    for frame in 0..frames {
        world_transforms_f64(source, source_motion.frame(frame), source_mode, &mut ws);
        world_transforms_f64(
            target,
            target_motion.frame(frame),
            OffsetMode::Replace,
            &mut wt,
        );
        for (bone, &(t, d)) in pairs.iter().enumerate() {
            let (Some(s), Some(sd), Some(Some(out))) =
                (map.source_of[t], map.source_of[d], errors.get_mut(bone))
            else {
                continue;
            };
            let mut a = us * (ws[sd].1 - ws[s].1);
            let mut b = ut * (wt[d].1 - wt[t].1);
            if let Some(Some(axis)) = axes[bone] {
                let axis = (ut * (wt[t].0 * axis)).normalize();
                a -= axis * a.dot(axis);
                b -= axis * b.dot(axis);
            }
            if a.length() > 1e-9 && b.length() > 1e-9 {
                out.push(a.angle_between(b).to_degrees());
            }
        }
    }
    errors
}

/// The foot-skate figure: of the frames where a foot or toe is within 5 cm of the floor (the
/// take's lowest foot point), the share in which it slides more than 2.5 cm along the floor to
/// the next frame. `feet`: the joints to follow (a retargeted take's mapped feet and toes, and
/// the source joints they come from, to compare like with like); `metres` per unit of the file.
pub fn foot_skate(
    skeleton: &Skeleton,
    motion: &Motion,
    feet: &[usize],
    up: Up,
    metres: f64,
) -> f64 {
    if feet.is_empty() || motion.frame_count() < 2 {
        return 0.0;
    }
    let turn = to_y_up(up);
    let mut world = Vec::new();
    let mut tracks: Vec<Vec<DVec3>> = vec![Vec::new(); feet.len()];
    for frame in 0..motion.frame_count() {
        world_transforms_f64(
            skeleton,
            motion.frame(frame),
            OffsetMode::Replace,
            &mut world,
        );
        for (track, &f) in tracks.iter_mut().zip(feet) {
            track.push(turn * world[f].1 * metres);
        }
    }
    let floor = tracks
        .iter()
        .flatten()
        .map(|p| p.y)
        .fold(f64::INFINITY, f64::min);
    let (mut near, mut sliding) = (0usize, 0usize);
    for track in &tracks {
        for pair in track.windows(2) {
            if pair[0].y - floor < 0.05 {
                near += 1;
                let step = DVec3::new(pair[1].x - pair[0].x, 0.0, pair[1].z - pair[0].z);
                if step.length() > 0.025 {
                    sliding += 1;
                }
            }
        }
    }
    if near == 0 {
        0.0
    } else {
        sliding as f64 / near as f64
    }
}

/// The value at fraction `q` (0 to 1) of sorted `values`.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let index = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[index]
}
