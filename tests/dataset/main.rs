//! `bvhview dataset` and `bvhview::dataset`: compiling takes into training arrays and reading
//! them back, hostile dataset folders, the fast posing against the plain one, and HumanML3D's
//! feature vectors.
//! One test binary; `cargo test --test dataset MODULE` runs one file's tests.

#[path = "../common/mod.rs"]
mod common;

mod compile_and_read;
mod fast_and_plain_posing_agree;
mod hostile_dataset_folders;
mod humanml3d_features;
