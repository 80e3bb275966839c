//! The AMC motion file: a header (`:FULLY-SPECIFIED`, `:DEGREES` or `:RADIANS`), then per frame its
//! number on a line of its own and one line per bone: the name and its dof values in the ASF's
//! order. The ASF/AMC article's `Read_AMC` stops at 5000 frames; here there is no limit, frame
//! numbers must count up by one, and every bone with a dof must appear once per frame.

use super::asf::ValueMap;
use super::text::{LineWords, error_at, expected, expected_at_start, number};
use crate::io::error::Error;
use crate::model::motion::Motion;
use std::path::Path;

/// Reads an AMC file into a Motion for the skeleton whose value maps `maps` describe
/// (`channels` columns per frame). `degrees` is the ASF's angle unit, which a `:RADIANS` or
/// `:DEGREES` line in the AMC overrides.
/// Reading stops with an error past `max_size` bytes.
pub fn load_amc(
    path: &Path,
    max_size: u64,
    maps: &[ValueMap],
    channels: usize,
    degrees: bool,
    frame_time: f64,
) -> Result<Motion, Error> {
    let bytes = crate::io::read::read_file(path, max_size)?;
    parse_amc(
        &String::from_utf8_lossy(&bytes),
        &path.display().to_string(),
        maps,
        channels,
        degrees,
        frame_time,
    )
}

/// Parses AMC text; see [`load_amc`].
pub fn parse_amc(
    text: &str,
    source: &str,
    maps: &[ValueMap],
    channels: usize,
    mut degrees: bool,
    frame_time: f64,
) -> Result<Motion, Error> {
    let mut lines = LineWords::new(text);
    let mut data: Vec<f32> = Vec::new();
    let mut frames = 0usize;
    let mut frame_number: Option<(i64, usize)> = None;
    let mut filled = vec![false; maps.len()];
    // Bone names to maps: one lookup per line, however many bones the skeleton has.
    let index: std::collections::HashMap<&str, usize> = maps
        .iter()
        .enumerate()
        .map(|(i, m)| (m.name.as_str(), i))
        .collect();

    // Checks that the frame just read gave every bone that has values.
    let finish = |filled: &mut Vec<bool>, number: Option<(i64, usize)>| -> Result<(), Error> {
        if let Some((n, line)) = number
            && let Some(missing) = maps
                .iter()
                .zip(filled.iter())
                .find(|(m, f)| !**f && !m.slots.is_empty())
        {
            return Err(error_at(
                source,
                line,
                1,
                format!("frame {n} has no line for '{}'", missing.0.name),
            ));
        }
        filled.iter_mut().for_each(|f| *f = false);
        Ok(())
    };

    let mut header_seen = false;
    while let Some(line) = lines.next_line() {
        let first = &line[0];
        if first.text.starts_with(':') {
            header_seen = true;
            if frame_number.is_some() {
                return Err(expected(source, first, "a bone name or a frame number"));
            }
            if first.is(":RADIANS") {
                degrees = false;
            } else if first.is(":DEGREES") {
                degrees = true;
            }
            continue;
        }
        if line.len() == 1
            && let Ok(n) = first.text.parse::<i64>()
        {
            finish(&mut filled, frame_number)?;
            if let Some((previous, _)) = frame_number {
                let next = previous.checked_add(1);
                if next != Some(n) {
                    let what = match next {
                        Some(next) => format!("frame number {next}"),
                        None => format!("the end (no frame number follows {previous})"),
                    };
                    return Err(expected(source, first, &what));
                }
            }
            frame_number = Some((n, first.line));
            frames += 1;
            data.resize(frames * channels, 0.0);
            continue;
        }
        if frame_number.is_none() {
            // Nothing of the file was an AMC's yet: it may not be motion at all, so
            // none of it is quoted.
            if !header_seen {
                return Err(expected_at_start(
                    source,
                    first,
                    "a frame number",
                    &[":FULLY-SPECIFIED", ":DEGREES", ":RADIANS"],
                ));
            }
            return Err(expected(source, first, "a frame number"));
        }
        let Some(bone) = index.get(first.text).copied() else {
            return Err(expected(source, first, "a bone of the ASF skeleton"));
        };
        let map = &maps[bone];
        if filled[bone] {
            return Err(error_at(
                source,
                first.line,
                first.column,
                format!("'{}' appears twice in this frame", first.text),
            ));
        }
        filled[bone] = true;
        let values = &line[1..];
        if values.len() != map.slots.len() {
            let (line_no, column) = values
                .get(map.slots.len())
                .map_or((first.line, first.column), |w| (w.line, w.column));
            return Err(error_at(
                source,
                line_no,
                column,
                format!(
                    "'{}' has {} dof in the ASF, found {}",
                    map.name,
                    map.slots.len(),
                    crate::io::error::counted(values.len(), "value")
                ),
            ));
        }
        let row = (frames - 1) * channels + map.first_channel;
        for ((word, &slot), &rotation) in values.iter().zip(&map.slots).zip(&map.rotations) {
            let value = number(source, word, "a number")?;
            // Rotations in radians become degrees; translations keep their length unit.
            let value = if !degrees && rotation {
                value.to_degrees()
            } else {
                value
            };
            let value = value as f32;
            if !value.is_finite() {
                return Err(expected(source, word, "a number a float can hold"));
            }
            data[row + slot] = value;
        }
    }
    finish(&mut filled, frame_number)?;
    Ok(Motion::new(frame_time, channels, frames, data))
}
