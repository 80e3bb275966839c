//! A glTF file and its buffers: base64 and percent-encoded URIs, buffers only from inside the
//! file's folder, the GLB header, the validation, and accessors decoded once.

use crate::io::error::Error;
use crate::io::message::Message;
use gltf::accessor::{DataType, Dimensions};
use std::path::{Path, PathBuf};

/// A refusal of the file `name`: why, after its name. Here, beside the reading it refuses, so
/// the reader's parts take it from a sibling rather than from the module above.
pub(super) fn bad(name: &str, why: impl std::fmt::Display) -> Error {
    Error::decoding(name, why)
}

/// Decodes standard base64 (with or without padding); `None` on any other byte.
pub(super) fn base64(text: &str) -> Option<Vec<u8>> {
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
pub(super) fn percent_decode(text: &str) -> Option<String> {
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
pub(super) fn buffer_path(folder: &Path, uri: &str) -> Result<PathBuf, String> {
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

pub(super) struct File {
    pub(super) gltf: gltf::Gltf,
    pub(super) buffers: Vec<Vec<u8>>,
    /// Bytes read for it: the file's own and its buffers' (what its budgets are counted from).
    pub(super) bytes: u64,
}

/// Refuses what the gltf crate's accessors would panic on instead of saying so: a value it kept
/// as `Invalid` (an unknown animation path, interpolation, component type or accessor type) and
/// an index past its list, on every path this reader follows (its validation misses some).
pub(super) fn unchecked_values(json: &gltf::json::Root) -> Result<(), String> {
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

/// Every mesh primitive's POSITION accessor exists (gltf-json 1.4.1's validation indexes it
/// unchecked, and panics on a file that names one past the list).
fn positions_in_range(json: &gltf::json::Root) -> Result<(), String> {
    use gltf::json::validation::Checked;
    for (m, mesh) in json.meshes.iter().enumerate() {
        for primitive in &mesh.primitives {
            let position = primitive
                .attributes
                .get(&Checked::Valid(gltf::json::mesh::Semantic::Positions));
            if let Some(accessor) = position
                && accessor.value() >= json.accessors.len()
            {
                return Err(format!(
                    "mesh {m}: a POSITION accessor {} of {}",
                    accessor.value(),
                    json.accessors.len()
                ));
            }
        }
    }
    Ok(())
}

/// The file at `path` and the folder its buffers may come from.
pub(super) fn read(path: &Path, max_size: u64) -> Result<File, Error> {
    let bytes = crate::io::whole::read_binary_file(path, max_size)?;
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    parse(&bytes, &path.display().to_string(), Some(folder), max_size)
}

/// Why a GLB's 12-byte header cannot be, if it cannot: the gltf crate subtracts the header's
/// size from its length field unchecked (a length under 12 overflowed: a panic in a debug
/// build, found by fuzzing on 2026-11-28).
pub(super) fn bad_glb_header(bytes: &[u8]) -> Option<String> {
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
pub(super) const SHOWN_VALIDATION_ERRORS: usize = 3;

/// The gltf crate's refusal as one short line: an extension the file requires and bvhview does
/// not read first (it is the reason), then the first few other validation errors and how many
/// more there are.
pub(super) fn invalid_gltf(error: &gltf::Error) -> String {
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
pub(super) fn parse(
    bytes: &[u8],
    path: &str,
    folder: Option<&Path>,
    max_size: u64,
) -> Result<File, Error> {
    if let Some(why) = bad_glb_header(bytes) {
        return Err(bad(path, why));
    }
    // Parsed, then checked where gltf-json's own validation would index without a check (a
    // primitive's POSITION accessor: fuzzing found that panic), then validated.
    let unvalidated = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| bad(path, invalid_gltf(&e)))?;
    positions_in_range(unvalidated.document.as_json()).map_err(|why| bad(path, why))?;
    let document = gltf::Document::from_json(unvalidated.document.into_json())
        .map_err(|e| bad(path, invalid_gltf(&e)))?;
    let gltf = gltf::Gltf {
        document,
        blob: unvalidated.blob,
    };
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
                let size = payload.len() as u64 / 4 * 3;
                if size > max_size {
                    return Err(Error::Limit {
                        what: "bytes",
                        limit: max_size,
                        found: size,
                        message: Message::from(format!("{path}: a data: URI larger than "))
                            .argument("max_size", None),
                    });
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
                let input = format!("{path}: buffer '{uri}'");
                crate::io::whole::read_file_start(&file, buffer.length() as u64, max_size, &input)?
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

/// Where an accessor's elements lie: its buffer, first byte, stride, component size and count,
/// every byte checked to be inside its view and buffer.
struct Located<'a> {
    buffer: &'a [u8],
    start: usize,
    stride: usize,
    size: usize,
    count: usize,
}

fn locate<'a>(
    file: &'a File,
    accessor: &gltf::Accessor,
    width: usize,
) -> Result<Option<Located<'a>>, String> {
    let index = accessor.index();
    if accessor.sparse().is_some() {
        return Err(format!("accessor {index} is sparse (not read)"));
    }
    let components = match accessor.dimensions() {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        Dimensions::Mat4 => 16,
        other => return Err(format!("accessor {index} is {other:?}, not a vector")),
    };
    if components != width {
        return Err(format!(
            "accessor {index} has {components} components, expected {width}"
        ));
    }
    let count = accessor.count();
    let Some(view) = accessor.view() else {
        return Ok(None);
    };
    let size = match accessor.data_type() {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    };
    let element = size * width;
    let stride = view.stride().unwrap_or(element);
    // A stride shorter than its element makes elements overlap: every vertex after the first
    // read from its neighbour's bytes (glTF 3.6.2.4: byteStride is at least the element's size).
    if stride < element {
        return Err(format!(
            "accessor {index}: its buffer view's byteStride {stride} is shorter than one element \
             ({element} bytes): the elements would overlap"
        ));
    }
    let buffer = &file.buffers[view.buffer().index()];
    let view_end = view.offset().checked_add(view.length());
    let start = view.offset().checked_add(accessor.offset());
    let end = count
        .checked_sub(1)
        .map_or(Some(0), |last| last.checked_mul(stride))
        .and_then(|e| e.checked_add(if count > 0 { element } else { 0 }))
        .and_then(|e| e.checked_add(start?));
    match (start, end, view_end) {
        (Some(start), Some(end), Some(view_end)) if end <= view_end && view_end <= buffer.len() => {
            Ok(Some(Located {
                buffer,
                start,
                stride,
                size,
                count,
            }))
        }
        _ => Err(format!(
            "accessor {index} reaches past its buffer view or buffer"
        )),
    }
}

/// The values of an accessor of unsigned integers (indices, joints), exactly.
pub(super) fn accessor_integers(
    file: &File,
    accessor: &gltf::Accessor,
    width: usize,
) -> Result<Vec<u32>, String> {
    let index = accessor.index();
    if accessor.normalized()
        || !matches!(
            accessor.data_type(),
            DataType::U8 | DataType::U16 | DataType::U32
        )
    {
        return Err(format!(
            "accessor {index} holds {:?}{}, not unsigned integers",
            accessor.data_type(),
            if accessor.normalized() {
                " normalized"
            } else {
                ""
            }
        ));
    }
    let Some(at) = locate(file, accessor, width)? else {
        // No view: all zeros, by the specification.
        return accessor
            .count()
            .checked_mul(width)
            .filter(|&n| n <= 1 << 28)
            .map(|n| vec![0; n])
            .ok_or_else(|| format!("accessor {index} counts {} elements", accessor.count()));
    };
    let mut out = Vec::with_capacity(at.count * width);
    for e in 0..at.count {
        let first = at.start + e * at.stride;
        for c in 0..width {
            let b = &at.buffer[first + c * at.size..first + (c + 1) * at.size];
            out.push(match at.size {
                1 => u32::from(b[0]),
                2 => u32::from(u16::from_le_bytes([b[0], b[1]])),
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            });
        }
    }
    Ok(out)
}

/// The values of an accessor as f32s, `width` per element, every byte checked to be in range.
pub(super) fn accessor_values(
    file: &File,
    accessor: &gltf::Accessor,
    width: usize,
) -> Result<Vec<f32>, String> {
    let index = accessor.index();
    let count = accessor.count();
    let Some(Located {
        buffer,
        start,
        stride,
        size,
        ..
    }) = locate(file, accessor, width)?
    else {
        // No view: all zeros, by the specification.
        return count
            .checked_mul(width)
            .filter(|&n| n <= 1 << 28)
            .map(|n| vec![0.0; n])
            .ok_or_else(|| format!("accessor {index} counts {count} elements"));
    };
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
