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
    /// The axis the take stands along, over the guess (as `info --up`): y, z, x, -y, -z or -x
    /// (the last four turn it to stand along y as it is read, said).
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<super::UpArg>,
}

pub(crate) fn run(mut args: PrintArgs) -> Result<ExitCode, Error> {
    args.source.up = args.up.map(Into::into);
    let loaded = load(&args.file, &args.source)?;
    write_text(&crate::bvh::print::print(&loaded.skeleton))?;
    Ok(ExitCode::SUCCESS)
}
