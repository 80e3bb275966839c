//! `bvhview skin-demo`: the two-bone linear blend skinning demo, in a window or offscreen.

use super::{check_output, parse_size, wrote};
use crate::io::error::Error;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct SkinDemoArgs {
    /// The second bone's bend about Y and Z, in degrees.
    #[arg(long, default_value = "0,0", value_parser = parse_bend, allow_hyphen_values = true)]
    bend: (f32, f32),
    /// Picture size, WIDTHxHEIGHT (the demo's window is 640x480).
    #[arg(long, default_value = "640x480", value_parser = parse_size)]
    size: (u32, u32),
    /// Draw offscreen into this PNG instead of opening a window.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// `30,-45` → (30, -45).
fn parse_bend(text: &str) -> Result<(f32, f32), String> {
    let bad = || format!("expected Y,Z in degrees such as 30,-45, found '{text}'");
    let (y, z) = text.split_once(',').ok_or_else(bad)?;
    let y: f32 = y.trim().parse().map_err(|_| bad())?;
    let z: f32 = z.trim().parse().map_err(|_| bad())?;
    if !(y.is_finite() && z.is_finite()) {
        return Err(bad());
    }
    Ok((y, z))
}

pub(crate) fn run(args: SkinDemoArgs) -> Result<ExitCode, Error> {
    match &args.output {
        Some(path) => {
            check_output(path, &["png"])?;
            let (width, height) = args.size;
            crate::render::skin_demo::render(args.bend, width, height)?.write_png(path)?;
            wrote(format_args!("{} ({width}x{height})", path.display()));
        }
        #[cfg(feature = "window")]
        None => crate::render::window::run_skin_demo(args.bend)?,
        #[cfg(not(feature = "window"))]
        None => {
            return Err(crate::render::without_window(
                crate::render::SKIN_DEMO_OFFSCREEN,
            ));
        }
    }
    Ok(ExitCode::SUCCESS)
}
