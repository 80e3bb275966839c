//! A walk over a binary FBX's records (node headers, property lists, nested lists) that finds
//! the first one that cannot be: ufbx reports a damaged binary file as "Failed to load" only,
//! and a user wants to know where. Kept by hand: the record layout is a few lines, and no kept
//! crate reads FBX's binary structure without also building a scene from it.

/// How a binary FBX begins.
pub(super) const BINARY_MAGIC: &[u8] = b"Kaydara FBX Binary";

/// Where the first record that cannot be is, and why, if one is found.
pub(super) fn first_fault(bytes: &[u8]) -> Option<String> {
    if !bytes.starts_with(BINARY_MAGIC) || bytes.len() < 27 {
        return None;
    }
    let version = u32::from_le_bytes(bytes[23..27].try_into().ok()?);
    let wide = version >= 7500;
    let mut path = Vec::new();
    list(bytes, 27, bytes.len(), wide, &mut path, 0).err()
}

fn number(bytes: &[u8], at: usize, wide: bool) -> Option<u64> {
    if wide {
        Some(u64::from_le_bytes(bytes.get(at..at + 8)?.try_into().ok()?))
    } else {
        Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?).into())
    }
}

fn inside(path: &[String]) -> String {
    if path.is_empty() {
        String::new()
    } else {
        format!(" (inside {})", path.join(" › "))
    }
}

/// The records from `at` up to `end` (a null record ends the list); `Ok` with where the
/// list ends.
fn list(
    bytes: &[u8],
    mut at: usize,
    end: usize,
    wide: bool,
    path: &mut Vec<String>,
    depth: usize,
) -> Result<usize, String> {
    let word = if wide { 8 } else { 4 };
    let header = 3 * word + 1;
    if depth > crate::limits::MAX_DEPTH {
        return Err(format!(
            "records nest deeper than {} levels",
            crate::limits::MAX_DEPTH
        ));
    }
    loop {
        let here = inside(path);
        let (Some(record_end), Some(_count), Some(props_len)) = (
            number(bytes, at, wide),
            number(bytes, at + word, wide),
            number(bytes, at + 2 * word, wide),
        ) else {
            return Err(format!(
                "the record at byte {at}{here} is cut off by the file's end"
            ));
        };
        if record_end == 0 {
            return Ok(at + header);
        }
        let name_len = usize::from(*bytes.get(at + 3 * word).unwrap_or(&0));
        let name_at = at + header;
        let record_end = usize::try_from(record_end).unwrap_or(usize::MAX);
        if record_end > end {
            let outer = if path.is_empty() {
                "the file"
            } else {
                "its parent"
            };
            return Err(format!(
                "the record at byte {at}{here} says it ends at byte {record_end}, past the \
                 end of {outer} at byte {end}"
            ));
        }
        if record_end <= name_at + name_len {
            return Err(format!(
                "the record at byte {at}{here} says it ends at byte {record_end}, before \
                 its own header does (byte {})",
                name_at + name_len
            ));
        }
        let name = String::from_utf8_lossy(&bytes[name_at..name_at + name_len]);
        let name: String = name.chars().filter(|c| !c.is_control()).take(40).collect();
        let props_at = name_at + name_len;
        let props_end = usize::try_from(props_len)
            .ok()
            .and_then(|n| props_at.checked_add(n))
            .filter(|&e| e <= record_end)
            .ok_or_else(|| {
                format!(
                    "the record \"{name}\" at byte {at}{here} has {props_len} bytes of \
                     properties, more than the record holds"
                )
            })?;
        let mut p = props_at;
        while p < props_end {
            p = property(bytes, p, props_end)
                .map_err(|why| format!("the record \"{name}\" at byte {at}{here}: {why}"))?;
        }
        if p != props_end {
            return Err(format!(
                "the record \"{name}\" at byte {at}{here}: its properties end at byte {p}, \
                 not {props_end} as its header says"
            ));
        }
        if props_end < record_end {
            path.push(format!("\"{name}\""));
            let nested_end = list(bytes, props_end, record_end, wide, path, depth + 1)?;
            path.pop();
            if nested_end != record_end {
                return Err(format!(
                    "the record \"{name}\" at byte {at}{here}: its children end at byte \
                     {nested_end}, not {record_end} as its header says"
                ));
            }
        }
        at = record_end;
    }
}

/// One property at `at`; `Ok` with where it ends.
fn property(bytes: &[u8], at: usize, end: usize) -> Result<usize, String> {
    let code = *bytes.get(at).ok_or("cut off")?;
    let u32_at = |k: usize| -> Result<usize, String> {
        let field = bytes.get(k..k + 4).ok_or("cut off")?;
        Ok(u32::from_le_bytes(field.try_into().expect("4 bytes")) as usize)
    };
    let next = match code {
        b'Y' => at + 3,
        b'C' => at + 2,
        b'I' | b'F' => at + 5,
        b'D' | b'L' => at + 9,
        b'S' | b'R' => at + 5 + u32_at(at + 1)?,
        b'f' | b'd' | b'l' | b'i' | b'b' => at + 13 + u32_at(at + 9)?,
        other => {
            return Err(format!(
                "property type byte {other:#04x} at byte {at} is none of FBX's"
            ));
        }
    };
    if next > end {
        return Err(format!("the property at byte {at} runs past its record"));
    }
    Ok(next)
}
