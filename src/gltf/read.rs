//! glTF 2.0 (`.gltf` with its buffers, or `.glb`) → the same `Skeleton` + `Motion` a BVH loads
//! into. The writer is [`crate::gltf`]; this is the reader beside it.
//!
//! The skeleton is the joints of the file's skins (with the nodes between them), or, in a file
//! without a skin, every animated node (with the nodes between them). Each animation is a take;
//! its frames are sampled at the rate of its keys (the key step that puts the most keys on a
//! frame, see `timing`; a warning when some keys fall between frames), every frame interpolated
//! as the file says (`STEP`, `LINEAR` with slerp for rotations, `CUBICSPLINE`), and the world
//! matrices go through [`crate::model::baked`]. glTF is Y up and in metres, bvhview's own convention:
//! nothing is converted.
//!
//! A file is hostile until read: buffers are taken only from the GLB's own chunk, from `data:`
//! URIs, or from files inside the `.gltf`'s own folder (no absolute path, no `..`, no scheme, no
//! symbolic link out), each a regular file (a FIFO, device or socket is refused before a read),
//! at least as long as its `byteLength` and read only that far, no longer than `--max-size` and
//! [`crate::io::limits::MAX_WHOLE_FILE_BYTES`]; every accessor's bytes are checked to lie inside its
//! buffer before they are read, and each is decoded once however many channels share it; an
//! animation's channels may ask for [`KEY_VALUES_PER_BYTE`] key values per byte of input, and
//! its frames × (joints + tracks) at most [`baked::FRAME_WORK_PER_BYTE`] per byte (each above
//! a floor), refused past them before the work; a key that is not a finite number is refused
//! by node, key and time; the node tree is checked for cycles and shared children.

use crate::io::error::Error;
use crate::model::baked::{self, Node, Pose};
use crate::model::reading::{Read, TakeInfo, pick_take};
use glam::{DMat4, DQuat, DVec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::animation::{Interpolation, Property};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

fn bad(name: &str, why: impl std::fmt::Display) -> Error {
    Error::Usage(format!("{name}: {why}"))
}

/// Decodes standard base64 (with or without padding); `None` on any other byte.
fn base64(text: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(text.len() / 4 * 3 + 3);
    let (mut bits, mut count) = (0u32, 0u32);
    for byte in text.bytes() {
        let value = match byte {
            b'A'..=b'Z' => byte - b'A',
            b'a'..=b'z' => byte - b'a' + 26,
            b'0'..=b'9' => byte - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            _ => return None,
        };
        bits = (bits << 6) | value as u32;
        count += 6;
        if count >= 8 {
            count -= 8;
            out.push((bits >> count) as u8);
            bits &= (1 << count) - 1;
        }
    }
    Some(out)
}

/// `%20` → space in a relative URI.
fn percent_decode(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The file a relative URI names inside `folder`, or why it is refused.
fn buffer_path(folder: &Path, uri: &str) -> Result<PathBuf, String> {
    let refuse = |why: &str| Err(format!("buffer '{uri}' refused: {why}"));
    let Some(relative) = percent_decode(uri) else {
        return refuse("not a valid URI");
    };
    if relative.is_empty() {
        return refuse("an empty URI names no file");
    }
    if relative.contains(':') || relative.starts_with('/') || relative.starts_with('\\') {
        return refuse("only files beside the glTF, or data: URIs, are read");
    }
    let relative = Path::new(&relative);
    // `./x.bin` is beside the file too; `..`, a root or a prefix leads out.
    if relative.components().any(|c| {
        !matches!(
            c,
            std::path::Component::Normal(_) | std::path::Component::CurDir
        )
    }) {
        return refuse("a path out of the glTF's folder");
    }
    let folder_real = folder
        .canonicalize()
        .map_err(|e| format!("buffer '{uri}': the glTF's folder: {e}"))?;
    let file = folder.join(relative);
    let real = file.canonicalize().map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => format!("buffer '{uri}': no such file beside the glTF"),
        _ => format!("buffer '{uri}': {}", crate::io::error::Error::io(&file, e)),
    })?;
    if !real.starts_with(&folder_real) {
        return refuse("it leads out of the glTF's folder");
    }
    Ok(real)
}

struct File {
    gltf: gltf::Gltf,
    buffers: Vec<Vec<u8>>,
    /// Bytes read for it: the file's own and its buffers' (what its budgets are counted from).
    bytes: u64,
}

/// Refuses what the gltf crate's accessors would panic on instead of saying so: a value it kept
/// as `Invalid` (an unknown animation path, interpolation, component type or accessor type) and
/// an index past its list, on every path this reader follows (its validation misses some).
fn unchecked_values(json: &gltf::json::Root) -> Result<(), String> {
    use gltf::json::validation::Checked;
    let within = |what: &str, index: usize, count: usize| {
        if index < count {
            Ok(())
        } else {
            Err(format!("{what} {index} of {count}"))
        }
    };
    let nodes = json.nodes.len();
    for (a, animation) in json.animations.iter().enumerate() {
        for channel in &animation.channels {
            if matches!(channel.target.path, Checked::Invalid) {
                return Err(format!(
                    "animation {a}: a channel with an unknown target path"
                ));
            }
            within("animation target node", channel.target.node.value(), nodes)?;
            within(
                "animation sampler",
                channel.sampler.value(),
                animation.samplers.len(),
            )?;
        }
        for sampler in &animation.samplers {
            if matches!(sampler.interpolation, Checked::Invalid) {
                return Err(format!("animation {a}: an unknown interpolation"));
            }
            within(
                "sampler input accessor",
                sampler.input.value(),
                json.accessors.len(),
            )?;
            within(
                "sampler output accessor",
                sampler.output.value(),
                json.accessors.len(),
            )?;
        }
    }
    for (i, accessor) in json.accessors.iter().enumerate() {
        if matches!(accessor.component_type, Checked::Invalid)
            || matches!(accessor.type_, Checked::Invalid)
        {
            return Err(format!("accessor {i}: an unknown component type or type"));
        }
        if let Some(view) = accessor.buffer_view {
            within(
                "accessor buffer view",
                view.value(),
                json.buffer_views.len(),
            )?;
        }
    }
    for view in &json.buffer_views {
        within(
            "buffer view buffer",
            view.buffer.value(),
            json.buffers.len(),
        )?;
    }
    for node in &json.nodes {
        for child in node.children.iter().flatten() {
            within("node child", child.value(), nodes)?;
        }
        if let Some(mesh) = node.mesh {
            within("node mesh", mesh.value(), json.meshes.len())?;
        }
        if let Some(camera) = node.camera {
            within("node camera", camera.value(), json.cameras.len())?;
        }
        if let Some(skin) = node.skin {
            within("node skin", skin.value(), json.skins.len())?;
        }
    }
    for skin in &json.skins {
        for joint in &skin.joints {
            within("skin joint", joint.value(), nodes)?;
        }
    }
    Ok(())
}

/// The file at `path` and the folder its buffers may come from.
fn read(path: &Path, max_size: u64) -> Result<File, Error> {
    let bytes = crate::io::read::read_binary_file(path, max_size)?;
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    parse(&bytes, &path.display().to_string(), Some(folder), max_size)
}

/// Why a GLB's 12-byte header cannot be, if it cannot: the gltf crate subtracts the header's
/// size from its length field unchecked (a length under 12 overflowed: a panic in a debug
/// build, found by fuzzing on 2026-11-28).
fn bad_glb_header(bytes: &[u8]) -> Option<String> {
    if !bytes.starts_with(b"glTF") {
        return None;
    }
    let Some(header) = bytes.get(..12) else {
        return Some(format!(
            "a GLB of {} bytes, shorter than its 12-byte header",
            bytes.len()
        ));
    };
    let length = u32::from_le_bytes([header[8], header[9], header[10], header[11]]);
    (length < 12).then(|| {
        format!("a GLB header whose length field ({length}) is shorter than the header itself")
    })
}

/// How many of the gltf crate's validation errors a message lists (a Draco-compressed file
/// gives one per accessor and attribute: thousands of characters on one line).
const SHOWN_VALIDATION_ERRORS: usize = 3;

/// The gltf crate's refusal as one short line: an extension the file requires and bvhview does
/// not read first (it is the reason), then the first few other validation errors and how many
/// more there are.
fn invalid_gltf(error: &gltf::Error) -> String {
    let gltf::Error::Validation(errors) = error else {
        return format!("not a valid glTF ({error})");
    };
    let (required, other): (Vec<_>, Vec<_>) = errors
        .iter()
        .partition(|(_, e)| matches!(e, gltf::json::validation::Error::Unsupported));
    let mut errors = required;
    errors.extend(other);
    let shown: Vec<String> = errors
        .iter()
        .take(SHOWN_VALIDATION_ERRORS)
        .map(|(path, e)| format!("{path}: {e}"))
        .collect();
    let more = errors.len().saturating_sub(SHOWN_VALIDATION_ERRORS);
    let more = match more {
        0 => String::new(),
        n => format!("; and {n} more"),
    };
    format!("not a valid glTF ({}{more})", shown.join("; "))
}

/// A glTF or GLB's bytes; buffers in other files only from inside `folder` (none without one).
fn parse(bytes: &[u8], path: &str, folder: Option<&Path>, max_size: u64) -> Result<File, Error> {
    if let Some(why) = bad_glb_header(bytes) {
        return Err(bad(path, why));
    }
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| bad(path, invalid_gltf(&e)))?;
    unchecked_values(gltf.document.as_json()).map_err(|why| bad(path, why))?;
    let mut buffers = Vec::new();
    for buffer in gltf.document.buffers() {
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| bad(path, "a buffer in the GLB's binary chunk, which it lacks"))?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                let Some((_, payload)) = uri.split_once(";base64,") else {
                    return Err(bad(path, "a data: URI that is not base64"));
                };
                if payload.len() as u64 / 4 * 3 > max_size {
                    return Err(bad(path, "a data: URI larger than --max-size"));
                }
                base64(payload)
                    .ok_or_else(|| bad(path, "a data: URI with bytes that are not base64"))?
            }
            gltf::buffer::Source::Uri(uri) => {
                let Some(folder) = folder else {
                    let why = format!("buffer '{uri}' refused: no folder to read it from");
                    return Err(bad(path, why));
                };
                let file = buffer_path(folder, uri).map_err(|why| bad(path, why))?;
                // Only the buffer's byteLength is read (what lies past it is never used), from a
                // regular file only: a FIFO, a device or a socket is refused before a read.
                crate::io::read::read_file_start(&file, buffer.length() as u64, max_size)
                    .map_err(|why| bad(path, format!("buffer '{uri}': {why}")))?
            }
        };
        if data.len() < buffer.length() {
            return Err(bad(
                path,
                format!(
                    "buffer {} holds {} bytes, fewer than its byteLength {}",
                    buffer.index(),
                    data.len(),
                    buffer.length()
                ),
            ));
        }
        buffers.push(data);
    }
    let bytes = buffers.iter().fold(bytes.len() as u64, |sum, b| {
        sum.saturating_add(b.len() as u64)
    });
    Ok(File {
        gltf,
        buffers,
        bytes,
    })
}

/// The values of an accessor as f32s, `width` per element, every byte checked to be in range.
fn accessor_values(
    file: &File,
    accessor: &gltf::Accessor,
    width: usize,
) -> Result<Vec<f32>, String> {
    let index = accessor.index();
    if accessor.sparse().is_some() {
        return Err(format!("accessor {index} is sparse (not read)"));
    }
    let components = match accessor.dimensions() {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        other => return Err(format!("accessor {index} is {other:?}, not a vector")),
    };
    if components != width {
        return Err(format!(
            "accessor {index} has {components} components, expected {width}"
        ));
    }
    let count = accessor.count();
    let Some(view) = accessor.view() else {
        // No view: all zeros, by the specification.
        return count
            .checked_mul(width)
            .filter(|&n| n <= 1 << 28)
            .map(|n| vec![0.0; n])
            .ok_or_else(|| format!("accessor {index} counts {count} elements"));
    };
    let size = match accessor.data_type() {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    };
    let element = size * width;
    let stride = view.stride().unwrap_or(element);
    let buffer = &file.buffers[view.buffer().index()];
    let view_end = view.offset().checked_add(view.length());
    let start = view.offset().checked_add(accessor.offset());
    let end = count
        .checked_sub(1)
        .map_or(Some(0), |last| last.checked_mul(stride))
        .and_then(|e| e.checked_add(if count > 0 { element } else { 0 }))
        .and_then(|e| e.checked_add(start?));
    match (start, end, view_end) {
        (Some(_), Some(end), Some(view_end)) if end <= view_end && view_end <= buffer.len() => {}
        _ => {
            return Err(format!(
                "accessor {index} reaches past its buffer view or buffer"
            ));
        }
    }
    let start = start.unwrap_or(0);
    let normalized = accessor.normalized();
    let mut out = Vec::with_capacity(count * width);
    for e in 0..count {
        let at = start + e * stride;
        for c in 0..width {
            let b = &buffer[at + c * size..at + c * size + size];
            let value = match accessor.data_type() {
                DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                DataType::I8 => {
                    let v = b[0] as i8 as f32;
                    if normalized { (v / 127.0).max(-1.0) } else { v }
                }
                DataType::U8 => {
                    let v = b[0] as f32;
                    if normalized { v / 255.0 } else { v }
                }
                DataType::I16 => {
                    let v = i16::from_le_bytes([b[0], b[1]]) as f32;
                    if normalized {
                        (v / 32767.0).max(-1.0)
                    } else {
                        v
                    }
                }
                DataType::U16 => {
                    let v = u16::from_le_bytes([b[0], b[1]]) as f32;
                    if normalized { v / 65535.0 } else { v }
                }
                DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
            };
            out.push(value);
        }
    }
    Ok(out)
}

/// One animated property of one node, read.
struct Track {
    node: usize,
    property: Property,
    interpolation: Interpolation,
    /// Key times, shared by every track whose sampler reads the same accessor.
    times: Rc<Vec<f32>>,
    /// `width` values per key (three per key for CUBICSPLINE: in-tangent, value, out-tangent),
    /// shared likewise.
    values: Rc<Vec<f32>>,
    width: usize,
}

impl Track {
    /// The value at `time`, `width` numbers. `hint` is the key found by the call before, where
    /// the search for this one starts: frames are sampled in order, so the key is that one or
    /// a little after it, and a take is read in one pass over each track's keys.
    fn sample(&self, time: f64, hint: &mut usize, out: &mut [f64]) {
        let w = self.width;
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let value = |k: usize, i: usize| -> f64 {
            let at = if cubic { (3 * k + 1) * w } else { k * w };
            self.values[at + i] as f64
        };
        let n = self.times.len();
        let t = |k: usize| self.times[k] as f64;
        if time <= t(0) || n == 1 {
            (0..w).for_each(|i| out[i] = value(0, i));
            return;
        }
        if time >= t(n - 1) {
            (0..w).for_each(|i| out[i] = value(n - 1, i));
            return;
        }
        // The last key at or before `time` (n − 2 at most): from the hint on where it is not
        // past `time`, else by a binary search.
        let mut k = (*hint).min(n - 2);
        if t(k) <= time {
            while k < n - 2 && t(k + 1) <= time {
                k += 1;
            }
        } else {
            k = self
                .times
                .partition_point(|&x| (x as f64) <= time)
                .saturating_sub(1)
                .min(n - 2);
        }
        *hint = k;
        let (t0, t1) = (t(k), t(k + 1));
        let dt = t1 - t0;
        let s = if dt > 0.0 {
            ((time - t0) / dt).clamp(0.0, 1.0)
        } else {
            0.0
        };
        match self.interpolation {
            Interpolation::Step => (0..w).for_each(|i| out[i] = value(k, i)),
            Interpolation::Linear if self.property == Property::Rotation => {
                let q =
                    |k: usize| DQuat::from_xyzw(value(k, 0), value(k, 1), value(k, 2), value(k, 3));
                let r = q(k).slerp(q(k + 1), s);
                out[..4].copy_from_slice(&r.to_array());
            }
            Interpolation::Linear => {
                (0..w).for_each(|i| out[i] = value(k, i) * (1.0 - s) + value(k + 1, i) * s)
            }
            Interpolation::CubicSpline => {
                let (s2, s3) = (s * s, s * s * s);
                let (h00, h10, h01, h11) = (
                    2.0 * s3 - 3.0 * s2 + 1.0,
                    s3 - 2.0 * s2 + s,
                    -2.0 * s3 + 3.0 * s2,
                    s3 - s2,
                );
                for (i, o) in out.iter_mut().enumerate().take(w) {
                    let out_tangent = self.values[(3 * k + 2) * w + i] as f64;
                    let in_tangent = self.values[(3 * (k + 1)) * w + i] as f64;
                    *o = h00 * value(k, i)
                        + h10 * dt * out_tangent
                        + h01 * value(k + 1, i)
                        + h11 * dt * in_tangent;
                }
            }
        }
    }
}

/// Key values (times and outputs, each key's numbers) that one byte of input may ask the
/// channels of an animation to read, above [`KEY_VALUES_FLOOR`]. A channel of its own stores each
/// key in at least 4 bytes; channels that share a sampler read its keys again, each (3,600
/// channels on one sampler of 56,000 keys: 1e9 values from a 437 KB file).
pub const KEY_VALUES_PER_BYTE: u64 = 16;

/// Key values any file may ask for, whatever its size.
pub const KEY_VALUES_FLOOR: u64 = 1 << 20;

/// The values of accessor `index` as f32s, `width` per element, decoded once per reader and
/// shared by every channel that reads it.
type Decoded = HashMap<(usize, usize), Rc<Vec<f32>>>;

fn decoded(
    file: &File,
    cache: &mut Decoded,
    accessor: &gltf::Accessor,
    width: usize,
) -> Result<Rc<Vec<f32>>, String> {
    let key = (accessor.index(), width);
    if let Some(values) = cache.get(&key) {
        return Ok(values.clone());
    }
    let values = Rc::new(accessor_values(file, accessor, width)?);
    cache.insert(key, values.clone());
    Ok(values)
}

/// The name a message gives node `index`: `node 3 'Hips'`.
fn node_label(document: &gltf::Document, index: usize) -> String {
    match document.nodes().nth(index).and_then(|n| n.name()) {
        Some(name) => format!("node {index} '{}'", crate::io::limits::quoted(name)),
        None => format!("node {index}"),
    }
}

fn tracks(file: &File, animation: &gltf::Animation) -> Result<Vec<Track>, String> {
    let a = animation.index();
    // The budget first, from the accessors' counts alone: nothing is decoded for a file that
    // asks for more than its size allows.
    let mut asked: u64 = 0;
    for channel in animation.channels() {
        let width = match channel.target().property() {
            Property::Translation | Property::Scale => 3,
            Property::Rotation => 4,
            Property::MorphTargetWeights => continue,
        };
        let sampler = channel.sampler();
        let keys = sampler.input().count() as u64;
        let outputs = (sampler.output().count() as u64).saturating_mul(width);
        asked = asked.saturating_add(keys.saturating_add(outputs));
    }
    let budget = KEY_VALUES_FLOOR.saturating_add(KEY_VALUES_PER_BYTE.saturating_mul(file.bytes));
    if asked > budget {
        return Err(format!(
            "animation {a}: its {} channels ask for {} key values (keys × channels), more than \
             a file of {} bytes is read for ({budget}: {KEY_VALUES_PER_BYTE} a byte); refused as \
             damaged or hostile",
            animation.channels().count(),
            crate::io::limits::show(asked as f64),
            file.bytes
        ));
    }
    let document = &file.gltf.document;
    let mut cache = Decoded::new();
    // Input accessors whose times were checked, and output accessors whose values were.
    let mut times_checked = std::collections::HashSet::new();
    let mut values_checked = std::collections::HashSet::new();
    let mut tracks = Vec::new();
    for channel in animation.channels() {
        let property = channel.target().property();
        let width = match property {
            Property::Translation | Property::Scale => 3,
            Property::Rotation => 4,
            Property::MorphTargetWeights => continue,
        };
        let sampler = channel.sampler();
        let times = decoded(file, &mut cache, &sampler.input(), 1)?;
        let values = decoded(file, &mut cache, &sampler.output(), width)?;
        let interpolation = sampler.interpolation();
        let per_key = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        if times.is_empty() || values.len() != times.len() * per_key * width {
            return Err(format!(
                "animation {a}: a sampler with {} keys and {} values",
                times.len(),
                values.len() / width
            ));
        }
        if times_checked.insert(sampler.input().index()) {
            if times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|p| p[1] < p[0]) {
                return Err(format!(
                    "animation {a}: key times that are not finite and increasing"
                ));
            }
            // glTF 2.0 (animation.sampler.input): `time[0] >= 0`, an error for the Khronos
            // validator. A key before 0 is a damaged file; read, it would stretch the take back
            // to it (fuzzing flipped the sign of a 0.5 s take's first key: 495 s, 59,469 frames
            // to evaluate).
            if times[0] < 0.0 {
                return Err(format!(
                    "animation {a}: a key at {} s, before 0 (glTF's key times start at 0 or later)",
                    times[0]
                ));
            }
        }
        // A key that is not a number is refused, as a translation's always was by the take's
        // final check; a rotation's was read as no rotation.
        let node = channel.target().node().index();
        if values_checked.insert((sampler.output().index(), sampler.input().index()))
            && let Some(at) = crate::edit::first_non_finite(&values)
        {
            let key = at / width / per_key;
            let what = match property {
                Property::Translation => "translation",
                Property::Rotation => "rotation",
                _ => "scale",
            };
            return Err(format!(
                "animation {a}: {}: {what} key {key} (at {} s) is not a finite number",
                node_label(document, node),
                crate::io::limits::brief(times[key.min(times.len() - 1)] as f64)
            ));
        }
        tracks.push(Track {
            node,
            property,
            interpolation,
            times,
            values,
            width,
        });
    }
    Ok(tracks)
}

/// Common frame rates: a rate found from key steps within [`SNAP`] of one is taken as it.
const COMMON_RATES: [f64; 24] = [
    10.0,
    12.0,
    15.0,
    20.0,
    24000.0 / 1001.0,
    24.0,
    25.0,
    30000.0 / 1001.0,
    30.0,
    48.0,
    50.0,
    60000.0 / 1001.0,
    60.0,
    72.0,
    90.0,
    100.0,
    120.0,
    144.0,
    180.0,
    200.0,
    240.0,
    250.0,
    480.0,
    1000.0,
];

/// How near (relative) a measured rate must be to a common one to be taken as it: 1e-6, the
/// spread of key times written as f32 at a rate, and less than bvhview's own BVH-to-glTF steps
/// are from a common rate (`Frame Time: 0.0083333` is 4e-6 from 1/120 s; kept as written, so
/// that sampling at its step lands on its keys).
const SNAP: f64 = 1e-6;

/// Gaps within this (relative) of the shortest of their group are one step.
const SAME_STEP: f64 = 5e-3;

/// How many of the most common steps are tried as the take's step.
const CANDIDATES: usize = 8;

/// A take's sampling: its start and end, the frames per second, and what is said about them.
struct Timing {
    start: f64,
    end: f64,
    fps: f64,
    warning: Option<String>,
}

/// How many of `times` (each list once) fall on a frame of `step` seconds from `start`: within
/// `slack` seconds, or the rounding of an f32 time.
fn on_frames(times: &[&[f32]], start: f64, step: f64, slack: f64) -> usize {
    times
        .iter()
        .flat_map(|list| list.iter())
        .filter(|&&t| {
            let since = t as f64 - start;
            let frames = since / step;
            let slack = slack.max(4.0 * f32::EPSILON as f64 * (t as f64).abs());
            (frames - frames.round()).abs() * step <= slack
        })
        .count()
}

/// The take's start, end and frame rate from its keys.
///
/// The rate is found from the **key steps** of all the take's tracks (each input accessor
/// once): every gap between two keys (gaps under a microsecond, repeated keys, left out) is
/// grouped with the gaps within 0.5 % of it; the [`CANDIDATES`] largest groups are tried, each
/// at the mean of its gaps (a rate within 1e-6 of a common rate, 24, 30000/1001, 30, 60, 120 …,
/// taken as that rate); the step that puts the most keys on a frame wins, the longer step on a
/// tie. So one odd key (a key 1.5 ms after a take at 30 fps) does not set the rate, nor do the
/// long gaps of tracks with a key at each end only. When keys fall between the frames of the
/// chosen rate, the take is still sampled at it (between keys as the file interpolates) and a
/// warning says how many do not fit. A rate past [`crate::io::limits::MAX_FPS`] (keys 0.5 ms apart)
/// is sampled at 1000 fps with a warning, and one below [`crate::io::limits::MIN_FPS`] at that: a
/// file is never refused for a rate it does not state.
fn timing(tracks: &[Track]) -> Timing {
    let mut start = f64::MAX;
    let mut end = f64::MIN;
    let mut seen: std::collections::HashSet<*const Vec<f32>> = Default::default();
    let mut lists: Vec<&[f32]> = Vec::new();
    for track in tracks {
        let n = track.times.len();
        start = start.min(track.times[0] as f64);
        end = end.max(track.times[n - 1] as f64);
        // Tracks sharing one input accessor count its keys once.
        if seen.insert(Rc::as_ptr(&track.times)) {
            lists.push(&track.times);
        }
    }
    let mut gaps: Vec<f64> = lists
        .iter()
        .flat_map(|list| list.windows(2).map(|p| p[1] as f64 - p[0] as f64))
        .filter(|&d| d > 1e-6)
        .collect();
    if start > end || gaps.is_empty() {
        return Timing {
            start: if start > end { 0.0 } else { start },
            end: if start > end { 0.0 } else { end },
            fps: 30.0,
            warning: None,
        };
    }
    gaps.sort_by(f64::total_cmp);
    // Groups of gaps within SAME_STEP of the group's shortest: (count, mean).
    let mut groups: Vec<(usize, f64)> = Vec::new();
    let mut i = 0;
    while i < gaps.len() {
        let first = gaps[i];
        let mut j = i;
        let mut sum = 0.0;
        while j < gaps.len() && gaps[j] <= first * (1.0 + SAME_STEP) {
            sum += gaps[j];
            j += 1;
        }
        groups.push((j - i, sum / (j - i) as f64));
        i = j;
    }
    groups.sort_by(|a, b| b.0.cmp(&a.0).then(b.1.total_cmp(&a.1)));
    let keys: usize = lists.iter().map(|l| l.len()).sum();
    // A key fits a frame within a hundredth of the shortest step tried (a hundredth of the
    // step itself would let a step of minutes fit every key of its first seconds).
    let slack = 0.01
        * groups
            .iter()
            .take(CANDIDATES)
            .map(|g| g.1)
            .fold(f64::MAX, f64::min);
    let (mut step, mut fitting) = (groups[0].1, 0usize);
    for &(_, mean) in groups.iter().take(CANDIDATES) {
        let snapped = COMMON_RATES
            .iter()
            .find(|&&rate| (rate * mean - 1.0).abs() <= SNAP)
            .map_or(mean, |rate| 1.0 / rate);
        let fit = on_frames(&lists, start, snapped, slack);
        if fit > fitting || (fit == fitting && snapped > step) {
            (step, fitting) = (snapped, fit);
        }
    }
    let mut fps = COMMON_RATES
        .iter()
        .copied()
        .find(|&rate| (rate * step - 1.0).abs() <= SNAP)
        .unwrap_or(1.0 / step);
    let mut notes = Vec::new();
    if fps > crate::io::limits::MAX_FPS {
        notes.push(format!(
            "its keys are {} ms apart ({} fps); sampled at {} fps, the fastest bvhview reads",
            crate::io::limits::brief(1e3 * step),
            crate::io::limits::brief((fps * 10.0).round() / 10.0),
            crate::io::limits::MAX_FPS
        ));
        fps = crate::io::limits::MAX_FPS;
        fitting = keys;
    } else if fps < crate::io::limits::MIN_FPS {
        notes.push(format!(
            "its keys are {} s apart; sampled at {} fps, the slowest bvhview reads",
            crate::io::limits::brief(step),
            crate::io::limits::MIN_FPS
        ));
        fps = crate::io::limits::MIN_FPS;
        fitting = keys;
    }
    if fitting < keys {
        notes.push(format!(
            "{} of {keys} key times do not fall on a frame at {} fps (the key step that fits \
             the most keys); frames are sampled at that rate, between keys as the file \
             interpolates",
            keys - fitting,
            crate::io::limits::brief(fps)
        ));
    }
    Timing {
        start,
        end,
        fps,
        warning: (!notes.is_empty()).then(|| notes.join("; ")),
    }
}

/// The frames of a take of `joints` joints and `tracks` tracks sampled as `timing` says, or why
/// not: past [`baked::frame_count`]'s limits, or more frames × (nodes + tracks) than the file's
/// size allows ([`baked::FRAME_WORK_PER_BYTE`] a byte above [`baked::FRAME_WORK_FLOOR`]), where
/// `nodes` are the nodes posed in each frame: the joints and every node above them (a joint
/// under a chain of 999 nodes costs 1000 products a frame).
fn frames_within(
    timing: &Timing,
    joints: usize,
    nodes: usize,
    tracks: usize,
    bytes: u64,
) -> Result<usize, String> {
    let frames = baked::frame_count(timing.start, timing.end, timing.fps, joints)?;
    let nodes = nodes.max(joints);
    let work = (frames as u64).saturating_mul((nodes + tracks) as u64);
    let budget = baked::frame_work_budget(bytes);
    if work > budget {
        return Err(format!(
            "the take lasts {} s at {} fps: {} of {}{} and {}, more than a file of {bytes} \
             bytes is read for (frames × (nodes + tracks) at most {}, {} a byte); refused as \
             damaged or hostile",
            crate::io::limits::brief(timing.end - timing.start),
            crate::io::limits::brief(timing.fps),
            crate::io::error::counted(frames, "frame"),
            crate::io::error::counted(joints, "joint"),
            if nodes > joints {
                format!(" ({nodes} nodes with those above them)")
            } else {
                String::new()
            },
            crate::io::error::counted(tracks, "track"),
            budget,
            baked::FRAME_WORK_PER_BYTE
        ));
    }
    Ok(frames)
}

fn animation_name(animation: &gltf::Animation) -> String {
    animation
        .name()
        .map(str::to_string)
        .unwrap_or_else(|| format!("animation{}", animation.index()))
}

/// The takes of a glTF file (its animations), in file order.
pub fn takes(path: &Path, max_size: u64) -> Result<Vec<TakeInfo>, Error> {
    let file = read(path, max_size)?;
    let path = &path.display().to_string();
    file.gltf
        .document
        .animations()
        .map(|animation| {
            let tracks = tracks(&file, &animation).map_err(|why| bad(path, why))?;
            let timing = timing(&tracks);
            let joints = tracks
                .iter()
                .map(|t| t.node)
                .collect::<std::collections::HashSet<_>>()
                .len();
            let frames = frames_within(&timing, joints, joints, tracks.len(), file.bytes)
                .map_err(|why| bad(path, why))?;
            Ok(TakeInfo {
                name: animation_name(&animation),
                frames,
                frame_time: 1.0 / timing.fps,
            })
        })
        .collect()
}

/// `q` normalized; the identity when it has no length (or is not finite).
fn unit(q: DQuat) -> DQuat {
    let length = q.length();
    if length.is_finite() && length > 1e-12 {
        q / length
    } else {
        DQuat::IDENTITY
    }
}

/// Local translation, rotation, scale of every node (its static transform).
type Trs = (DVec3, DQuat, DVec3);

fn trs_matrix(trs: &Trs) -> DMat4 {
    DMat4::from_scale_rotation_translation(trs.2, trs.1, trs.0)
}

/// Reads take `take` (an animation's name or index; the first when `None`) of the glTF at `path`.
pub fn load(path: &Path, max_size: u64, take: Option<&str>) -> Result<Read, Error> {
    let file = read(path, max_size)?;
    load_file(&file, &path.display().to_string(), take)
}

/// [`load`] of a GLB's or glTF's bytes alone (buffers inside it or in data: URIs), `name`
/// naming it in errors (the fuzz target's entry).
pub fn load_bytes(bytes: &[u8], name: &str, take: Option<&str>) -> Result<Read, Error> {
    let file = parse(bytes, name, None, bytes.len() as u64)?;
    load_file(&file, name, take)
}

fn load_file(file: &File, path: &str, take: Option<&str>) -> Result<Read, Error> {
    let document = &file.gltf.document;
    let count = document.nodes().len();
    // Parents, refusing shared children and cycles.
    let mut parent = vec![None; count];
    for node in document.nodes() {
        for child in node.children() {
            let c = child.index();
            if parent[c].is_some() || c == node.index() {
                return Err(bad(path, format!("node {c} has more than one parent")));
            }
            parent[c] = Some(node.index());
        }
    }
    let mut depth = vec![0usize; count];
    for (i, d) in depth.iter_mut().enumerate() {
        let mut up = parent[i];
        while let Some(p) = up {
            *d += 1;
            if *d > count || *d > crate::io::limits::MAX_DEPTH {
                return Err(bad(path, "the node tree has a cycle or nests too deep"));
            }
            up = parent[p];
        }
    }

    let animations: Vec<gltf::Animation> = document.animations().collect();
    let names: Vec<String> = animations.iter().map(animation_name).collect();
    let mut warnings = Vec::new();
    let mut take_name = None;
    let chosen = if animations.is_empty() {
        if take.is_some() {
            pick_take(&names, take, path)?;
        }
        None
    } else {
        let index = pick_take(&names, take, path)?;
        if take.is_none() && names.len() > 1 {
            warnings.push(format!(
                "{} takes; reading take 0 '{}' (--take NAME|INDEX picks another; `bvhview info` \
                 lists them)",
                names.len(),
                names[0]
            ));
        }
        take_name = Some(names[index].clone());
        Some(&animations[index])
    };
    let tracks = match chosen {
        Some(animation) => tracks(file, animation).map_err(|why| bad(path, why))?,
        None => Vec::new(),
    };

    // The skeleton: skin joints, else every node any animation moves; and the nodes between.
    let mut seed = vec![false; count];
    for skin in document.skins() {
        for joint in skin.joints() {
            seed[joint.index()] = true;
        }
    }
    if !seed.iter().any(|&s| s) {
        for animation in &animations {
            for channel in animation.channels() {
                if channel.target().property() != Property::MorphTargetWeights {
                    seed[channel.target().node().index()] = true;
                }
            }
        }
    }
    // No skin and no animation, and nothing but nodes (a rest pose as bvhview writes one, from a
    // take of 0 frames): the tree is the skeleton, its bare leaves End Sites (issue 44: bvhview
    // could not read back its own output).
    let bare = document.meshes().len() == 0 && document.cameras().len() == 0;
    if !seed.iter().any(|&s| s) && animations.is_empty() && bare {
        for node in document.nodes() {
            seed[node.index()] = node.children().len() > 0 || parent[node.index()].is_none();
        }
    }
    let mut selected = seed.clone();
    for i in 0..count {
        if !seed[i] {
            continue;
        }
        let mut between = Vec::new();
        let mut up = parent[i];
        while let Some(p) = up {
            if seed[p] {
                for &b in &between {
                    selected[b] = true;
                }
                break;
            }
            between.push(p);
            up = parent[p];
        }
    }
    // A bare leaf under a joint (no mesh, no camera, no children: an end point, as bvhview's
    // own export writes a BVH's End Sites) joins as an End Site.
    let nodes: Vec<gltf::Node> = document.nodes().collect();
    for node in &nodes {
        let i = node.index();
        if !selected[i]
            && parent[i].is_some_and(|p| selected[p])
            && node.children().len() == 0
            && node.mesh().is_none()
            && node.camera().is_none()
        {
            selected[i] = true;
        }
    }
    let mut order: Vec<usize> = (0..count).filter(|&i| selected[i]).collect();
    if order.is_empty() {
        return Err(bad(
            path,
            "no skeleton: the file has no skin and no animated node",
        ));
    }
    order.sort_by_key(|&i| depth[i]);
    let mut position = vec![usize::MAX; count];
    for (k, &i) in order.iter().enumerate() {
        position[i] = k;
    }
    let mut skeleton_nodes = order
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            let mut up = parent[i];
            let mut joint_parent = None;
            while let Some(p) = up {
                if position[p] != usize::MAX {
                    joint_parent = Some(position[p]);
                    break;
                }
                up = parent[p];
            }
            let name = nodes[i].name().unwrap_or("");
            Ok(Node {
                name: baked::joint_name(name, k).map_err(|why| bad(path, why))?,
                parent: joint_parent,
            })
        })
        .collect::<Result<Vec<Node>, Error>>()?;
    warnings.extend(baked::unique_names(&mut skeleton_nodes));

    // Static transforms.
    let statics: Vec<Trs> = nodes
        .iter()
        .map(|node| {
            let (t, r, s) = node.transform().decomposed();
            let r = DQuat::from_xyzw(r[0] as f64, r[1] as f64, r[2] as f64, r[3] as f64);
            (
                DVec3::from(t.map(|v| v as f64)),
                unit(r),
                DVec3::from(s.map(|v| v as f64)),
            )
        })
        .collect();
    let static_matrices: Vec<DMat4> = nodes
        .iter()
        .map(|node| {
            let m = node.transform().matrix();
            DMat4::from_cols_array_2d(&m.map(|c| c.map(|v| v as f64)))
        })
        .collect();
    // World matrices of the selected nodes, from local matrices of all nodes.
    let world_of = |local: &dyn Fn(usize) -> DMat4| -> Vec<Pose> {
        let mut cache: Vec<Option<DMat4>> = vec![None; count];
        let mut out = Vec::with_capacity(order.len());
        for &i in &order {
            let mut chain = Vec::new();
            let mut up = Some(i);
            while let Some(n) = up {
                if cache[n].is_some() {
                    break;
                }
                chain.push(n);
                up = parent[n];
            }
            for &n in chain.iter().rev() {
                let above = parent[n].and_then(|p| cache[p]).unwrap_or(DMat4::IDENTITY);
                cache[n] = Some(above * local(n));
            }
            out.push(Pose::of_matrix(&cache[i].unwrap_or(DMat4::IDENTITY)));
        }
        out
    };
    let rest = world_of(&|n| static_matrices[n]);
    let timing = timing(&tracks);
    let (start, fps) = (timing.start, timing.fps);
    if let Some(warning) = &timing.warning {
        warnings.push(warning.clone());
    }
    let (skeleton, motion) = if tracks.is_empty() {
        warnings.push("no animation in the file: its rest pose, as one frame".to_string());
        baked::build(&skeleton_nodes, &rest, 1, 1.0 / fps, |_, out| {
            out.extend_from_slice(&rest);
            Ok(())
        })
    } else {
        // The nodes posed in each frame: the joints and every node above them.
        let mut posed = vec![false; count];
        for &i in &order {
            let mut up = Some(i);
            while let Some(n) = up.filter(|&n| !posed[n]) {
                posed[n] = true;
                up = parent[n];
            }
        }
        let nodes = posed.iter().filter(|&&p| p).count();
        let frame_count = frames_within(&timing, order.len(), nodes, tracks.len(), file.bytes)
            .map_err(|why| bad(path, why))?;
        let mut animated: Vec<Option<Trs>> = vec![None; count];
        let mut sample = [0.0f64; 4];
        let mut hints = vec![0usize; tracks.len()];
        baked::build(&skeleton_nodes, &rest, frame_count, 1.0 / fps, |f, out| {
            let time = start + f as f64 / fps;
            for slot in animated.iter_mut() {
                *slot = None;
            }
            for (track, hint) in tracks.iter().zip(hints.iter_mut()) {
                let trs = animated[track.node].get_or_insert(statics[track.node]);
                track.sample(time, hint, &mut sample);
                match track.property {
                    Property::Translation => trs.0 = DVec3::new(sample[0], sample[1], sample[2]),
                    Property::Scale => trs.2 = DVec3::new(sample[0], sample[1], sample[2]),
                    Property::Rotation => {
                        trs.1 = unit(DQuat::from_xyzw(sample[0], sample[1], sample[2], sample[3]))
                    }
                    Property::MorphTargetWeights => {}
                }
            }
            out.extend(world_of(&|n| match &animated[n] {
                Some(trs) => trs_matrix(trs),
                None => static_matrices[n],
            }));
            Ok(())
        })
    }
    .map_err(|e| match e {
        Error::Usage(message) if !message.starts_with(path) => bad(path, message),
        other => other,
    })?;
    Ok(Read {
        skeleton,
        motion,
        warnings,
        take: take_name,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes() {
        assert_eq!(base64("aGVsbG8=").unwrap(), b"hello");
        assert_eq!(base64("aGVsbG8").unwrap(), b"hello");
        assert!(base64("a$").is_none());
    }

    fn keyed(times: Vec<f32>) -> Track {
        let values = Rc::new(vec![0.0; 3 * times.len()]);
        Track {
            node: 0,
            property: Property::Translation,
            interpolation: Interpolation::Linear,
            times: Rc::new(times),
            values,
            width: 3,
        }
    }

    /// The rate is the key step that puts the most keys on a frame, snapped to a common rate;
    /// what does not fit is said; nothing is refused for a rate.
    #[test]
    fn the_rate_is_the_key_step_that_fits_the_most_keys() {
        let at = |rate: f32, n: usize| (0..n).map(|k| k as f32 / rate).collect::<Vec<f32>>();
        // Every frame of 30 fps: 30, no warning.
        let even = timing(&[keyed(at(30.0, 61))]);
        assert_eq!((even.fps, even.warning.is_none()), (30.0, true));
        // One odd key 1.5 ms after the last: still 30, said.
        let mut times = at(30.0, 31);
        times.push(1.0015);
        let odd = timing(&[keyed(times)]);
        assert_eq!(odd.fps, 30.0);
        assert!(odd.warning.unwrap().starts_with("1 of 32 key times"));
        // A track at 60 fps beside one at 30: every key is on a frame of 60.
        let both = timing(&[keyed(at(30.0, 61)), keyed(at(60.0, 121))]);
        assert_eq!((both.fps, both.warning.is_none()), (60.0, true));
        // Twenty tracks keyed at their ends only do not outvote one keyed at every frame.
        let mut tracks: Vec<Track> = (0..20).map(|_| keyed(vec![0.0, 2.0])).collect();
        tracks.push(keyed(at(30.0, 61)));
        assert_eq!(timing(&tracks).fps, 30.0);
        // Keys 0.5 ms apart: 1000 fps, said.
        let fast = timing(&[keyed((0..100).map(|k| k as f32 * 5e-4).collect())]);
        assert_eq!(fast.fps, 1000.0);
        assert!(
            fast.warning
                .unwrap()
                .contains("(2000 fps); sampled at 1000 fps")
        );
        // bvhview's own `Frame Time: 0.0083333` keys keep their step (not 1/120 s).
        let own = timing(&[keyed((0..200).map(|k| k as f32 * 0.0083333).collect())]);
        assert!((1.0 / own.fps - 0.0083333).abs() < 1e-9, "{}", own.fps);
    }

    #[test]
    fn buffer_paths_stay_in_the_folder() {
        let folder = std::env::temp_dir();
        for uri in [
            "/etc/passwd",
            "../x.bin",
            "http://host/x.bin",
            "a/../../x",
            "file:///x",
        ] {
            assert!(buffer_path(&folder, uri).is_err(), "{uri}");
        }
        // Issue 44: `./x.bin` is beside the file; an empty URI and a missing file say so.
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("x.bin"), [0u8; 4]).unwrap();
        assert!(buffer_path(dir.path(), "./x.bin").is_ok());
        let empty = buffer_path(dir.path(), "").unwrap_err();
        assert!(empty.contains("an empty URI names no file"), "{empty}");
        let missing = buffer_path(dir.path(), "y.bin").unwrap_err();
        assert_eq!(missing, "buffer 'y.bin': no such file beside the glTF");
    }
}
