//! Reading joint positions: a NumPy `.npy` array of frames × joints × 3 (float32 or float64,
//! either byte order, C or Fortran order, as numpy writes them; read by the `npyz` crate), or
//! the CSV `bvhview positions` writes (`frame,joint,x,y,z`, a row per joint and frame).

use super::positions::{Positions, SMPL22_ORDER};
use crate::io::error::{Error, quoted};
use crate::io::message::Message;
use glam::DVec3;
use std::path::Path;

/// The joint names `spec` gives: a layout's (`smpl22`, or `humanml3d`, the same order), or
/// names separated by commas.
///
/// ```
/// let names = bvhview::solve::joint_names("humanml3d");
/// assert_eq!((names.len(), names[1].as_str()), (22, "left_hip"));
/// assert_eq!(bvhview::solve::joint_names("Hips, LeftUpLeg"), ["Hips", "LeftUpLeg"]);
/// ```
pub fn joint_names(spec: &str) -> Vec<String> {
    match spec.trim().to_ascii_lowercase().as_str() {
        "smpl22" | "humanml3d" | "smpl" => SMPL22_ORDER.iter().map(|n| n.to_string()).collect(),
        _ => spec
            .split(',')
            .map(|n| n.trim().to_string())
            .filter(|n| !n.is_empty())
            .collect(),
    }
}

/// The positions in `path` (`.npy` or `.csv`), `frame_time` seconds apart. An `.npy` holds no
/// names: `joints` gives them ([`joint_names`]), and 22 joints without it are read in SMPL's
/// order, which the second value says; a CSV names its own and `joints` is refused with it.
pub fn read_positions(
    path: &Path,
    joints: Option<&str>,
    frame_time: f64,
    max_size: u64,
) -> Result<(Positions, Option<Message>), Error> {
    let shown = path.display().to_string();
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match extension.as_str() {
        "npy" => {
            let bytes = read_npy_file(path, max_size)?;
            let (joint_count, points) = read_npy(&bytes, &shown)?;
            let (names, note) = match joints {
                Some(spec) => (joint_names(spec), None),
                None if joint_count == 22 => (
                    joint_names("smpl22"),
                    Some(
                        Message::from(format!(
                            "{shown}: 22 unnamed joints read in SMPL's order (pelvis, left_hip, \
                             right_hip, …; "
                        ))
                        .argument("joints", None)
                        .text(" names them otherwise)"),
                    ),
                ),
                None => {
                    return Err(Error::usage(
                        Message::from(format!(
                            "{shown}: {joint_count} unnamed joints a frame: name them in order \
                             with "
                        ))
                        .argument("joints", Some("A,B,…"))
                        .text(" (or ")
                        .argument("joints", Some("smpl22"))
                        .text(" for SMPL's 22)"),
                    ));
                }
            };
            if names.len() != joint_count {
                return Err(Error::usage(
                    Message::from(format!("{shown}: {joint_count} joints a frame, and "))
                        .argument("joints", None)
                        .text(format!(" names {}", names.len())),
                ));
            }
            let positions =
                Positions::new(names, points, frame_time).map_err(|e| e.about(&shown))?;
            Ok((positions, note))
        }
        "csv" => {
            if joints.is_some() {
                return Err(Error::usage(
                    Message::from(format!("{shown}: a CSV names its joints; "))
                        .argument("joints", None)
                        .text(" is for an .npy"),
                ));
            }
            // Read whole, as an .npy is: a regular file only (a FIFO would wait for a writer),
            // within the same budget, and only once its first line is the header.
            let bytes =
                crate::io::whole::read_binary_file_checked(path, max_size, 32, |start, _| {
                    match start.starts_with(CSV_HEADER.as_bytes()) {
                        true => Ok(()),
                        false => Err(Error::usage(format!("{shown}:1: {}", no_csv_header()))),
                    }
                })?;
            let text = std::str::from_utf8(&bytes)
                .map_err(|_| Error::usage(format!("{shown}: not UTF-8 text")))?;
            let (names, points) = read_csv(text, &shown)?;
            let positions =
                Positions::new(names, points, frame_time).map_err(|e| e.about(&shown))?;
            Ok((positions, None))
        }
        _ => Err(Error::usage(format!(
            "{shown}: positions are read from .npy (frames × joints × 3) or the .csv `bvhview \
             positions` writes"
        ))),
    }
}

/// The most bytes an `.npy`'s header may take. numpy's own reader refuses more than 10,000;
/// a version-1 header takes at most 65,535, and past that a header is damage (a length of
/// 0xFFFFFFF0 would ask for 4 GB).
pub const MAX_NPY_HEADER_BYTES: u64 = 65_535;

/// The bytes an `.npy`'s magic, version and header length take in version 2 and 3 (10 in 1).
const NPY_PREFIX_BYTES: u64 = 12;

/// Where the data of an `.npy` of `size` bytes that begins with `start` starts (after its
/// header), or why it is not an `.npy` bvhview reads: no magic, a version numpy does not
/// write, a header longer than [`MAX_NPY_HEADER_BYTES`] or than the file.
fn npy_data_start(start: &[u8], size: u64) -> Result<u64, String> {
    if !start.starts_with(b"\x93NUMPY") {
        return Err("not an .npy array (it does not begin with numpy's \\x93NUMPY)".into());
    }
    let (length, prefix) = match (start.get(6), start.get(7)) {
        (Some(1), Some(0)) => (
            start
                .get(8..10)
                .map(|b| u64::from(u16::from_le_bytes([b[0], b[1]]))),
            10,
        ),
        (Some(2 | 3), Some(0)) => (
            start
                .get(8..12)
                .map(|b| u64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))),
            12,
        ),
        (Some(major), Some(minor)) => {
            return Err(format!(
                "an .npy of version {major}.{minor}; numpy writes versions 1.0, 2.0 and 3.0"
            ));
        }
        _ => (None, 0),
    };
    let Some(length) = length else {
        return Err(format!("{size} bytes: shorter than an .npy header"));
    };
    if length > MAX_NPY_HEADER_BYTES {
        return Err(format!(
            "its .npy header claims {length} bytes, more than the {MAX_NPY_HEADER_BYTES} \
             bvhview reads (the file is damaged)"
        ));
    }
    if prefix + length > size {
        return Err(format!(
            "its .npy header claims {length} bytes, and {} follow in the file",
            size.saturating_sub(prefix)
        ));
    }
    Ok(prefix + length)
}

/// The whole of the `.npy` at `path`, read only after its magic and header length are found
/// sound (`npy_data_start`) and the file within `max_size`: neither a file of something
/// else nor a damaged header makes bvhview read (or ask for) more than the file's first bytes.
pub fn read_npy_file(path: &Path, max_size: u64) -> Result<Vec<u8>, Error> {
    crate::io::whole::read_binary_file_checked(path, max_size, NPY_PREFIX_BYTES, |start, size| {
        npy_data_start(start, size)
            .map(|_| ())
            .map_err(|why| Error::decoding(path.display(), why))
    })
}

/// The deepest an `.npy`'s header may nest brackets. numpy writes a dict holding a tuple (2
/// levels) for the arrays bvhview reads, and a structured dtype's list of tuples of shapes in
/// 4; the Python-literal parser npyz uses takes three times longer with each level of `{`
/// (12 took 28 s in a debug build; the fuzzer's had 20), so a deeper header is refused before
/// it is parsed.
pub const MAX_NPY_HEADER_NESTING: usize = 4;

/// How deep `header`'s brackets (`(`, `[`, `{`) nest, those in quoted strings aside.
fn nesting(header: &[u8]) -> usize {
    let (mut depth, mut deepest) = (0usize, 0usize);
    let mut quote: Option<u8> = None;
    let mut escaped = false;
    for &b in header {
        match quote {
            Some(_) if escaped => escaped = false,
            Some(_) if b == b'\\' => escaped = true,
            Some(q) if b == q => quote = None,
            Some(_) => {}
            None => match b {
                b'\'' | b'"' => quote = Some(b),
                b'(' | b'[' | b'{' => {
                    depth += 1;
                    deepest = deepest.max(depth);
                }
                b')' | b']' | b'}' => depth = depth.saturating_sub(1),
                _ => {}
            },
        }
    }
    deepest
}

/// The bytes of magic, version and length before an `.npy` header's text (10 in version 1).
fn prefix_of(bytes: &[u8]) -> usize {
    match bytes.get(6) {
        Some(1) => 10,
        _ => 12,
    }
}

/// The shape a header's text gives, when its dimensions other than 0 multiply past a 64-bit
/// count: npyz multiplies them (the count and each stride) unchecked, a panic where overflow is
/// checked. The text is read by npyz's own parser (`py_literal`), so the shape is the one npyz
/// would see; what that parser refuses is left to npyz to tell.
fn overflowing_shape(text: &[u8]) -> Option<Vec<u64>> {
    let text = std::str::from_utf8(text).ok()?;
    let text = text.strip_suffix('\n').unwrap_or(text);
    let py_literal::Value::Dict(entries) = text.parse::<py_literal::Value>().ok()? else {
        return None;
    };
    let shape = entries.iter().find_map(|(key, value)| match (key, value) {
        (py_literal::Value::String(key), py_literal::Value::Tuple(dims))
        | (py_literal::Value::String(key), py_literal::Value::List(dims))
            if key == "shape" =>
        {
            Some(dims)
        }
        _ => None,
    })?;
    let shape: Vec<u64> = shape
        .iter()
        .map(|dim| match dim {
            py_literal::Value::Integer(n) => u64::try_from(n).ok(),
            _ => None,
        })
        .collect::<Option<_>>()?;
    let fits = shape
        .iter()
        .filter(|&&d| d != 0)
        .try_fold(1u64, |count, &d| count.checked_mul(d))
        .is_some();
    (!fits).then_some(shape)
}

/// `bytes`, an `.npy`, opened by npyz once its header is found sound (`npy_data_start`):
/// the file, where its data starts and the bytes each value takes (float32 and float64 only).
fn open_npy<'a>(
    bytes: &'a [u8],
    shown: &str,
) -> Result<(npyz::NpyFile<&'a [u8]>, u64, u64), Error> {
    let refuse = |why: String| Error::decoding(shown, why);
    let (file, start) = open_npy_any(bytes, shown)?;
    let width = match file.dtype() {
        npyz::DType::Plain(kind)
            if kind.type_char() == npyz::TypeChar::Float && matches!(kind.size_field(), 4 | 8) =>
        {
            kind.size_field()
        }
        other => {
            return Err(refuse(format!(
                "dtype {}: not supported; bvhview reads float32 and float64 (<f4, >f4, <f8, >f8)",
                quoted(other.descr().trim_matches('\''))
            )));
        }
    };
    Ok((file, start, width))
}

/// An array of an `.npy` as bvhview reads any (an `.npz`'s member): its shape and values as
/// numbers (floats, integers and booleans, in C order), as text (numpy's `U` and `S` strings),
/// or only its dtype — anything else, an object array above all: a pickle, never loaded.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum NpyArray {
    Numbers {
        shape: Vec<usize>,
        values: Vec<f64>,
    },
    Text {
        shape: Vec<usize>,
        values: Vec<String>,
    },
    Other {
        dtype: String,
    },
}

/// [`NpyArray`] of `bytes`, an `.npy`, its header found sound and its data checked to hold every
/// value its shape says before one is read.
pub(crate) fn npy_array(bytes: &[u8], shown: &str) -> Result<NpyArray, Error> {
    let refuse = |why: String| Error::decoding(shown, why);
    let (file, start) = open_npy_any(bytes, shown)?;
    let npyz::DType::Plain(kind) = file.dtype() else {
        return Ok(NpyArray::Other {
            dtype: file.dtype().descr(),
        });
    };
    let shape: Vec<u64> = file.shape().to_vec();
    use npyz::TypeChar as T;
    // A `U` string's size counts code points, four bytes each.
    let size = match kind.type_char() {
        T::UnicodeStr => kind.size_field().saturating_mul(4),
        _ => kind.size_field(),
    };
    let data = &bytes[start as usize..];
    let count = shape
        .iter()
        .try_fold(1u64, |n, &d| n.checked_mul(d))
        .filter(|&n| n.checked_mul(size).is_some_and(|b| b <= data.len() as u64))
        .ok_or_else(|| {
            refuse(format!(
                "shape {shape:?} of {size}-byte values: more than the file's {} bytes of data \
                 hold",
                data.len()
            ))
        })? as usize;
    let fortran = file.order() == npyz::Order::Fortran;
    let dims: Vec<usize> = shape.iter().map(|&d| d as usize).collect();
    let big = kind.endianness() == npyz::Endianness::Big;
    let size = size as usize;
    let cells = || data[..count * size].chunks_exact(size.max(1));
    let numbers: Option<Vec<f64>> = match (kind.type_char(), size) {
        (T::Float, 4) => Some(
            cells()
                .map(|c| f64::from(f32::from_bits(word(c, big) as u32)))
                .collect(),
        ),
        (T::Float, 8) => Some(cells().map(|c| f64::from_bits(word(c, big))).collect()),
        (T::Int, 1 | 2 | 4 | 8) => Some(
            cells()
                .map(|c| {
                    let shift = 64 - 8 * c.len() as u32;
                    (((word(c, big) << shift) as i64) >> shift) as f64
                })
                .collect(),
        ),
        (T::Uint | T::Bool, 1 | 2 | 4 | 8) => Some(cells().map(|c| word(c, big) as f64).collect()),
        _ => None,
    };
    if let Some(values) = numbers {
        return Ok(NpyArray::Numbers {
            values: in_c_order(values, &dims, fortran),
            shape: dims,
        });
    }
    let text: Option<Vec<String>> = match kind.type_char() {
        T::ByteStr => Some(
            cells()
                .map(|c| {
                    let end = c.iter().rposition(|&b| b != 0).map_or(0, |e| e + 1);
                    String::from_utf8_lossy(&c[..end]).into_owned()
                })
                .collect(),
        ),
        T::UnicodeStr => Some(
            cells()
                .map(|c| {
                    c.chunks_exact(4)
                        .map(|unit| word(unit, big) as u32)
                        .take_while(|&unit| unit != 0)
                        .map(|unit| char::from_u32(unit).unwrap_or('\u{fffd}'))
                        .collect()
                })
                .collect(),
        ),
        _ => None,
    };
    Ok(match text {
        Some(values) => NpyArray::Text {
            values: in_c_order(values, &dims, fortran),
            shape: dims,
        },
        None => NpyArray::Other {
            dtype: kind.to_string(),
        },
    })
}

/// The unsigned number of `bytes` (at most 8), little- or big-endian.
fn word(bytes: &[u8], big: bool) -> u64 {
    let mut value = 0u64;
    for k in 0..bytes.len() {
        let b = if big {
            bytes[k]
        } else {
            bytes[bytes.len() - 1 - k]
        };
        value = (value << 8) | u64::from(b);
    }
    value
}

/// `values` of an array of shape `dims` in C order (the last index fastest), from Fortran order
/// (the first fastest) when `fortran`.
fn in_c_order<V: Clone>(values: Vec<V>, dims: &[usize], fortran: bool) -> Vec<V> {
    if !fortran || dims.len() < 2 {
        return values;
    }
    let count = values.len();
    let mut index = vec![0usize; dims.len()];
    (0..count)
        .map(|_| {
            // The Fortran position of the C-order index, then the next C-order index.
            let mut at = 0;
            for d in (0..dims.len()).rev() {
                at = at * dims[d] + index[d];
            }
            for d in (0..dims.len()).rev() {
                index[d] += 1;
                if index[d] < dims[d] {
                    break;
                }
                index[d] = 0;
            }
            values[at].clone()
        })
        .collect()
}

/// `bytes`, an `.npy` of any dtype, opened by npyz once its header is found sound: the file and
/// where its data starts.
fn open_npy_any<'a>(bytes: &'a [u8], shown: &str) -> Result<(npyz::NpyFile<&'a [u8]>, u64), Error> {
    let refuse = |why: String| Error::decoding(shown, why);
    let start = npy_data_start(bytes, bytes.len() as u64).map_err(refuse)?;
    // The header's text: after the magic, the version and its length (whose bytes may be any).
    let header = bytes
        .get(prefix_of(bytes)..start as usize)
        .unwrap_or_default();
    let depth = nesting(header);
    if depth > MAX_NPY_HEADER_NESTING {
        return Err(refuse(format!(
            "its .npy header nests brackets {depth} deep; an array's header nests at most \
             {MAX_NPY_HEADER_NESTING} (the file is damaged)"
        )));
    }
    if let Some(shape) = overflowing_shape(header) {
        return Err(refuse(format!(
            "shape {shape:?}: more values than a 64-bit count holds (the file is damaged)"
        )));
    }
    let file = npyz::NpyFile::new(bytes)
        .map_err(|e| refuse(format!("not an .npy array: {}", npy_error(&e))))?;
    Ok((file, start))
}

/// npyz's error in one line: a header that is not a Python dict is told by its parser in
/// several (the header again, a caret under the fault); its place and what it expected are
/// what is kept.
fn npy_error(error: &std::io::Error) -> String {
    let text = error.to_string();
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let first = lines.first().copied().unwrap_or("");
    let said = match first.split_once("-->") {
        Some((what, at)) => {
            let expected = lines.iter().find_map(|l| l.strip_prefix("= "));
            let what = what.trim_end().trim_end_matches(':');
            match expected {
                Some(expected) => format!("its header: {what} at {} ({expected})", at.trim()),
                None => format!("its header: {what} at {}", at.trim()),
            }
        }
        None => first.to_string(),
    };
    // A message is one line of sane length, whatever the header held.
    match said.char_indices().nth(200) {
        Some((cut, _)) => format!("{}…", &said[..cut]),
        None => said,
    }
}

/// An `.npy` of frames × joints × 3 (or joints × 3: one frame): the joints a frame and every
/// position, frame after frame.
pub fn read_npy(bytes: &[u8], shown: &str) -> Result<(usize, Vec<DVec3>), Error> {
    let refuse = |why: String| Error::decoding(shown, why);
    let (file, start, width) = open_npy(bytes, shown)?;
    let shape: Vec<u64> = file.shape().to_vec();
    let (frames, joints) = match shape[..] {
        [frames, joints, 3] => (frames, joints),
        [joints, 3] => (1, joints),
        _ => {
            return Err(refuse(format!(
                "shape {shape:?}: expected frames × joints × 3"
            )));
        }
    };
    // Checked before anything is read: a header may promise more than the file holds.
    let data_bytes = (bytes.len() as u64).saturating_sub(start);
    let count = frames
        .checked_mul(joints)
        .and_then(|n| n.checked_mul(3))
        .filter(|&n| n.saturating_mul(width) <= data_bytes)
        .ok_or_else(|| {
            refuse(format!(
                "shape {shape:?} of {width}-byte values: more than the file's {data_bytes} bytes \
                 of data hold"
            ))
        })?;
    if frames == 0 || joints == 0 {
        return Err(refuse(format!("shape {shape:?}: no positions")));
    }
    let fortran = file.order() == npyz::Order::Fortran;
    let values = numbers(file, shown)?;
    if values.len() as u64 != count {
        return Err(refuse(format!(
            "{} values for shape {shape:?}",
            values.len()
        )));
    }
    let (frames, joints) = (frames as usize, joints as usize);
    let value = |f: usize, j: usize, c: usize| match fortran {
        false => values[(f * joints + j) * 3 + c],
        true => values[f + frames * (j + joints * c)],
    };
    let points = (0..frames)
        .flat_map(|f| (0..joints).map(move |j| (f, j)))
        .map(|(f, j)| DVec3::new(value(f, j, 0), value(f, j, 1), value(f, j, 2)))
        .collect();
    Ok((joints, points))
}

/// An `.npy` of rows of `width` values each (frames × width; HumanML3D's feature vectors), as
/// numbers: the rows and the values, row after row.
pub fn read_npy_rows(bytes: &[u8], shown: &str, width: usize) -> Result<(usize, Vec<f64>), Error> {
    let refuse = |why: String| Error::decoding(shown, why);
    let (file, start, value_bytes) = open_npy(bytes, shown)?;
    let shape: Vec<u64> = file.shape().to_vec();
    let [rows, columns] = shape[..] else {
        return Err(refuse(format!(
            "shape {shape:?}: expected frames × {width}"
        )));
    };
    if columns != width as u64 {
        return Err(refuse(format!(
            "shape {shape:?}: expected frames × {width}"
        )));
    }
    let data_bytes = (bytes.len() as u64).saturating_sub(start);
    rows.checked_mul(columns)
        .filter(|&n| n.saturating_mul(value_bytes) <= data_bytes)
        .ok_or_else(|| {
            refuse(format!(
                "shape {shape:?} of {value_bytes}-byte values: more than the file's \
                 {data_bytes} bytes of data hold"
            ))
        })?;
    let fortran = file.order() == npyz::Order::Fortran;
    let values = numbers(file, shown)?;
    let rows = rows as usize;
    let ordered = match fortran {
        false => values,
        true => (0..rows)
            .flat_map(|r| (0..width).map(move |c| (r, c)))
            .map(|(r, c)| values[r + rows * c])
            .collect(),
    };
    Ok((rows, ordered))
}

/// Every value of an `.npy` of float64 or float32 ([`open_npy`] has checked which), as stored.
fn numbers(file: npyz::NpyFile<&[u8]>, shown: &str) -> Result<Vec<f64>, Error> {
    let refuse = |why: String| Error::decoding(shown, why);
    let dtype = file.dtype().descr();
    match file.try_data::<f64>() {
        Ok(data) => data.collect::<std::io::Result<_>>(),
        Err(file) => match file.try_data::<f32>() {
            Ok(data) => data
                .map(|v| v.map(f64::from))
                .collect::<std::io::Result<_>>(),
            Err(_) => {
                return Err(refuse(format!(
                    "dtype {}: expected float32 or float64 values",
                    quoted(dtype.trim_matches('\''))
                )));
            }
        },
    }
    .map_err(|e| refuse(format!("the data: {e}")))
}

/// The first line of the CSV `bvhview positions` writes.
const CSV_HEADER: &str = "frame,joint,x,y,z";

/// What is said of a CSV without [`CSV_HEADER`] first.
fn no_csv_header() -> String {
    format!("expected the header {CSV_HEADER} (the CSV `bvhview positions` writes)")
}

/// The CSV `bvhview positions` writes: a header `frame,joint,x,y,z`, then for frame N, N + 1,
/// … (from the first row's, 0 unless `--frames` chose others) a row per joint, the same joints
/// in the same order in every frame.
pub fn read_csv(text: &str, shown: &str) -> Result<(Vec<String>, Vec<DVec3>), Error> {
    let at = |line: usize, why: String| Error::usage(format!("{shown}:{line}: {why}"));
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    match lines.next() {
        Some((_, header)) if header.trim_end() == CSV_HEADER => {}
        _ => return Err(at(1, no_csv_header())),
    }
    let mut names: Vec<String> = Vec::new();
    let mut points = Vec::new();
    let (mut frame, mut joint) = (0usize, 0usize);
    let mut first_frame: Option<usize> = None;
    for (number, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let fields = split_csv(line).map_err(|why| at(number, why))?;
        let [f, name, x, y, z] = &fields[..] else {
            return Err(at(number, format!("{} fields, expected 5", fields.len())));
        };
        let f: usize = f
            .parse()
            .map_err(|_| at(number, format!("frame {f:?}: not a frame number")))?;
        if first_frame.is_none() {
            frame = f;
        }
        let number_of = |v: &str| {
            v.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| at(number, format!("{v:?}: not a finite number")))
        };
        let point = DVec3::new(number_of(x)?, number_of(y)?, number_of(z)?);
        let start = *first_frame.get_or_insert(f);
        if f == start && frame == start {
            names.push(name.clone());
        } else {
            // The next frame's number: none after the largest a frame number can be (a
            // wrapped sum would read 2^64 - 1 then 0 as consecutive).
            let next = frame.checked_add(1);
            if joint == names.len() && next == Some(f) {
                (frame, joint) = (f, 0);
            }
            if f != frame || names.get(joint) != Some(name) {
                let expected = match (names.get(joint), next) {
                    (Some(want), _) => format!("frame {frame}, joint {}", quoted(want)),
                    (None, Some(next)) => format!("frame {next}, joint {}", quoted(&names[0])),
                    (None, None) => {
                        format!("nothing after frame {frame}, the largest frame number")
                    }
                };
                return Err(at(
                    number,
                    format!(
                        "frame {f}, joint {}: expected {expected} (every frame lists the same \
                         joints in the same order, frame after frame)",
                        quoted(name)
                    ),
                ));
            }
        }
        joint += 1;
        points.push(point);
    }
    if names.is_empty() {
        return Err(at(2, "no positions".into()));
    }
    if joint != names.len() {
        return Err(Error::usage(format!(
            "{shown}: the last frame ({frame}) lists {joint} of its {} joints",
            names.len()
        )));
    }
    Ok((names, points))
}

/// One CSV row's fields (quotes as `bvhview positions` writes them: a field in double quotes,
/// a quote inside doubled).
fn split_csv(line: &str) -> Result<Vec<String>, String> {
    let mut fields = Vec::new();
    let mut chars = line.trim_end_matches('\r').chars().peekable();
    loop {
        let mut field = String::new();
        if chars.peek() == Some(&'"') {
            chars.next();
            loop {
                match chars.next() {
                    Some('"') if chars.peek() == Some(&'"') => {
                        chars.next();
                        field.push('"');
                    }
                    Some('"') => break,
                    Some(c) => field.push(c),
                    None => return Err("a quoted field is not closed".into()),
                }
            }
            match chars.next() {
                None => {
                    fields.push(field);
                    return Ok(fields);
                }
                Some(',') => fields.push(field),
                Some(c) => return Err(format!("{c:?} after a quoted field")),
            }
        } else {
            loop {
                match chars.next() {
                    None => {
                        fields.push(field);
                        return Ok(fields);
                    }
                    Some(',') => break,
                    Some(c) => field.push(c),
                }
            }
            fields.push(field);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_csv_reads_back_its_joints_and_refuses_a_frame_out_of_order() {
        let text = "frame,joint,x,y,z\n0,Hips,0,1,2\n0,\"Left, Arm\",3,4,5\n1,Hips,6,7,8\n1,\"Left, Arm\",9,10,11\n";
        let (names, points) = read_csv(text, "t.csv").unwrap();
        assert_eq!(names, ["Hips", "Left, Arm"]);
        assert_eq!(points[3], DVec3::new(9.0, 10.0, 11.0));
        // `positions --frames 100..102` writes frames 100 and 101.
        let later =
            "frame,joint,x,y,z\n100,Hips,0,1,2\n100,Arm,3,4,5\n101,Hips,6,7,8\n101,Arm,9,10,11\n";
        let (names, points) = read_csv(later, "t.csv").unwrap();
        assert_eq!((names.len(), points.len()), (2, 4));
        let bad = "frame,joint,x,y,z\n0,Hips,0,1,2\n0,Arm,3,4,5\n1,Arm,6,7,8\n";
        assert_eq!(
            read_csv(bad, "t.csv").unwrap_err().to_string(),
            "t.csv:4: frame 1, joint \"Arm\": expected frame 1, joint \"Hips\" (every frame lists \
             the same joints in the same order, frame after frame)"
        );
    }

    #[test]
    fn an_npy_in_either_order_and_width_reads_the_same() {
        // numpy's own bytes for np.arange(12, dtype='<f8').reshape(2, 2, 3), and the same array
        // saved Fortran-ordered as float32.
        let header = |descr: &str, fortran: bool| {
            let dict = format!(
                "{{'descr': '{descr}', 'fortran_order': {}, 'shape': (2, 2, 3), }}",
                if fortran { "True" } else { "False" }
            );
            let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
            let padded = (10 + dict.len() + 1).div_ceil(64) * 64;
            let length = padded - 10;
            bytes.extend_from_slice(&(length as u16).to_le_bytes());
            bytes.extend_from_slice(dict.as_bytes());
            bytes.resize(padded - 1, b' ');
            bytes.push(b'\n');
            bytes
        };
        let mut c_order = header("<f8", false);
        for v in 0..12 {
            c_order.extend_from_slice(&f64::from(v).to_le_bytes());
        }
        let mut f_order = header("<f4", true);
        for c in 0..3 {
            for j in 0..2 {
                for f in 0..2 {
                    f_order.extend_from_slice(&(((f * 2 + j) * 3 + c) as f32).to_le_bytes());
                }
            }
        }
        let a = read_npy(&c_order, "c.npy").unwrap();
        let b = read_npy(&f_order, "f.npy").unwrap();
        assert_eq!(a, b);
        assert_eq!(a.1[3], DVec3::new(9.0, 10.0, 11.0));
        // A header promising more than the file holds is refused before anything is read.
        let mut short = header("<f8", false);
        short.extend_from_slice(&[0; 16]);
        assert_eq!(
            read_npy(&short, "s.npy").unwrap_err().to_string(),
            "s.npy: shape [2, 2, 3] of 8-byte values: more than the file's 16 bytes of data hold"
        );
    }
}
