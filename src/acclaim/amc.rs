//! The AMC motion file: a header (`:FULLY-SPECIFIED`, `:DEGREES` or `:RADIANS`), then per frame its
//! number on a line of its own and one line per bone: the name and its dof values in the ASF's
//! order. The ASF/AMC article's `Read_AMC` stops at 5000 frames; here there is no limit, frame
//! numbers must count up by one, and every bone with a dof must appear once per frame.

use super::asf::ValueMap;
use super::text::{LineWords, Word, error_at, expected, expected_at_start, number};
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
    degrees: bool,
    frame_time: f64,
) -> Result<Motion, Error> {
    let mut lines = LineWords::new(text);
    let mut reading = Reading::new(source, maps, channels, degrees);
    while let Some(line) = lines.next_line() {
        reading.line(line)?;
    }
    reading.finish_frame()?;
    Ok(Motion::new(
        frame_time,
        channels,
        reading.frames,
        reading.data,
    ))
}

/// An AMC file as its lines are read: the rows so far, and what the frame being read has given.
struct Reading<'a> {
    source: &'a str,
    maps: &'a [ValueMap],
    channels: usize,
    /// The angle unit: the ASF's, unless a `:RADIANS` or `:DEGREES` line said otherwise.
    degrees: bool,
    data: Vec<f32>,
    frames: usize,
    /// The number of the frame being read, and its line.
    frame_number: Option<(i64, usize)>,
    /// Per map: whether the frame being read has given its line.
    filled: Vec<bool>,
    /// Bone names to maps: one lookup per line, however many bones the skeleton has.
    index: std::collections::HashMap<&'a str, usize>,
    header_seen: bool,
}

impl<'a> Reading<'a> {
    fn new(source: &'a str, maps: &'a [ValueMap], channels: usize, degrees: bool) -> Self {
        Reading {
            source,
            maps,
            channels,
            degrees,
            data: Vec::new(),
            frames: 0,
            frame_number: None,
            filled: vec![false; maps.len()],
            index: maps
                .iter()
                .enumerate()
                .map(|(i, m)| (m.name.as_str(), i))
                .collect(),
            header_seen: false,
        }
    }

    /// One line: a header line, a frame number, or a bone's values in the frame being read.
    fn line(&mut self, line: &[Word<'_>]) -> Result<(), Error> {
        let source = self.source;
        let first = &line[0];
        if first.text.starts_with(':') {
            self.header_seen = true;
            if self.frame_number.is_some() {
                return Err(expected(source, first, "a bone name or a frame number"));
            }
            if first.is(":RADIANS") {
                self.degrees = false;
            } else if first.is(":DEGREES") {
                self.degrees = true;
            }
            return Ok(());
        }
        if line.len() == 1
            && let Ok(n) = first.text.parse::<i64>()
        {
            return self.frame(first, n);
        }
        if self.frame_number.is_none() {
            // Nothing of the file was an AMC's yet: it may not be motion at all, so
            // none of it is quoted.
            if !self.header_seen {
                return Err(expected_at_start(
                    source,
                    first,
                    "a frame number",
                    &[":FULLY-SPECIFIED", ":DEGREES", ":RADIANS"],
                ));
            }
            return Err(expected(source, first, "a frame number"));
        }
        self.bone_line(line)
    }

    /// Checks that the frame just read gave every bone that has values.
    fn finish_frame(&mut self) -> Result<(), Error> {
        if let Some((n, line)) = self.frame_number
            && let Some(missing) = self
                .maps
                .iter()
                .zip(self.filled.iter())
                .find(|(m, f)| !**f && !m.slots.is_empty())
        {
            return Err(error_at(
                self.source,
                line,
                1,
                format!("frame {n} has no line for '{}'", missing.0.name),
            ));
        }
        self.filled.iter_mut().for_each(|f| *f = false);
        Ok(())
    }

    /// Frame number `n` starts a frame: the one before must be complete, and `n` follow its
    /// number.
    fn frame(&mut self, first: &Word<'_>, n: i64) -> Result<(), Error> {
        self.finish_frame()?;
        if let Some((previous, _)) = self.frame_number {
            let next = previous.checked_add(1);
            if next != Some(n) {
                let what = match next {
                    Some(next) => format!("frame number {next}"),
                    None => format!("the end (no frame number follows {previous})"),
                };
                return Err(expected(self.source, first, &what));
            }
        }
        self.frame_number = Some((n, first.line));
        self.frames += 1;
        self.data.resize(self.frames * self.channels, 0.0);
        Ok(())
    }

    /// A bone's line: once a frame, with as many values as it has dofs in the ASF.
    fn bone_line(&mut self, line: &[Word<'_>]) -> Result<(), Error> {
        let (source, maps) = (self.source, self.maps);
        let first = &line[0];
        let Some(bone) = self.index.get(first.text).copied() else {
            return Err(expected(source, first, "a bone of the ASF skeleton"));
        };
        let map = &maps[bone];
        if self.filled[bone] {
            return Err(error_at(
                source,
                first.line,
                first.column,
                format!("'{}' appears twice in this frame", first.text),
            ));
        }
        self.filled[bone] = true;
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
        let row = (self.frames - 1) * self.channels + map.first_channel;
        for ((word, &slot), &rotation) in values.iter().zip(&map.slots).zip(&map.rotations) {
            let value = number(source, word, "a number")?;
            // Rotations in radians become degrees; translations keep their length unit.
            let value = if !self.degrees && rotation {
                value.to_degrees()
            } else {
                value
            };
            let value = value as f32;
            if !value.is_finite() {
                return Err(expected(source, word, "a number a float can hold"));
            }
            self.data[row + slot] = value;
        }
        Ok(())
    }
}
