//! C++: `BVH::print` and `BVH::printRecursive`: the loaded tree, one joint per line.

use crate::model::skeleton::Skeleton;
use std::fmt::Write;

/// The longest name `print` writes, in bytes. The article's `newNode` keeps at most 22 bytes of a
/// name (it copies 24 into `name[NAMESIZE]`, then writes its terminator two places back), but the
/// reference prints in tests/oracle/print were made by the article's program with a robust loader
/// whose names keep 23, and this output matches those byte for byte. Names of 22 bytes or fewer
/// (all the article's own inputs) print the same either way.
pub const NAME_LIMIT: usize = 23;

/// C++: `BVH::print`. Writes what the article's program prints for the same file, byte for byte:
/// per joint ` -` once per level, the name, ` : x,y,z -flags- ` and the order in lower case.
/// End Sites print as `Site` with flags 0, as the article's `processEnd` names them. Names are cut
/// to [`NAME_LIMIT`] bytes, because the article stores them in a fixed `name[NAMESIZE]`; only this
/// output keeps a limit, every other command has the whole name. One change:
/// the article dereferences a null root when the load failed; here there is nothing to print
/// because a failed load is an error and no tree exists.
pub fn print(skeleton: &Skeleton) -> String {
    let mut out = String::new();
    for root in skeleton.roots() {
        print_recursive(skeleton, root, 0, &mut out);
    }
    out
}

/// C++: `BVH::printRecursive`. Numbers are `printf("%f")` of the stored single-precision values.
pub fn print_recursive(skeleton: &Skeleton, joint: usize, depth: usize, out: &mut String) {
    let node = &skeleton.joints[joint];
    for _ in 0..depth {
        out.push_str(" -");
    }
    let flags = node.rotation_order.map_or(0, |order| order.flag());
    let letters = node.rotation_order.map_or("", |order| order.letters());
    let [x, y, z] = node.offset.to_array().map(f64::from);
    // Infallible: writing to a String cannot fail.
    let bytes = node.name.as_bytes();
    let name = String::from_utf8_lossy(&bytes[..bytes.len().min(NAME_LIMIT)]);
    let _ = writeln!(out, "{name} : {x:.6},{y:.6},{z:.6} -{flags}- {letters}");
    for &child in &node.children {
        print_recursive(skeleton, child, depth + 1, out);
    }
}
