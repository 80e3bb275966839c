//! When a foot point is planted: the one reading of foot contacts, asked by the dataset's
//! contacts, foot locking (`--lock-feet`) and retargeting's sliding figure.
//!
//! A point is planted in a frame when it is within [`Planting::height`] of where it rests on the
//! ground (the lowest the feet come within [`Planting::window`] seconds each way, plus the
//! point's least height above it over the take: a heel rests higher than a toe tip) and moves
//! slower than [`Planting::speed`] (the central difference, one-sided at the ends).

use super::{Body, Limb};
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, Up, world_transforms_f64};
use crate::model::skeleton::Skeleton;
use glam::DVec3;
use std::collections::VecDeque;
use std::ops::Range;

/// What "planted" means, in metres and seconds.
///
/// ```
/// use bvhview::model::body::contact::Planting;
/// use glam::DVec3;
///
/// // A point resting on the floor for 5 frames, then lifted 20 cm and carried away.
/// let track: Vec<DVec3> = (0..10)
///     .map(|f| if f < 5 { DVec3::ZERO } else { DVec3::new(0.1 * f as f64, 0.2, 0.0) })
///     .collect();
/// let planted = Planting::default().frames(&track, DVec3::Y, 1.0 / 30.0);
/// assert_eq!(planted.iter().filter(|&&p| p).count(), 4);
/// assert_eq!(Planting::contacts(&planted), vec![0..4]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Planting {
    /// At most this far above its own floor (metres)…
    pub height: f64,
    /// …and slower than this (metres per second)…
    pub speed: f64,
    /// …where the ground under a frame is the lowest the points come within this many seconds
    /// each way…
    pub window: f64,
    /// …and a point rests on it at most this high (metres: an ankle above the sole), however
    /// high it stays over a take: a foot that never comes down is not planted.
    pub rests_at_most: f64,
}

impl Default for Planting {
    /// 5 cm, 0.5 m/s, a second each way (a window that holds a step of each foot in a walk), an
    /// ankle at most 12 cm above the sole.
    fn default() -> Planting {
        Planting {
            height: 0.05,
            speed: 0.5,
            window: 1.0,
            rests_at_most: 0.12,
        }
    }
}

impl Planting {
    /// Per frame, whether a point following `track` (metres; `up` a unit vector; frames
    /// `frame_time` seconds apart) is planted: [`Planting::frames_of`] of that point alone.
    pub fn frames(&self, track: &[DVec3], up: DVec3, frame_time: f64) -> Vec<bool> {
        self.frames_of(std::slice::from_ref(&track.to_vec()), up, frame_time)
            .pop()
            .unwrap_or_default()
    }

    /// Per point of `tracks` (each its positions over the same frames, metres) and frame,
    /// whether it is planted: within [`Planting::height`] of where it rests on the ground, and
    /// slower than [`Planting::speed`]. The ground under a frame is the lowest any of the points
    /// comes within [`Planting::window`] seconds each way; where a point rests is its least
    /// height above that ground over the take (a heel rests higher than a toe tip), at most
    /// [`Planting::rests_at_most`]. So a foot held still in the air, as in a balance on one leg,
    /// is not planted, and a floor that rises or falls is followed.
    pub fn frames_of(&self, tracks: &[Vec<DVec3>], up: DVec3, frame_time: f64) -> Vec<Vec<bool>> {
        let frames = tracks.iter().map(Vec::len).min().unwrap_or(0);
        if frames == 0 {
            return vec![Vec::new(); tracks.len()];
        }
        let heights: Vec<Vec<f64>> = tracks
            .iter()
            .map(|track| track[..frames].iter().map(|p| p.dot(up)).collect())
            .collect();
        let lowest: Vec<f64> = (0..frames)
            .map(|f| heights.iter().map(|h| h[f]).fold(f64::INFINITY, f64::min))
            .collect();
        let reach = if frame_time > 0.0 {
            (self.window / frame_time).round().max(1.0) as usize
        } else {
            frames
        };
        let ground = sliding_minimum(&lowest, reach);
        tracks
            .iter()
            .zip(&heights)
            .map(|(track, heights)| {
                let rests = (0..frames)
                    .map(|f| heights[f] - ground[f])
                    .fold(f64::INFINITY, f64::min)
                    .min(self.rests_at_most);
                (0..frames)
                    .map(|f| {
                        let (before, after) = (f.saturating_sub(1), (f + 1).min(frames - 1));
                        let speed = if after > before && frame_time > 0.0 {
                            (track[after] - track[before]).length()
                                / ((after - before) as f64 * frame_time)
                        } else {
                            0.0
                        };
                        heights[f] - ground[f] - rests <= self.height && speed < self.speed
                    })
                    .collect()
            })
            .collect()
    }

    /// The contacts in per-frame `planted` flags: each run of at least two planted frames.
    pub fn contacts(planted: &[bool]) -> Vec<Range<usize>> {
        let mut runs = Vec::new();
        let mut f = 0;
        while f < planted.len() {
            if !planted[f] {
                f += 1;
                continue;
            }
            let start = f;
            while f < planted.len() && planted[f] {
                f += 1;
            }
            if f - start >= 2 {
                runs.push(start..f);
            }
        }
        runs
    }
}

impl Body {
    /// Per leg (0 left, 1 right) and frame, whether its ankle is planted ([`Planting`]), in a
    /// take posed in `mode` whose file stands along `up` with `metres` per unit; empty for a leg
    /// without an ankle. A retarget's source says when feet are planted better than the
    /// retargeted take, whose feet may slide: `retarget --lock-feet` locks on these.
    pub fn planted_ankles(
        &self,
        skeleton: &Skeleton,
        motion: &Motion,
        mode: OffsetMode,
        (up, metres): (Up, f64),
        planting: &Planting,
    ) -> [Vec<bool>; 2] {
        let up = match up {
            Up::Y => DVec3::Y,
            Up::Z => DVec3::Z,
        };
        let ankles = self.limbs.map(|limb| limb[Limb::Foot as usize]);
        let mut tracks = [Vec::new(), Vec::new()];
        let mut world = Vec::new();
        for f in 0..motion.frame_count() {
            world_transforms_f64(skeleton, motion.frame(f), mode, &mut world);
            for (track, ankle) in tracks.iter_mut().zip(ankles) {
                if let Some(ankle) = ankle {
                    track.push(world[ankle].1 * metres);
                }
            }
        }
        // Read together, so that each is measured against the ground both stand on.
        let present: Vec<Vec<DVec3>> = tracks.iter().filter(|t| !t.is_empty()).cloned().collect();
        let mut read = planting
            .frames_of(&present, up, motion.frame_time)
            .into_iter();
        tracks.map(|track| match track.is_empty() {
            true => Vec::new(),
            false => read.next().unwrap_or_default(),
        })
    }
}

/// How far a point following `track` slides along the floor (across `up`) during `contacts`:
/// the path summed over each contact's frames, and the farthest it comes from where a contact
/// began. In the track's units.
///
/// ```
/// use bvhview::model::body::contact::sliding;
/// use glam::DVec3;
///
/// let track = [DVec3::ZERO, DVec3::new(0.01, 0.0, 0.0), DVec3::new(0.02, 0.5, 0.0)];
/// let (path, farthest) = sliding(&track, DVec3::Y, &[0..3]);
/// assert!((path - 0.02).abs() < 1e-12 && (farthest - 0.02).abs() < 1e-12);
/// ```
pub fn sliding(track: &[DVec3], up: DVec3, contacts: &[Range<usize>]) -> (f64, f64) {
    let flat = |v: DVec3| v - up * v.dot(up);
    let (mut path, mut farthest) = (0.0f64, 0.0f64);
    for contact in contacts {
        let Some(frames) = track.get(contact.clone()) else {
            continue;
        };
        let Some(&first) = frames.first() else {
            continue;
        };
        path += frames
            .windows(2)
            .map(|w| flat(w[1] - w[0]).length())
            .sum::<f64>();
        farthest = frames
            .iter()
            .map(|&p| flat(p - first).length())
            .fold(farthest, f64::max);
    }
    (path, farthest)
}

/// The lowest of `values` within `reach` places each way of every place: a queue of places
/// whose values increase, the front the lowest (linear in the length, whatever the reach).
pub fn sliding_minimum(values: &[f64], reach: usize) -> Vec<f64> {
    let count = values.len();
    let mut queue = VecDeque::new();
    let mut out = Vec::with_capacity(count);
    let mut next = 0;
    for f in 0..count {
        while next < count && next <= f + reach {
            while queue.back().is_some_and(|&b| values[b] >= values[next]) {
                queue.pop_back();
            }
            queue.push_back(next);
            next += 1;
        }
        while queue.front().is_some_and(|&front| front + reach < f) {
            queue.pop_front();
        }
        out.push(queue.front().map_or(f64::INFINITY, |&k| values[k]));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sliding_minimum_is_the_window_s_minimum() {
        let values = [5.0, 3.0, 4.0, 9.0, 1.0, 7.0, 8.0, 6.0, 2.0];
        for reach in 0..5 {
            let expected: Vec<f64> = (0..values.len())
                .map(|f| {
                    values[f.saturating_sub(reach)..(f + reach + 1).min(values.len())]
                        .iter()
                        .copied()
                        .fold(f64::INFINITY, f64::min)
                })
                .collect();
            assert_eq!(sliding_minimum(&values, reach), expected, "reach {reach}");
        }
    }

    #[test]
    fn a_foot_held_still_in_the_air_is_not_planted() {
        // One foot stands (ankle 8 cm up, toe tip 2 cm), the other is held 25 cm up, all still.
        let still = |y: f64| vec![DVec3::new(0.0, y, 0.0); 90];
        let tracks = [still(0.08), still(0.02), still(0.30), still(0.25)];
        let planted = Planting::default().frames_of(&tracks, DVec3::Y, 1.0 / 30.0);
        let all = |k: usize, value: bool| planted[k].iter().all(|&p| p == value);
        assert!(all(0, true) && all(1, true), "the standing foot");
        assert!(all(2, false) && all(3, false), "the raised foot");
    }

    #[test]
    fn a_heel_is_planted_on_its_own_floor_and_a_raised_foot_is_not() {
        // A heel 8 cm up at rest (higher than a toe would be), still for 10 frames, then lifted
        // 30 cm over 10 frames at 1 m/s across.
        let frame_time = 0.1;
        let track: Vec<DVec3> = (0..20)
            .map(|f| {
                if f < 10 {
                    DVec3::new(0.0, 0.08, 0.0)
                } else {
                    DVec3::new(0.1 * (f - 9) as f64, 0.08 + 0.03 * (f - 9) as f64, 0.0)
                }
            })
            .collect();
        let planted = Planting::default().frames(&track, DVec3::Y, frame_time);
        assert_eq!(Planting::contacts(&planted), vec![0..9]);
        // Along z up the same track lies on its side: heights are z, all 0, and it moves fast
        // after frame 9, so the contact is the same.
        let turned: Vec<DVec3> = track.iter().map(|p| DVec3::new(p.x, p.z, p.y)).collect();
        assert_eq!(
            Planting::default().frames(&turned, DVec3::Z, frame_time),
            planted
        );
    }
}
