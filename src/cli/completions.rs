//! `granflow completions <SHELL>`: print the shell's completion script for granflow (generated
//! by clap_complete from the command definitions, so it always matches them).

use clap::{Args, CommandFactory};
use clap_complete::Shell;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow completions bash > ~/.local/share/bash-completion/completions/granflow
  granflow completions zsh > ~/.zfunc/_granflow     # with fpath+=(~/.zfunc) in ~/.zshrc
  granflow completions fish > ~/.config/fish/completions/granflow.fish")]
pub struct CompletionsArgs {
    /// the shell to complete in
    #[arg(value_enum)]
    pub shell: Shell,
}

pub fn run(args: CompletionsArgs) -> anyhow::Result<()> {
    let mut command = super::Cli::command();
    let name = command.get_name().to_string();
    // generated into memory, then written through `out`: a full stdout is an error (exit 75),
    // never a panic
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut command, name, &mut script);
    super::out::write(format_args!("{}", String::from_utf8_lossy(&script)));
    Ok(())
}
