//! Reading and writing the file formats: BVH (errors, real files, streaming, the row loops,
//! loading in a forked child, convert's round trip), ASF/AMC, FBX and glTF in, glTF out.
//! One test binary; `cargo test --test formats MODULE` runs one file's tests.

#[path = "../common/mod.rs"]
mod common;

mod amass;
mod asf_amc;
mod bvh_convert_roundtrip;
mod bvh_errors;
mod bvh_real_files;
mod bvh_rows_plain_and_engine_agree;
mod bvh_streaming;
mod error_kinds;
#[cfg(all(feature = "fbx", feature = "gltf"))]
mod fbx_gltf_reading;
#[cfg(feature = "fbx")]
mod fbx_out;
#[cfg(feature = "gltf")]
mod gltf_export;
mod loading_in_a_forked_child;
mod smpl_model;
