//! The documentation holds what it says: links, commands, and docs/TESTING.md's list of test files.

#[path = "../common/mod.rs"]
mod common;

mod links_and_commands;
mod messages_name_arguments_as_data;
mod testing_md_lists_every_test_file;
