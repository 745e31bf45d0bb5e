use anyhow::Context;
use std::path::PathBuf;
use std::process::ExitCode;
use swarmctl::mission::TEMPLATE;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Write the template here instead of standard output.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    match &args.output {
        Some(path) => std::fs::write(path, TEMPLATE)
            .with_context(|| format!("cannot write {}", path.display()))?,
        None => print!("{TEMPLATE}"),
    }
    Ok(ExitCode::SUCCESS)
}
