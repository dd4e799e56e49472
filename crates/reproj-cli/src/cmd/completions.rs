//! `reproj completions SHELL`: the shell completion script, from the same clap definition that
//! parses the arguments (`clap_complete`).

use std::io::Write;

use crate::CompletionsArgs;

pub fn run(args: &CompletionsArgs) -> anyhow::Result<()> {
    let mut out = Vec::new();
    clap_complete::generate(
        args.shell,
        &mut crate::command(crate::ui::ColorChoice::Never),
        "reproj",
        &mut out,
    );
    super::stdout::stdout().write_all(&out)?;
    Ok(())
}
