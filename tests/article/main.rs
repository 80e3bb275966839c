//! The article's program and bvhview side by side: what it printed and drew, its program rebuilt
//! from its text, each defect of its loader, and the Chinese chapter that teaches it.
//! One test binary; `cargo test --test article MODULE` runs one file's tests.

#[path = "../common/mod.rs"]
mod common;

mod article_program_rebuilt;
mod loader_defects;
mod pictures_match_article;
mod print_matches_article;
mod teaching_zh_taiwan_register;
