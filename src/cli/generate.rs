//! `bvhview generate`: the man page and shell completions, made from the one clap command (as
//! `rg --generate` makes ripgrep's), so they never disagree with `--help`.

use super::*;

#[derive(Args)]
pub(crate) struct GenerateArgs {
    /// What to write on stdout: the man page (roff), or the completions for a shell.
    what: Generated,
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

/// Writes what was asked for on stdout; a reader that has gone ends it quietly.
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
    let text = String::from_utf8(text).map_err(|e| Error::Usage(e.to_string()))?;
    write_text(&text)?;
    Ok(ExitCode::SUCCESS)
}
