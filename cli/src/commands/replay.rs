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
    /// Where the recording goes; by default `FLIGHT.replay.rrd` beside the log,
    /// never over the live recording `fly` wrote (`FLIGHT.rrd`).
    #[command(flatten)]
    viewer: record::ViewerArgs,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let log: FlightLog = read_json(&args.flight, "a flight log written by `swarmctl fly`")?;
    let mission = args.mission.as_deref().map(mission::load).transpose()?;
    if let (Some(m), Some(path)) = (&mission, &args.mission) {
        check_log_is_of(&log, &args.flight, m, path)?;
    }
    let plan: Option<CompiledPlan> = match (&args.plan, &mission) {
        (Some(path), Some(m)) => {
            // The same checks `fly --plan` makes: a plan of another mission (or
            // an edited one) would draw paths the flight never had.
            Some(swarmctl::compiled::file::load(path, m)?.into_compiled())
        }
        _ => None,
    };
    let sink = args
        .viewer
        .sink()
        .unwrap_or_else(|| record::Sink::File(default_replay_path(&args.flight)));
    let replaced = matches!(&sink, record::Sink::File(path) if path.exists());
    let stats = record::record_flight(&log, mission.as_ref(), plan.as_ref(), &sink)
        .with_context(|| format!("recording {}", args.flight.display()))?;
    println!(
        "{}: {} drones, {} telemetry samples recorded",
        log.mission,
        log.drones.len(),
        stats.samples_logged
    );
    let note = if replaced {
        " (replaced the file that was there)"
    } else {
        ""
    };
    println!("  recording            {}{note}", describe(&sink));
    Ok(ExitCode::SUCCESS)
}

/// Where a replay goes without `--rrd`/`--spawn`/`--connect`: beside the log, as
/// `FLIGHT.replay.rrd`, so it never replaces the live recording `fly` wrote
/// (`FLIGHT.rrd`, with the plan as well as the flight).
pub fn default_replay_path(flight: &Path) -> PathBuf {
    flight.with_extension("replay.rrd")
}

/// Refuses a flight log that was not flown from `mission`: another mission's
/// name, or drones the mission does not have (or lacks).
fn check_log_is_of(
    log: &FlightLog,
    log_path: &Path,
    mission: &mission::Mission,
    mission_path: &Path,
) -> anyhow::Result<()> {
    let mission_ids: Vec<&str> = mission.drones().map(|(_, d)| d.id.as_str()).collect();
    let log_ids: Vec<&str> = log.drones.iter().map(|d| d.id.as_str()).collect();
    let unknown: Vec<&str> = log_ids
        .iter()
        .copied()
        .filter(|id| !mission_ids.contains(id))
        .collect();
    let missing: Vec<&str> = mission_ids
        .iter()
        .copied()
        .filter(|id| !log_ids.contains(id))
        .collect();
    let mut problems = Vec::new();
    if log.mission != mission.name {
        problems.push(format!(
            "the log is of mission {:?}, the file is mission {:?}",
            log.mission, mission.name
        ));
    }
    if !unknown.is_empty() {
        problems.push(format!(
            "the log flew drones the mission does not have: {}",
            unknown.join(", ")
        ));
    }
    if !missing.is_empty() {
        problems.push(format!(
            "the mission's drones {} are not in the log",
            missing.join(", ")
        ));
    }
    if problems.is_empty() {
        return Ok(());
    }
    anyhow::bail!(
        "flight log {} was not flown from {}: {} (give --mission the mission that was flown)",
        log_path.display(),
        mission_path.display(),
        problems.join("; ")
    )
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
