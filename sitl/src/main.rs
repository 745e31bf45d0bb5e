//! `swarmctl-sitl`: run mock autopilots standalone (see sitl/README.md).

use clap::Parser;
use std::process::ExitCode;

/// Mock PX4 / ArduPilot quadcopters speaking MAVLink 2 on UDP.
#[derive(Debug, Parser)]
#[command(name = "swarmctl-sitl", version, about)]
struct Cli {
    #[command(flatten)]
    args: swarmctl_sitl::cli::Args,
}

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(tracing_subscriber::EnvFilter::from_default_env())
        .with_writer(std::io::stderr)
        .init();
    match swarmctl_sitl::cli::run(Cli::parse().args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
