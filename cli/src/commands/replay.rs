//! `swarmctl replay`: rebuild a Rerun recording from a flight log.

use anyhow::Context;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use swarmctl::compiled::CompiledPlan;
use swarmctl::fly::FlightLog;
use swarmctl::mission;
use swarmctl_cli::record;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Flight log (JSON) written by `swarmctl fly`.
    flight: PathBuf,
    /// The mission flown, to show its world, groups and starts.
    #[arg(long)]
    mission: Option<PathBuf>,
    /// The plan flown (JSON from `swarmctl plan -o`), to show it beside the flight;
    /// needs --mission.
    #[arg(long, requires = "mission")]
    plan: Option<PathBuf>,
    #[command(flatten)]
    viewer: record::ViewerArgs,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let log: FlightLog = read_json(&args.flight, "a flight log written by `swarmctl fly`")?;
    let mission = args.mission.as_deref().map(mission::load).transpose()?;
    let plan: Option<CompiledPlan> = args
        .plan
        .as_deref()
        .map(|p| read_json(p, "a plan written by `swarmctl plan -o`"))
        .transpose()?;
    let sink = args.viewer.sink_or_beside(&args.flight);
    let stats = record::record_flight(&log, mission.as_ref(), plan.as_ref(), &sink)
        .with_context(|| format!("recording {}", args.flight.display()))?;
    println!(
        "{}: {} drones, {} telemetry samples recorded",
        log.mission,
        log.drones.len(),
        stats.samples_logged
    );
    println!("  recording            {}", describe(&sink));
    Ok(ExitCode::SUCCESS)
}

fn read_json<T: serde::de::DeserializeOwned>(path: &Path, what: &str) -> anyhow::Result<T> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| format!("{} is not {what}", path.display()))
}

/// Where the recording went, for the report.
pub fn describe(sink: &record::Sink) -> String {
    match sink {
        record::Sink::File(path) => path.display().to_string(),
        record::Sink::Spawn => "streamed to a spawned Rerun viewer".to_string(),
        record::Sink::Connect(addr) => format!("streamed to the Rerun viewer at {addr}"),
    }
}
