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

impl Command {
    /// Whether the command only computes and reports: nothing it owns (a vehicle in
    /// the air, a simulator, a relay process) outlives an abrupt end.
    fn only_reports(&self) -> bool {
        matches!(
            self,
            Command::Check(_)
                | Command::Gen(_)
                | Command::Plan(_)
                | Command::Replay(_)
                | Command::Template(_)
        )
    }
}

/// Lets a closed pipe end the process quietly, as it ends `cat` or `grep`:
/// `swarmctl plan MISSION | head -1` stops at the first line nobody reads. Rust
/// ignores SIGPIPE, so every `println!` after the reader left would panic (exit
/// 101, "failed printing to stdout: Broken pipe"); with the default disposition
/// the kernel ends the process at that write instead. Only for commands that
/// merely report: a flight must never be ended by a terminal going away, so `fly`,
/// `relay`, `sitl` and `bench` keep SIGPIPE ignored (their live status lines
/// ignore a closed stderr, see `status`).
fn end_quietly_on_closed_pipe() {
    // SAFETY: signal(2) with SIG_DFL installs no handler; called before any other
    // thread exists, so nothing races the change of disposition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if cli.command.only_reports() {
        end_quietly_on_closed_pipe();
    }
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
