//! The `bvhview` command: the command line lives in the library (`src/cli/`), so the plumbing
//! it shares with the readers stays private to the crate.

fn main() -> std::process::ExitCode {
    bvhview::cli::main()
}
