//! `swarmctl sitl`: run the bundled mock autopilots (crate `swarmctl-sitl`)
//! until Ctrl-C, with the same flags as the `swarmctl-sitl` binary.

use std::process::ExitCode;

#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    sitl: swarmctl_sitl::cli::Args,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    swarmctl_sitl::cli::run(args.sitl)?;
    Ok(ExitCode::SUCCESS)
}
