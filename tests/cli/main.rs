//! The command line: commands, exit codes and messages, help, every output by its hash, folder
//! conversion and walks, `trace`, hostile input, and outputs in folders other users share.
//! One test binary; `cargo test --test cli MODULE` runs one file's tests
//! (`BVHVIEW_CLI_WRITE=1 cargo test --test cli outputs_manifest` rewrites the manifest).

#[path = "../common/mod.rs"]
mod common;

mod bad_calls_and_exit_codes;
mod commands_and_exit_codes;
mod convert_folder;
mod folder_walks;
mod help_and_messages;
mod hostile_inputs;
mod outputs_in_shared_folders;
mod outputs_manifest;
mod trace_gl_calls;
mod up_axes;
