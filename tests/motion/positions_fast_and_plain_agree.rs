//! The positions export exists twice: `export::write_positions_plain`, the plain
//! formatter, and `write_positions`, the fast one the CLI runs. Both must write the same bytes
//! (or refuse with the same error) for every file of the repository, the rest pose, ASF/AMC,
//! generated names and values, CSV and JSON, with every option. And the float text both use
//! (`export::Shortest`, from zmij) must be what `ryu` wrote before: on millions of values here,
//! on every f32 with `cargo run --release --example every_f32`.

use crate::common;
use bvhview::model::motion::Motion;
use bvhview::model::pose::OffsetMode;
use bvhview::model::skeleton::Skeleton;
use bvhview::positions::{
    PositionsFormat, PositionsOptions, Shortest, write_positions, write_positions_plain,
};
use common::*;
use std::ops::Range;

/// The text exports had with ryu: its shortest form without `.0` on whole numbers.
fn ryu_text(value: f32) -> String {
    let mut buffer = ryu::Buffer::new();
    let printed = buffer.format_finite(value);
    printed.strip_suffix(".0").unwrap_or(printed).to_string()
}

fn same_as_ryu(shortest: &mut Shortest, value: f32) {
    if !value.is_finite() {
        return;
    }
    let ours = shortest.format(value);
    assert_eq!(
        std::str::from_utf8(ours).unwrap(),
        ryu_text(value),
        "{value:e} (bits {:#010x})",
        value.to_bits()
    );
}

/// A small, fixed pseudo-random sequence (xorshift64*), so a failure repeats.
fn bits(seed: u64) -> impl Iterator<Item = u32> {
    let mut state = seed;
    std::iter::repeat_with(move || {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 32) as u32
    })
}

#[test]
fn shortest_float_text_is_ryus_on_edges_random_bits_and_a_sweep_of_every_exponent() {
    let mut shortest = Shortest::default();
    let edges = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        30.0,
        -30.0,
        100000.0,
        1e7,
        16777216.0,
        1e-7,
        -1e-7,
        1e-5,
        0.000001,
        9.999999e-7,
        0.1,
        0.3,
        1e12,
        9999999e6,
        1e13,
        -1e13,
        1e16,
        1e20,
        f32::MAX,
        f32::MIN,
        f32::MIN_POSITIVE,
        -f32::MIN_POSITIVE,
        f32::from_bits(1),
        f32::from_bits(0x8000_0001),
        f32::from_bits(0x007f_ffff),
        f32::EPSILON,
    ];
    for value in edges {
        same_as_ryu(&mut shortest, value);
    }
    // Every exponent and sign, the mantissas spread (a step that is odd and not a power of 2).
    for b in (0..=u32::MAX).step_by(4099) {
        same_as_ryu(&mut shortest, f32::from_bits(b));
    }
    // Random bit patterns, and random values in the range positions have.
    for b in bits(0x9e37_79b9_7f4a_7c15).take(2_000_000) {
        same_as_ryu(&mut shortest, f32::from_bits(b));
        same_as_ryu(&mut shortest, (b as i32) as f32 / 65536.0);
    }
    // Both sides of where the exponent form starts (1e13) and of the smallest plain decimal.
    for start in [1e13f32, 1e-6, 1e-5, 1e16] {
        let b = start.to_bits();
        for b in b - 2000..b + 2000 {
            same_as_ryu(&mut shortest, f32::from_bits(b));
            same_as_ryu(&mut shortest, -f32::from_bits(b));
        }
    }
}

/// The bytes (or the error) of one export, fast or plain.
fn export(
    skeleton: &Skeleton,
    motion: &Motion,
    frames: Range<usize>,
    options: &PositionsOptions,
    fast: bool,
) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let result = match fast {
        true => write_positions(&mut out, skeleton, motion, frames, options),
        false => write_positions_plain(&mut out, skeleton, motion, frames, options),
    };
    result.map(|()| out).map_err(|e| e.to_string())
}

/// Every option on `skeleton` + `motion`, over short frame ranges (the first frames, a run
/// that crosses the FK's batches of eight, the last frame): both formats, scales (one that
/// overflows), handedness and offset modes; then every frame as CSV and as JSON.
fn same_both_ways(what: &str, skeleton: &Skeleton, motion: &Motion) {
    let count = motion.frame_count().max(1);
    let mut ranges = vec![0..count.min(9), count - 1..count];
    if count > 20 {
        ranges.push(3..count.min(30) - 1);
    }
    for format in [PositionsFormat::Csv, PositionsFormat::Json] {
        for scale in [1.0, 0.01, -2.5, 3e37] {
            for left_handed in [false, true] {
                for offset_mode in [OffsetMode::Replace, OffsetMode::Add] {
                    let options = PositionsOptions {
                        format,
                        offset_mode,
                        left_handed,
                        scale,
                    };
                    for frames in &ranges {
                        compare(what, skeleton, motion, frames.clone(), &options);
                    }
                }
            }
        }
        let options = PositionsOptions {
            format,
            ..Default::default()
        };
        compare(what, skeleton, motion, 0..count, &options);
    }
}

fn compare(
    what: &str,
    skeleton: &Skeleton,
    motion: &Motion,
    frames: Range<usize>,
    options: &PositionsOptions,
) {
    let plain = export(skeleton, motion, frames.clone(), options, false);
    let fast = export(skeleton, motion, frames.clone(), options, true);
    if plain != fast {
        let shown = |r: &Result<Vec<u8>, String>| match r {
            Ok(bytes) => String::from_utf8_lossy(bytes).into_owned(),
            Err(e) => format!("error: {e}"),
        };
        let (plain, fast) = (shown(&plain), shown(&fast));
        let at = (plain.bytes().zip(fast.bytes()))
            .position(|(a, b)| a != b)
            .unwrap_or(plain.len().min(fast.len()));
        let from = at.saturating_sub(200);
        panic!(
            "{what}: {options:?}, frames {frames:?}: differ at byte {at}\n\
             plain: …{}\nfast:  …{}",
            &plain[from..(at + 100).min(plain.len())],
            &fast[from..(at + 100).min(fast.len())]
        );
    }
}

#[test]
fn fast_and_plain_write_the_same_bytes_for_every_repository_file() {
    for path in files_in(&repo_data("bvh"), "bvh") {
        let bvh = load_path(&path);
        same_both_ways(&path.display().to_string(), &bvh.skeleton, &bvh.motion);
    }
}

#[test]
fn fast_and_plain_write_the_same_bytes_for_asf_amc_and_the_rest_pose() {
    let asf = repo_data("asf_amc/heiden_12.asf");
    let amc = repo_data("asf_amc/heiden_12_02_01.amc");
    let loaded = crate::common::load_take(&asf, Some(&amc), None).unwrap();
    same_both_ways("heiden_12", &loaded.skeleton, &loaded.motion);
    let rest = crate::common::load_take(&asf, None, None).unwrap();
    same_both_ways("heiden_12 rest", &rest.skeleton, &rest.motion);
    let bvh = load_path(&edge("frames_zero.bvh"));
    assert_eq!(bvh.motion.frame_count(), 0);
    same_both_ways("frames_zero", &bvh.skeleton, &bvh.motion);
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn fast_and_plain_write_the_same_bytes_for_every_corpus_take() {
    for path in files_in(&shared_data("bvh"), "bvh") {
        let bvh = load_path(&path);
        same_both_ways(&path.display().to_string(), &bvh.skeleton, &bvh.motion);
    }
    let folder = shared_data("asf_amc");
    for amc in files_in(&folder, "amc") {
        let name = amc.file_stem().unwrap().to_string_lossy().into_owned();
        // A take is named after its skeleton: `heiden_12_02_01`, `simchoni_lambada_1`.
        let asf = files_in(&folder, "asf")
            .into_iter()
            .filter(|asf| name.starts_with(&*asf.file_stem().unwrap().to_string_lossy()))
            .max_by_key(|asf| asf.as_os_str().len())
            .unwrap_or_else(|| panic!("no skeleton for {name}"));
        let loaded = crate::common::load_take(&asf, Some(&amc), None).unwrap();
        same_both_ways(&name, &loaded.skeleton, &loaded.motion);
    }
}

/// Names that CSV quotes, names longer than the fast path's short moves, values that print
/// with exponents both ways, negative zero, and joints where their parent is.
#[test]
fn fast_and_plain_write_the_same_bytes_for_generated_names_and_values() {
    let long = "L".repeat(40);
    let text = format!(
        "HIERARCHY\nROOT a,\"b\"\n{{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition \
         Zrotation Xrotation Yrotation\n JOINT {long}\n {{\n  OFFSET 0 0 0\n  CHANNELS 3 \
         Zrotation Xrotation Yrotation\n  JOINT c\n  {{\n   OFFSET 1e-7 -0 2.5\n   CHANNELS 3 \
         Zrotation Xrotation Yrotation\n   End Site\n   {{\n    OFFSET 0 0 0\n   }}\n  }}\n }}\n \
         JOINT d\n {{\n  OFFSET 1e20 30 -1e-30\n  End Site\n  {{\n   OFFSET 0 1 0\n  }}\n }}\n}}\n\
         MOTION\nFrames: 40\nFrame Time: 0.1\n"
    );
    let mut text = text;
    for (i, b) in bits(7).take(40).enumerate() {
        let angle = |k: u32| ((b >> k) % 360) as f32;
        let zero = if i % 3 == 0 { 0.0 } else { angle(3) };
        text.push_str(&format!(
            "{} {} -0 {zero} {} {} 0 0 0 {} {} {}\n",
            (b as i32) as f32 / 1e3,
            1e15 * (b % 7) as f32,
            angle(1),
            angle(2),
            angle(4),
            angle(5),
            angle(6)
        ));
    }
    let bvh = load_text(&text).unwrap();
    same_both_ways("generated", &bvh.skeleton, &bvh.motion);
}
