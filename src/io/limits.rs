//! The limits every count, rate and size is held to, checked once where it enters: from a file
//! (the BVH and ASF/AMC loaders), from an option (the CLI), or from Python. One function per kind,
//! so that every path refuses the same things with the same words, and nothing a file or an
//! option says can make bvhview panic, abort, or render or allocate without end.

use crate::io::error::Error;

/// Deepest nesting of joints the loaders accept (and the BVH writer writes): deeper files are
/// refused, not a stack overflow in the recursions that walk the tree.
pub const MAX_DEPTH: usize = 1000;

/// Longest joint or bone name, in bytes. Real names are under 64; a longer one is damage, and
/// every frame of a `positions` export repeats it.
pub const MAX_NAME_BYTES: usize = 1024;

/// Most bytes before the MOTION rows (the hierarchy and the MOTION header), and the most an
/// ASF skeleton may hold. A 1000-joint hierarchy is about 100 KB; past this, a file that is not
/// BVH at all (a link to /dev/zero) stops being read.
pub const MAX_HEADER_BYTES: usize = 64 << 20;

/// Longest frame time, in seconds, from a file or `--frame-time`: an hour per frame.
pub const MAX_FRAME_TIME: f64 = 3600.0;

/// Shortest frame time other than 0 (which some exporters write for "unknown"): a microsecond,
/// a million frames per second. Below it the rate is not a number a picture can play at.
pub const MIN_FRAME_TIME: f64 = 1e-6;

/// Slowest and fastest rates, in frames per second, for `--fps` (animations and resampling).
/// An APNG delay counts thousandths of a second.
pub const MIN_FPS: f64 = 0.01;
/// Fastest rate, in frames per second, for `--fps`: a thousandth of a second per frame.
pub const MAX_FPS: f64 = 1000.0;

/// Browsers show GIF frames shorter than 20 ms slower than asked, so a GIF plays at most this
/// fast (its delays count hundredths of a second).
pub const GIF_MAX_FPS: f64 = 50.0;

/// Most frames an animated picture holds (33 minutes at 50 per second); each is drawn.
pub const MAX_ANIMATION_FRAMES: usize = 100_000;

/// Most values (frames × channels) an edit may make: 1 GiB of f32, a BVH file of about 2 GB.
pub const MAX_GENERATED_VALUES: u64 = 1 << 28;

/// Values (frames × target channels) a retarget may make for each value of the take it reads
/// (frames × source channels) and each channel of the target, above [`RETARGET_VALUES_FLOOR`]:
/// the take was paid for when it was read, so what it asks of the target is held to a multiple
/// of it (a biped of 60 channels onto a character of 1,900 fits). A 982 KB take onto a glTF of
/// 17,000 skin joints asked for 14.3 GB up front, and aborted.
pub const RETARGET_VALUES_PER_VALUE: u64 = 32;

/// Values (frames × target channels) any retarget may make: 16 M (10 minutes at 120 Hz onto
/// 230 channels).
pub const RETARGET_VALUES_FLOOR: u64 = 1 << 24;

/// Whether retargeting `frames` frames of `source_channels` onto a skeleton of `joints` joints
/// and `target_channels` channels stays within the budget: at most [`RETARGET_VALUES_PER_VALUE`]
/// values a value of the take and of the target above [`RETARGET_VALUES_FLOOR`], and never past
/// a third of [`MAX_GENERATED_VALUES`] (the retarget holds each chained joint's angles in f64
/// beside the values: three times their memory at most). `what` names the take and the target.
pub fn retarget_values(
    what: &str,
    frames: usize,
    source_channels: usize,
    joints: usize,
    target_channels: usize,
) -> Result<(), Error> {
    let (frames, source, target) = (
        frames as u64,
        source_channels as u64,
        target_channels as u64,
    );
    let wanted = frames.saturating_mul(target);
    let budget = RETARGET_VALUES_PER_VALUE
        .saturating_mul(frames.saturating_mul(source).saturating_add(target))
        .saturating_add(RETARGET_VALUES_FLOOR)
        .min(MAX_GENERATED_VALUES / 3);
    if wanted > budget {
        return Err(Error::limit(
            "values",
            budget,
            wanted,
            format!(
                "{what}: {} onto {} ({target} channels) make {} values, more than a take of {} \
             values is put on a skeleton for (at most {}: {RETARGET_VALUES_PER_VALUE} a value \
             of the take and the target, above {}); trim the take or use a skeleton with fewer \
             joints",
                crate::io::error::counted(frames, "frame"),
                crate::io::error::counted(joints, "joint"),
                show(wanted as f64),
                show(frames.saturating_mul(source) as f64),
                show(budget as f64),
                show(RETARGET_VALUES_FLOOR as f64)
            ),
        ));
    }
    Ok(())
}

/// Most bytes of a file read whole into memory (FBX, GLB, glTF JSON, one glTF buffer, an `.npy`
/// of positions): 2 GiB. Past it a file is refused by its size on disk, before a byte is read
/// (a sparse 6 GB file takes 4 KB of disk and would take 6 GB of memory).
pub const MAX_WHOLE_FILE_BYTES: u64 = 2 << 30;

/// A number as a message shows it: `1e300`, not three hundred digits.
pub fn show<T>(value: T) -> String
where
    T: Copy + Into<f64> + std::fmt::Display + std::fmt::LowerExp,
{
    let size = value.into().abs();
    if size >= 1e6 || (size < 1e-4 && size > 0.0) {
        format!("{value:e}")
    } else {
        format!("{value}")
    }
}

/// `value` with at most four decimals (`0.3667`, `2000`), for a message.
pub fn brief(value: f64) -> String {
    let text = format!("{value:.4}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// A name from a file as a message quotes it: its first 64 characters, `…` after them when
/// there are more (an error quotes no more of a file than it needs).
pub fn quoted(name: &str) -> String {
    let mut short: String = name.chars().take(64).collect();
    if short.len() < name.len() {
        short.push('…');
    }
    short
}

/// A name's length, or what is wrong with it.
pub fn name(bytes: usize) -> Result<(), String> {
    if bytes > MAX_NAME_BYTES {
        return Err(format!(
            "a name of {bytes} bytes; names are at most {MAX_NAME_BYTES} bytes"
        ));
    }
    Ok(())
}

/// Whether a frame time read from a file is one bvhview accepts: 0 (some exporters write it),
/// or [`MIN_FRAME_TIME`] to [`MAX_FRAME_TIME`].
pub fn frame_time_in_file(seconds: f64) -> bool {
    seconds == 0.0 || (MIN_FRAME_TIME..=MAX_FRAME_TIME).contains(&seconds)
}

/// `--frame-time` (or Python's `frame_time=`): seconds per frame, above 0, at most
/// [`MAX_FRAME_TIME`].
pub fn frame_time_option(seconds: Option<f64>) -> Result<(), Error> {
    match seconds {
        Some(time) if !(MIN_FRAME_TIME..=MAX_FRAME_TIME).contains(&time) => Err(Error::invalid(
            "frame_time",
            show(time),
            format!(
                "expected seconds per frame, from {} to {MAX_FRAME_TIME}",
                show(MIN_FRAME_TIME)
            ),
        )),
        _ => Ok(()),
    }
}

/// `--fps`: frames per second from [`MIN_FPS`] to [`MAX_FPS`] (to [`GIF_MAX_FPS`] for a GIF).
pub fn fps(fps: f64, gif: bool) -> Result<f64, Error> {
    let most = if gif { GIF_MAX_FPS } else { MAX_FPS };
    if !(MIN_FPS..=most).contains(&fps) {
        let why = if gif {
            " (a GIF plays at most 50 frames per second; .apng plays faster)"
        } else {
            ""
        };
        return Err(Error::invalid(
            "fps",
            show(fps),
            format!("expected frames per second from {MIN_FPS} to {most}{why}"),
        ));
    }
    Ok(fps)
}

/// How many frames `frames` frames of `frame_time` seconds make at `fps`, refused past `most`.
fn frames_at(frames: usize, frame_time: f64, fps: f64, most: u64) -> Result<usize, Error> {
    let count = (frames as f64 * frame_time * fps).round().max(1.0);
    if !(count.is_finite() && count <= most as f64) {
        return Err(Error::limit(
            "frames",
            most,
            count.min(u64::MAX as f64) as u64,
            format!(
                "{} of {} s at {} per second make {} frames; at most {most} can be made",
                crate::io::error::counted(frames, "frame"),
                show(frame_time),
                show(fps),
                show(count)
            ),
        ));
    }
    Ok(count as usize)
}

/// Frames an animation of `frames` frames at `fps` holds, at most [`MAX_ANIMATION_FRAMES`].
pub fn animation_frames(frames: usize, frame_time: f64, fps: f64) -> Result<usize, Error> {
    frames_at(frames, frame_time, fps, MAX_ANIMATION_FRAMES as u64)
}

/// Frames a take of `frames` frames resampled to `fps` holds, its values (× `channels`) at
/// most [`MAX_GENERATED_VALUES`].
pub fn resampled_frames(
    frames: usize,
    frame_time: f64,
    fps: f64,
    channels: usize,
) -> Result<usize, Error> {
    frames_at(
        frames,
        frame_time,
        fps,
        MAX_GENERATED_VALUES / channels.max(1) as u64,
    )
}

/// Most pixels a picture may have: 8192 × 8192 (its buffers take about 800 MB).
pub const MAX_PICTURE_PIXELS: u64 = 8192 * 8192;

/// A picture's size: 1 to 16384 pixels each way, at most [`MAX_PICTURE_PIXELS`] in all.
pub fn picture_size(width: u32, height: u32) -> Result<(), Error> {
    let invalid = |expected: String| Error::invalid("size", format!("{width}x{height}"), expected);
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(invalid("width and height must be 1 to 16384".into()));
    }
    if u64::from(width) * u64::from(height) > MAX_PICTURE_PIXELS {
        return Err(invalid(format!(
            "at most {MAX_PICTURE_PIXELS} pixels (8192x8192)"
        )));
    }
    Ok(())
}

/// `count` zero bytes, or [`Error::Memory`] where `vec!` would abort the process.
pub fn zeroed_bytes(count: usize, what: &str) -> Result<Vec<u8>, Error> {
    let mut probe: Vec<u8> = Vec::new();
    probe.try_reserve_exact(count).map_err(|_| {
        Error::Memory(format!(
            "{what}: {:.1} GB do not fit in memory",
            count as f64 / 1e9
        ))
    })?;
    drop(probe);
    Ok(vec![0; count])
}

/// `count` zeros to fill, or [`Error::Memory`] where `vec!` would abort the process: a count
/// that overflows, or more memory than the machine will give.
pub fn zeroed_floats(count: usize, what: &str) -> Result<Vec<f32>, Error> {
    let too_much = || {
        Error::Memory(format!(
            "{what}: {count} values ({:.1} GB) do not fit in memory",
            count as f64 * 4.0 / 1e9
        ))
    };
    let bytes = count.checked_mul(4).ok_or_else(too_much)?;
    // More than the machine has is refused whatever the kernel's overcommit setting would say.
    // SAFETY: sysconf only reads system values.
    let (pages, page) = unsafe {
        (
            libc::sysconf(libc::_SC_PHYS_PAGES),
            libc::sysconf(libc::_SC_PAGESIZE),
        )
    };
    if pages > 0 && page > 0 && bytes as u128 > pages as u128 * page as u128 {
        return Err(too_much());
    }
    // Asked first without touching the memory, so that a refusal is an error, not an abort;
    // then `vec!`, which gets zeroed pages from the system without writing them.
    let mut probe: Vec<f32> = Vec::new();
    probe.try_reserve_exact(count).map_err(|_| too_much())?;
    drop(probe);
    Ok(vec![0.0; count])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rates_and_counts_are_refused_past_their_limits() {
        assert!(fps(f64::NAN, false).is_err());
        assert!(fps(1e300, false).is_err());
        assert!(fps(60.0, true).is_err());
        assert_eq!(fps(60.0, false).unwrap(), 60.0);
        // Rates that would make an animation of endless frames: `Frame Time: 1e308`, `--fps 1e300`
        // and `--fps 1e7` on two frames.
        assert!(animation_frames(100, 1e308, 30.0).is_err());
        assert!(animation_frames(100, 0.01, 1e300).is_err());
        assert!(animation_frames(2, 1.0 / 30.0, 1e7).is_err());
        assert_eq!(animation_frames(12, 1.0 / 120.0, 30.0).unwrap(), 3);
        assert!(resampled_frames(1000, 3600.0, 1000.0, 100).is_err());
        assert_eq!(resampled_frames(120, 1.0 / 120.0, 30.0, 100).unwrap(), 30);
        assert!(!frame_time_in_file(1e308));
        assert!(frame_time_in_file(0.0));
        assert!(frame_time_option(Some(0.0)).is_err());
        assert!(name(MAX_NAME_BYTES + 1).is_err());
        assert!(name(MAX_NAME_BYTES).is_ok());
    }

    /// 8,000 frames onto 17,021 joints is refused; a CMU walk onto a 65-joint character is not.
    #[test]
    fn a_retarget_is_held_to_a_multiple_of_its_take() {
        let error = retarget_values("walk.bvh onto big.glb", 8000, 60, 17_021, 51_066).unwrap_err();
        assert_eq!(
            error.to_string(),
            "walk.bvh onto big.glb: 8000 frames onto 17021 joints (51066 channels) make 4.08528e8 \
             values, more than a take of 480000 values is put on a skeleton for (at most \
             3.3771328e7: 32 a value of the take and the target, above 1.6777216e7); trim the \
             take or use a skeleton with fewer joints"
        );
        assert!(retarget_values("x", 4000, 96, 65, 198).is_ok());
        assert!(retarget_values("x", usize::MAX, usize::MAX, 1, usize::MAX).is_err());
    }

    /// 243 GB of matrices is a `MemoryError`, not an abort.
    #[test]
    fn an_allocation_the_machine_cannot_give_is_an_error() {
        let error = zeroed_floats(100_000_000 * 38 * 16, "world_matrices").unwrap_err();
        assert!(matches!(error, Error::Memory(_)), "{error}");
        assert!(zeroed_floats(usize::MAX, "x").is_err());
        assert_eq!(zeroed_floats(3, "x").unwrap(), vec![0.0; 3]);
    }
}
