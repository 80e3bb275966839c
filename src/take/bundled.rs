//! The take shown when no file is given, built into the library.

/// The default motion shown when no file is given: a short walk on the skeleton printed in the
/// article's companion text about MOTION rows, made by `examples/make_walk.rs`.
pub const DEFAULT_MOTION: &[u8] = include_bytes!("../../assets/walk.bvh");

/// How the default motion is named in messages: it is built into the binary, so no path names
/// it (assets/walk.bvh exists only in the source).
pub const DEFAULT_MOTION_NAME: &str = "the bundled walk";
