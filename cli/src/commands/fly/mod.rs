//! `swarmctl fly`: plan (or load a plan), compose and check it, then fly exactly
//! that over MAVLink — against the mission's endpoints, or the bundled SITL when
//! the mission names none.
//!
//! This file runs the flight; `args` checks the flags, `plan_source` plans or
//! loads what is flown, `vehicles` (with `bundled_sitl`) reaches the drones,
//! `recording` keeps the Rerun recording and `report` writes the log and says
//! how the flight went.

mod args;
mod bundled_sitl;
mod dry_run;
mod plan_source;
mod recording;
mod report;
mod start_instant;
mod vehicles;

pub use args::Args;

use anyhow::Context;
use args::{Durations, check_args, frame_source};
use std::process::ExitCode;
use std::sync::Arc;
use swarmctl::compiled::CheckedPlan;
use swarmctl::fly::{self, FlyOptions};
use swarmctl::import;
use swarmctl::link::SigningKey;
use swarmctl::mission::{KeySource, Mission};
use swarmctl::plan::DiscretePlan;
use swarmctl_cli::status::{StatusMode, StatusView};
use vehicles::{Backing, vehicles};

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let began = std::time::Instant::now();
    let durations = check_args(&args)?;
    // The same inputs `swarmctl plan` accepts: mission YAML or an imported instance.
    let mission = import::load_any(&args.mission, None)?;
    if let Some(usage) = super::refuse_unknown_fault_drones(&args.faults, &mission) {
        return Ok(usage);
    }
    // Composed and checked before anything starts; what flies is exactly this.
    let checked = match &args.plan {
        Some(path) => plan_source::load_plan(path, &mission)?,
        None => plan_source::plan_now(&mission, (args.deadline, began), args.optimal)?,
    };
    let plan = checked.discrete();
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    let flight = Flight {
        mission: &mission,
        checked: &checked,
        plan: &plan,
    };
    if args.dry_run {
        return runtime.block_on(dry_run::run(&args, &durations, flight));
    }
    let path = args
        .log
        .clone()
        .unwrap_or_else(|| report::default_log_path(&args.mission));
    // Recorded live; flying never depends on it (a recorder that fails only warns).
    let recording = recording::start_recording(&args, &mission, checked.compiled(), &path);
    let observer = recording.as_ref().map(|(r, _)| r.observer());
    let log = match runtime.block_on(fly_async(&args, &durations, flight, observer)) {
        Ok(log) => log,
        Err(refused) => {
            if let Some(recording) = recording {
                recording::discard_recording(recording);
            }
            return Err(refused);
        }
    };
    report::write_log(&path, &log)?;
    report::print_report(&mission, &log, &path);
    if let Some(recording) = recording {
        recording::finish_recording(recording, &log);
    }
    // Exit 0 only when every drone landed (README, exit codes): survivors that
    // completed after a loss do not make a drone lost in the air a success, and a
    // broken limit never exits 0.
    Ok(if log.summary.succeeded() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// What is flown: the mission, its checked plan and that plan's discrete part.
#[derive(Clone, Copy)]
struct Flight<'a> {
    mission: &'a Mission,
    checked: &'a CheckedPlan,
    plan: &'a DiscretePlan,
}

/// Flies the checked plan with the live status view (and `observer`, the
/// recording), on the mission's vehicles or the bundled SITL; Ctrl-C lands
/// everyone.
async fn fly_async(
    args: &Args,
    durations: &Durations,
    flight: Flight<'_>,
    observer: Option<Arc<dyn fly::FlightObserver>>,
) -> anyhow::Result<fly::FlightLog> {
    let Flight {
        mission,
        checked,
        plan,
    } = flight;
    let (abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    abort_on_ctrl_c(abort_tx);
    let (mut options, backing) = prepare(args, durations, mission, plan).await?;
    options.observers.extend(observer);
    let status = Arc::new(StatusView::new(if args.plain {
        StatusMode::Plain
    } else {
        StatusMode::Auto
    }));
    options.observers.push(status.clone());
    let result = fly::fly_checked(mission, checked, &options, abort_rx).await;
    status.finish();
    backing.shutdown().await;
    Ok(result?)
}

/// The vehicles' links (started here for the bundled SITL) and the options a
/// flight or a dry run of `plan` uses.
async fn prepare(
    args: &Args,
    durations: &Durations,
    mission: &Mission,
    plan: &DiscretePlan,
) -> anyhow::Result<(FlyOptions, Backing)> {
    let source = match &args.signing_key_file {
        Some(file) => Some(KeySource::File(file.clone())),
        None => mission.link.signing.clone(),
    };
    let signing_key = source.as_ref().map(SigningKey::load).transpose()?;
    let (vehicles, backing) = vehicles(args, mission, plan, signing_key.as_ref()).await?;
    let mut options = FlyOptions::new(vehicles);
    let bundled = matches!(backing, Backing::Sitl(_));
    options.ready_timeout = durations
        .ready
        .unwrap_or(std::time::Duration::from_secs(if bundled { 5 } else { 60 }));
    options.frames = frame_source(args);
    options.start_tolerance_m = args.pad_tolerance;
    options.start_at = durations.start_at;
    options.replan = fly::ReplanOptions {
        enabled: !args.no_replan,
        deadline: durations.replan_deadline,
        max_replans: args.max_replans,
    };
    if signing_key.is_some() {
        eprintln!("MAVLink 2 signing on: unsigned or wrongly signed messages are refused");
    }
    options.signing_key = signing_key;
    Ok((options, backing))
}

/// On Ctrl-C every drone holds, then lands (the flight sees `abort_tx`); a second
/// Ctrl-C quits at once.
fn abort_on_ctrl_c(abort_tx: tokio::sync::watch::Sender<bool>) {
    tokio::spawn(async move {
        if tokio::signal::ctrl_c().await.is_ok() {
            eprintln!("Ctrl-C: every drone holds, then lands (Ctrl-C again to quit at once)");
            let _ = abort_tx.send(true);
            if tokio::signal::ctrl_c().await.is_ok() {
                std::process::exit(130);
            }
        }
    });
}
