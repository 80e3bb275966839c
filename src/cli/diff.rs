//! `bvhview diff`: how many pixels two pictures differ in, and where.

use super::{check_output, write_text, wrote};
use crate::io::error::Error;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct DiffArgs {
    /// The first PNG picture.
    first: PathBuf,
    /// The second PNG picture, of the same size.
    second: PathBuf,
    /// Write the difference: differing pixels red, the rest dimmed.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// Exits 1 when the pictures differ, 0 when they are the same.
pub(crate) fn run(args: DiffArgs) -> Result<ExitCode, Error> {
    use crate::render::Image;
    if let Some(output) = &args.output {
        check_output(output, &["png"])?;
    }
    let (a, b) = (
        Image::read_png(&args.first)?,
        Image::read_png(&args.second)?,
    );
    if (a.width, a.height) != (b.width, b.height) {
        return Err(Error::usage(format!(
            "the pictures differ in size: {}x{} and {}x{}",
            a.width, a.height, b.width, b.height
        )));
    }
    let differing = a.differing_pixels(&b);
    let total = a.width as usize * a.height as usize;
    if let Some(path) = &args.output {
        a.difference(&b).write_png(path)?;
        wrote(format_args!("{}", path.display()));
    }
    let percent = differing as f64 * 100.0 / total as f64;
    let verb = if differing == 1 { "differs" } else { "differ" };
    write_text(&format!(
        "{differing} of {} {verb} ({percent:.3}%)\n",
        crate::io::error::counted(total, "pixel")
    ))?;
    Ok(if differing > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}
