//! `swarmctl sitl`: run the bundled mock autopilots (crate `swarmctl-sitl`)
//! until Ctrl-C, with the same flags as the `swarmctl-sitl` binary.

use std::process::ExitCode;

/// The `swarmctl-sitl` binary's flags, taken as they are (a wrapper struct
/// flattening them would give clap two argument groups named `Args`).
pub type Args = swarmctl_sitl::cli::Args;

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    swarmctl_sitl::cli::run(args)?;
    Ok(ExitCode::SUCCESS)
}
