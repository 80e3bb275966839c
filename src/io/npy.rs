//! numpy's `.npy` header, the one writer every `.npy` bvhview writes starts with (a dataset's
//! arrays, AMASS members, `positions --layout`, `positions --vertices`).

/// The magic, version 1.0 and a header of `descr` (`<f4`, `|u1`, `<U6`…) and `shape` (`[]`
/// for a scalar), padded with spaces to a newline as numpy pads it: the whole header a
/// multiple of 64 bytes, and at least `at_least` long (a dataset's array keeps a fixed
/// 128-byte header so that its row count can be written again in place).
pub fn header(descr: &str, shape: &[usize], at_least: usize) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    let shape = match dims.len() {
        1 => format!("({},)", dims[0]),
        _ => format!("({})", dims.join(", ")),
    };
    let mut dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    // Magic and version (8), the length (2), the dict, its newline.
    while (10 + dict.len() + 1) % 64 != 0 || 10 + dict.len() + 1 < at_least {
        dict.push(' ');
    }
    dict.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend((dict.len() as u16).to_le_bytes());
    out.extend(dict.as_bytes());
    out
}

#[cfg(test)]
mod tests {
    use super::header;

    #[test]
    fn headers_are_padded_as_numpy_pads_them() {
        let h = header("<f4", &[3, 2], 0);
        assert_eq!(
            (h.len(), &h[..8], h[h.len() - 1]),
            (128, &b"\x93NUMPY\x01\x00"[..], b'\n')
        );
        assert_eq!(u16::from_le_bytes([h[8], h[9]]), 118);
        // The dict alone is longer than 64 bytes: the next multiple, and the next past a long
        // shape.
        assert_eq!(header("|u1", &[2], 0).len(), 128);
        assert_eq!(header("<f8", &[123_456_789; 7], 0).len(), 192);
        let dict = std::str::from_utf8(&h[10..]).unwrap();
        assert!(dict.starts_with("{'descr': '<f4', 'fortran_order': False, 'shape': (3, 2), }  "));
        assert_eq!(header("<f8", &[5], 128).len(), 128);
        let scalar = header("<U4", &[], 0);
        assert!(
            std::str::from_utf8(&scalar[10..])
                .unwrap()
                .contains("'shape': ()")
        );
        let one = header("<i8", &[7], 0);
        assert!(
            std::str::from_utf8(&one[10..])
                .unwrap()
                .contains("'shape': (7,)")
        );
    }
}
