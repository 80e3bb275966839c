//! glTF 2.0 (`.gltf` with its buffers, or `.glb`) → the same `Skeleton` + `Motion` a BVH loads
//! into. The writer is [`crate::gltf`]; this is the reader beside it.
//!
//! The skeleton is the joints of the file's skins (with the nodes between them), or, in a file
//! without a skin, every animated node (with the nodes between them). Each animation is a take;
//! its frames are sampled at the rate of its keys (the step of evenly spaced keys, else the
//! shortest step between two), every frame interpolated as the
//! file says (`STEP`, `LINEAR` with slerp for rotations, `CUBICSPLINE`), and the world matrices
//! go through [`crate::baked`]. glTF is Y up and in metres, bvhview's own convention: nothing is
//! converted.
//!
//! A file is hostile until read: buffers are taken only from the GLB's own chunk, from `data:`
//! URIs, or from files inside the `.gltf`'s own folder (no absolute path, no `..`, no scheme, no
//! symbolic link out), each no larger than `--max-size` and at least as long as the file says;
//! every accessor's bytes are checked to lie inside its buffer before they are read; the node
//! tree is checked for cycles and shared children.

use crate::baked::{self, Node, Pose};
use crate::error::Error;
use crate::fbx::{Read, TakeInfo, pick_take};
use glam::{DMat4, DQuat, DVec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::animation::{Interpolation, Property};
use std::path::{Path, PathBuf};

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
    if relative.contains(':') || relative.starts_with('/') || relative.starts_with('\\') {
        return refuse("only files beside the glTF, or data: URIs, are read");
    }
    let relative = Path::new(&relative);
    if relative
        .components()
        .any(|c| !matches!(c, std::path::Component::Normal(_)))
    {
        return refuse("a path out of the glTF's folder");
    }
    let folder_real = folder
        .canonicalize()
        .map_err(|e| format!("buffer '{uri}': the glTF's folder: {e}"))?;
    let file = folder.join(relative);
    let real = file
        .canonicalize()
        .map_err(|e| format!("buffer '{uri}': {}", e.kind()))?;
    if !real.starts_with(&folder_real) {
        return refuse("it leads out of the glTF's folder");
    }
    Ok(real)
}

struct File {
    gltf: gltf::Gltf,
    buffers: Vec<Vec<u8>>,
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
    let bytes = crate::read::read_binary_file(path, max_size)?;
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    parse(&bytes, &path.display().to_string(), Some(folder), max_size)
}

/// A glTF or GLB's bytes; buffers in other files only from inside `folder` (none without one).
fn parse(bytes: &[u8], path: &str, folder: Option<&Path>, max_size: u64) -> Result<File, Error> {
    let gltf =
        gltf::Gltf::from_slice(bytes).map_err(|e| bad(path, format!("not a valid glTF ({e})")))?;
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
                crate::read::read_binary_file(&file, max_size)?
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
    Ok(File { gltf, buffers })
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
    times: Vec<f32>,
    /// `width` values per key (three per key for CUBICSPLINE: in-tangent, value, out-tangent).
    values: Vec<f32>,
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

fn tracks(file: &File, animation: &gltf::Animation) -> Result<Vec<Track>, String> {
    let mut tracks = Vec::new();
    for channel in animation.channels() {
        let property = channel.target().property();
        let width = match property {
            Property::Translation | Property::Scale => 3,
            Property::Rotation => 4,
            Property::MorphTargetWeights => continue,
        };
        let sampler = channel.sampler();
        let times = accessor_values(file, &sampler.input(), 1)?;
        let values = accessor_values(file, &sampler.output(), width)?;
        let interpolation = sampler.interpolation();
        let per_key = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        if times.is_empty() || values.len() != times.len() * per_key * width {
            return Err(format!(
                "animation {}: a sampler with {} keys and {} values",
                animation.index(),
                times.len(),
                values.len() / width
            ));
        }
        if times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|p| p[1] < p[0]) {
            return Err(format!(
                "animation {}: key times that are not finite and increasing",
                animation.index()
            ));
        }
        // glTF 2.0 (animation.sampler.input): `time[0] >= 0`, an error for the Khronos validator.
        // A key before 0 is a damaged file; read, it would stretch the take back to it (fuzzing
        // flipped the sign of a 0.5 s take's first key: 495 s, 59,469 frames to evaluate).
        if times[0] < 0.0 {
            return Err(format!(
                "animation {}: a key at {} s, before 0 (glTF's key times start at 0 or later)",
                animation.index(),
                times[0]
            ));
        }
        tracks.push(Track {
            node: channel.target().node().index(),
            property,
            interpolation,
            times,
            values,
            width,
        });
    }
    Ok(tracks)
}

/// The take's start, end and frames per second from its keys.
fn timing(tracks: &[Track]) -> (f64, f64, f64) {
    let mut start = f64::MAX;
    let mut end = f64::MIN;
    let mut step = f64::MAX;
    for track in tracks {
        let n = track.times.len();
        start = start.min(track.times[0] as f64);
        end = end.max(track.times[n - 1] as f64);
        if n > 1 {
            // The mean step of a track whose keys are evenly spaced; otherwise its shortest.
            let mean = (track.times[n - 1] as f64 - track.times[0] as f64) / (n - 1) as f64;
            let even = track
                .times
                .windows(2)
                .all(|p| ((p[1] - p[0]) as f64 - mean).abs() <= 1e-3 * mean);
            let this = if even {
                mean
            } else {
                track
                    .times
                    .windows(2)
                    .map(|p| (p[1] - p[0]) as f64)
                    .filter(|&d| d > 1e-4)
                    .fold(f64::MAX, f64::min)
            };
            if this > 1e-4 {
                step = step.min(this);
            }
        }
    }
    if start > end {
        return (0.0, 0.0, 30.0);
    }
    // The step itself, not a rounded rate: bvhview's own export writes `Frame Time: 0.0083333`
    // as keys 0.0083333 s apart, which are not 1/120 s apart.
    let fps = if step == f64::MAX { 30.0 } else { 1.0 / step };
    (start, end, fps)
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
            let (start, end, fps) = timing(&tracks);
            let frames = baked::frame_count(start, end, fps, 1).map_err(|why| bad(path, why))?;
            Ok(TakeInfo {
                name: animation_name(&animation),
                frames,
                frame_time: 1.0 / fps,
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
            if *d > count || *d > crate::limits::MAX_DEPTH {
                return Err(bad(path, "the node tree has a cycle or nests too deep"));
            }
            up = parent[p];
        }
    }

    let animations: Vec<gltf::Animation> = document.animations().collect();
    let names: Vec<String> = animations.iter().map(animation_name).collect();
    let mut warnings = Vec::new();
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
    let skeleton_nodes = order
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
    let (start, end, fps) = timing(&tracks);
    let (skeleton, motion) = if tracks.is_empty() {
        warnings.push("no animation in the file: its rest pose, as one frame".to_string());
        baked::build(&skeleton_nodes, &rest, 1, 1.0 / fps, |_, out| {
            out.extend_from_slice(&rest);
            Ok(())
        })
    } else {
        let frame_count =
            baked::frame_count(start, end, fps, order.len()).map_err(|why| bad(path, why))?;
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
    }
}
