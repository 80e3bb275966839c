//! `bvhview generate`: the man page and shell completions, made from the one clap command (as
//! `rg --generate` makes ripgrep's), so they never disagree with `--help`.

use super::{finish_write, is_stdio, open_output, wrote};
use crate::io::error::Error;
use clap::Args;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct GenerateArgs {
    /// What to write: the man page (roff), or the completions for a shell.
    what: Generated,
    /// The file to write (its folders are made if missing; `-` or none: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Generated {
    Man,
    CompleteBash,
    CompleteZsh,
    CompleteFish,
    CompleteElvish,
    CompletePowershell,
}

/// Writes what was asked for into `-o` or on stdout; a reader that has gone ends it quietly.
pub(crate) fn run(args: GenerateArgs, mut command: clap::Command) -> Result<ExitCode, Error> {
    use clap_complete::Shell;
    let mut text = Vec::new();
    let shell = match args.what {
        Generated::Man => {
            clap_mangen::Man::new(command.clone())
                .render(&mut text)
                .map_err(|e| Error::output(Path::new("<stdout>"), e))?;
            None
        }
        Generated::CompleteBash => Some(Shell::Bash),
        Generated::CompleteZsh => Some(Shell::Zsh),
        Generated::CompleteFish => Some(Shell::Fish),
        Generated::CompleteElvish => Some(Shell::Elvish),
        Generated::CompletePowershell => Some(Shell::PowerShell),
    };
    if let Some(shell) = shell {
        clap_complete::generate(shell, &mut command, "bvhview", &mut text);
    }
    let path = args.output.as_deref().filter(|p| !is_stdio(p));
    if let Some(folder) = path
        .and_then(Path::parent)
        .filter(|f| !f.as_os_str().is_empty())
    {
        std::fs::create_dir_all(folder).map_err(|e| Error::output(folder, e))?;
    }
    let mut out = open_output(path)?;
    let result = out.write_all(&text);
    finish_write(out, result, path)?;
    if let Some(path) = path {
        wrote(format_args!("{}", path.display()));
    }
    Ok(ExitCode::SUCCESS)
}
