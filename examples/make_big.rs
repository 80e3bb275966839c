//! Writes a big BVH file by repeating the MOTION rows of a real one, for benchmarks.
//!
//! `cargo run --release --example make_big -- SOURCE.bvh OUT.bvh [MEGABYTES]` (default 100).
//! The hierarchy is copied byte for byte; the rows are repeated in order, each with its trailing
//! blanks and the file's line ending, until the file reaches the size, and `Frames:` is set to the
//! number of rows written.

use std::io::{BufWriter, Write};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        eprintln!("usage: make_big SOURCE.bvh OUT.bvh [MEGABYTES]");
        std::process::exit(2);
    }
    let megabytes: f64 = args.get(3).map_or(Ok(100.0), |s| s.parse())?;
    let text = std::fs::read(&args[1])?;
    // Up to the Frames line, the line with `Frame Time`, then the rows.
    let find = |needle: &[u8], from: usize| {
        text[from..]
            .windows(needle.len())
            .position(|w| w.eq_ignore_ascii_case(needle))
            .map(|i| i + from)
    };
    let motion = find(b"MOTION", 0).ok_or("no MOTION section")?;
    let frames = find(b"Frames", motion).ok_or("no Frames line")?;
    let time = find(b"Frame Time", frames).ok_or("no Frame Time line")?;
    let line_end = |from: usize| {
        text[from..]
            .iter()
            .position(|&b| b == b'\n' || b == b'\r')
            .map_or(text.len(), |i| i + from)
    };
    let newline: &[u8] = if text[line_end(time)..].starts_with(b"\r\n") {
        b"\r\n"
    } else {
        b"\n"
    };
    let rows: Vec<&[u8]> = text[line_end(time)..]
        .split(|&b| b == b'\n' || b == b'\r')
        // A blank after the last number stays: the article's loader needs it (`p += 8`, then
        // on to the next blank, then over CR LF).
        .map(|r| r.trim_ascii_start())
        .filter(|r| !r.trim_ascii().is_empty())
        .collect();
    if rows.is_empty() {
        return Err("no MOTION rows to repeat".into());
    }
    let row_bytes: usize = rows.iter().map(|r| r.len() + newline.len()).sum::<usize>() / rows.len();
    let target = (megabytes * 1e6) as usize;
    let count = target.saturating_sub(time) / row_bytes.max(1) + 1;
    let mut out = BufWriter::with_capacity(1 << 20, std::fs::File::create(&args[2])?);
    out.write_all(&text[..frames])?;
    write!(out, "Frames: {count}")?;
    out.write_all(newline)?;
    out.write_all(&text[time..line_end(time)])?;
    out.write_all(newline)?;
    for i in 0..count {
        out.write_all(rows[i % rows.len()])?;
        out.write_all(newline)?;
    }
    out.flush()?;
    eprintln!("wrote {} with {count} frames", args[2]);
    Ok(())
}
