//! `bvhview print`: the joint tree exactly as the article's `BVH::print()` prints it.

use super::{Source, load, write_text};
use crate::io::error::Error;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct PrintArgs {
    /// A take: .bvh, .fbx, .gltf, .glb or AMASS .npz, or an .asf skeleton (its motion with --motion).
    file: PathBuf,
    #[command(flatten)]
    source: Source,
}

pub(crate) fn run(args: PrintArgs) -> Result<ExitCode, Error> {
    let loaded = load(&args.file, &args.source)?;
    write_text(&crate::bvh::print::print(&loaded.skeleton))?;
    Ok(ExitCode::SUCCESS)
}
