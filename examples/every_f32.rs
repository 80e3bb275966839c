//! Checks the float text of exports (`export::Shortest`, from zmij) against what `ryu` wrote
//! before (its shortest form, `.0` taken off whole numbers) on every finite f32: 4.3 billion
//! values, minutes in a release build, too slow for the test suite (which checks millions).
//!
//! `cargo run --release --example every_f32` prints the count checked, or the first difference
//! and exits with 1.

use bvhview::positions::Shortest;

fn main() {
    let (mut ours, mut theirs) = (Shortest::default(), ryu::Buffer::new());
    let mut checked = 0u64;
    for bits in 0..=u32::MAX {
        let value = f32::from_bits(bits);
        if !value.is_finite() {
            continue;
        }
        let printed = theirs.format_finite(value);
        let expected = printed.strip_suffix(".0").unwrap_or(printed);
        if ours.format(value) != expected.as_bytes() {
            let got = String::from_utf8_lossy(ours.format(value)).into_owned();
            eprintln!("{value:e} (bits {bits:#010x}): ryu {expected}, Shortest {got}");
            std::process::exit(1);
        }
        checked += 1;
    }
    println!("every finite f32 ({checked}) prints as ryu printed it");
}
