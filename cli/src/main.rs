//! The `swarmctl` command line: parses arguments, calls the library, reports.

mod commands;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Plan, schedule and fly drone swarms from one mission file.
#[derive(Debug, Parser)]
#[command(name = "swarmctl", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Benchmark the pipeline's stages on seeded instances.
    #[command(subcommand_required = true)]
    Bench(commands::bench::Args),
    /// Validate mission files and summarise them.
    Check(commands::check::Args),
    /// Fly a mission over MAVLink (the bundled SITL when the mission names no endpoints).
    Fly(commands::fly::Args),
    /// Generate a random mission like the paper's experiments.
    Gen(commands::generate::Args),
    /// Plan collision-free paths (makespan-optimal TAPF) and write the plan file.
    Plan(commands::plan::Args),
    /// Serve some of a mission's drones to a controller over Zenoh (`fly --via zenoh`).
    Relay(commands::relay::Args),
    /// Rebuild a Rerun recording from a flight log.
    Replay(commands::replay::Args),
    /// Run mock PX4 / ArduPilot quadcopters on UDP until Ctrl-C (see sitl/README.md).
    Sitl(commands::sitl::Args),
    /// Print a commented mission template documenting every field.
    Template(commands::template::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Bench(args) => commands::bench::run(args),
        Command::Check(args) => commands::check::run(args),
        Command::Fly(args) => commands::fly::run(args),
        Command::Gen(args) => commands::generate::run(args),
        Command::Plan(args) => commands::plan::run(args),
        Command::Relay(args) => commands::relay::run(args),
        Command::Replay(args) => commands::replay::run(args),
        Command::Sitl(args) => commands::sitl::run(args),
        Command::Template(args) => commands::template::run(args),
    };
    match result {
        Ok(code) => code,
        Err(error) => {
            eprintln!("error: {}", swarmctl_cli::error_text::chain(&error));
            ExitCode::FAILURE
        }
    }
}
