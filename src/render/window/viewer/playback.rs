//! Playback's timing: the speeds + and - step through, how long a frame shows, when the window
//! wakes and how many frames it steps when it wakes late.

use std::time::{Duration, Instant};

/// Playback speeds `+` and `-` step through.
pub(super) const SPEEDS: [f64; 9] = [0.1, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0];

/// How long playback shows each frame: the file's Frame Time, kept between 1 ns and an hour so
/// that any value a file holds (0, 1e-300, 1e300) plays without a panic; 1/30 s when the file
/// gives none. Ticks shorter than the window wakes ([`next_wake`]) are stepped several at a time.
pub(super) fn playback_step(frame_time: f64) -> Duration {
    if !(frame_time > 0.0 && frame_time.is_finite()) {
        return Duration::from_secs_f64(1.0 / 30.0);
    }
    Duration::from_secs_f64(frame_time.clamp(1e-9, 3600.0))
}

/// The window wakes at most this often while playing: no busy loop, whatever the frame rate.
pub(super) const SHORTEST_WAKE: Duration = Duration::from_millis(1);

/// When to wake next: when the next tick is due, but not sooner than [`SHORTEST_WAKE`] from now.
pub(super) fn next_wake(now: Instant, next_tick: Instant) -> Instant {
    next_tick.max(now + SHORTEST_WAKE)
}

/// When a frame was due `late` ago and frames last `step`: how many frames to step (at least
/// one), and how much later than the missed time the next one is due.
pub(super) fn frames_due(late: Duration, step: Duration) -> (u64, Duration) {
    let step_nanos = step.as_nanos().max(1);
    let frames = late.as_nanos() / step_nanos + 1;
    let later = Duration::from_nanos(u64::try_from(frames * step_nanos).unwrap_or(u64::MAX));
    (u64::try_from(frames).unwrap_or(u64::MAX), later)
}
