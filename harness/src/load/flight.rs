//! Flying the load mission on the bundled SITL, with the watcher measuring.

use super::report::{self, CpuUse, LoadReport};
use super::vehicles::VehiclesAfter;
use super::watch::{self, Watched, cpu_since_s};
use super::{CONTROLLER_THREAD, LoadOptions, SITL_THREAD, WATCH_THREAD};
use crate::{HarnessError, resources};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use swarmctl::fly::{self, FlightLog, FlyError, VehicleLink};
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;
use swarmctl_sitl::{Swarm, TickStats};

/// Flies `plan` on the bundled SITL and measures it (see
/// [`run_load`](super::run_load)). `plan_times_s` goes into the report as is.
pub fn fly_load(
    mission: &Mission,
    plan: &DiscretePlan,
    plan_times_s: Vec<f64>,
    options: &LoadOptions,
) -> Result<LoadReport, HarnessError> {
    let fds_before = resources::process_resources().open_fds;
    let sitl_runtime = runtime(SITL_THREAD, "SITL")?;
    let controller_runtime = runtime(CONTROLLER_THREAD, "controller")?;
    let configs = swarmctl_bundled::vehicle_configs(mission, plan, options.flavour, &[])?;
    let (swarm, links) = sitl_runtime.block_on(swarmctl_bundled::start(
        configs,
        mission.link.setpoint_rate_hz,
    ))?;
    let swarm = Arc::new(swarm);
    let flown = fly_watched(&controller_runtime, &swarm, mission, plan, links, options)?;
    // What the vehicles saw, before they go.
    let vehicles = VehiclesAfter::read(&swarm, mission, plan);
    match Arc::try_unwrap(swarm) {
        Ok(swarm) => sitl_runtime.block_on(swarm.shutdown()),
        Err(_) => return Err(HarnessError::SwarmStillShared),
    }
    drop(controller_runtime);
    drop(sitl_runtime);
    let fds_after = resources::process_resources().open_fds;
    let run = Run {
        mission,
        plan,
        plan_times_s,
        options,
        fds: [fds_before, fds_after],
    };
    Ok(run.report(flown, vehicles))
}

/// A multi-threaded runtime whose threads are named `thread_name`, so their CPU
/// can be told apart.
fn runtime(
    thread_name: &str,
    runtime: &'static str,
) -> Result<tokio::runtime::Runtime, HarnessError> {
    tokio::runtime::Builder::new_multi_thread()
        .thread_name(thread_name)
        .enable_all()
        .build()
        .map_err(|source| HarnessError::RuntimeStart { runtime, source })
}

/// The flight and what was measured around it.
struct Flown {
    /// The flight's result, or `Err` if it hit the time limit.
    result: Result<Result<FlightLog, FlyError>, tokio::time::error::Elapsed>,
    /// Wall time of the flight, seconds.
    wall_s: f64,
    /// Process CPU over the flight, seconds.
    total_cpu_s: f64,
    /// The SITL threads' CPU over the flight, seconds.
    sitl_cpu_s: f64,
    /// The physics ticker's counters over the flight.
    ticks: TickStats,
    /// What the watcher saw.
    watched: Watched,
}

/// Flies `plan` on the controller runtime within the limit while the watcher
/// samples `swarm`, and measures wall time, CPU and physics ticks around it.
fn fly_watched(
    controller_runtime: &tokio::runtime::Runtime,
    swarm: &Arc<Swarm>,
    mission: &Mission,
    plan: &DiscretePlan,
    links: Vec<VehicleLink>,
    options: &LoadOptions,
) -> Result<Flown, HarnessError> {
    let fly_options = swarmctl_bundled::fly_options(links);
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let done = Arc::new(AtomicBool::new(false));
    let ellipsoid = mission
        .limits
        .is_ellipsoid()
        .then(|| mission.limits.separation());
    let watcher = {
        let (swarm, done) = (swarm.clone(), done.clone());
        std::thread::Builder::new()
            .name(WATCH_THREAD.into())
            .spawn(move || watch::watch(&swarm, ellipsoid, &done))
            .map_err(|source| HarnessError::WatcherStart { source })?
    };
    let ticks_before = swarm.tick_stats();
    let (wall0, cpu0, sitl0) = (
        Instant::now(),
        resources::process_cpu_s(),
        resources::threads_named_cpu_s(SITL_THREAD),
    );
    let result = controller_runtime.block_on(async {
        let flight = fly::fly(mission, plan, &fly_options, abort_rx);
        tokio::time::timeout(options.limit, flight).await
    });
    let (wall_s, total_cpu_s, sitl_cpu_s) = (
        wall0.elapsed().as_secs_f64(),
        cpu_since_s(cpu0, resources::process_cpu_s()),
        cpu_since_s(sitl0, resources::threads_named_cpu_s(SITL_THREAD)),
    );
    let ticks = tick_delta(&ticks_before, &swarm.tick_stats());
    done.store(true, Ordering::Relaxed);
    let watched = watcher.join().map_err(|_| HarnessError::WatcherPanicked)?;
    Ok(Flown {
        result,
        wall_s,
        total_cpu_s,
        sitl_cpu_s,
        ticks,
        watched,
    })
}

/// The ticker's counters between two readings.
fn tick_delta(before: &TickStats, after: &TickStats) -> TickStats {
    TickStats {
        ticks: after.ticks - before.ticks,
        steps: after.steps - before.steps,
        missed_ticks: after.missed_ticks - before.missed_ticks,
        skipped_steps: after.skipped_steps - before.skipped_steps,
    }
}

/// What was flown, for the report.
struct Run<'a> {
    mission: &'a Mission,
    plan: &'a DiscretePlan,
    plan_times_s: Vec<f64>,
    options: &'a LoadOptions,
    /// Open file descriptors before and after.
    fds: [usize; 2],
}

impl Run<'_> {
    /// The report: the measurements, how the flight ended, and the failures.
    fn report(self, flown: Flown, vehicles: VehiclesAfter) -> LoadReport {
        let mut failures = Vec::new();
        let (observed, log) = outcome(flown.result, self.options.limit, &mut failures);
        if let Some(log) = &log {
            report::log_failures(log, &mut failures);
        }
        let summary = log.as_ref().map(|l| &l.summary);
        let watched = flown.watched;
        let mut report = LoadReport {
            vehicles: self.plan.drones.len(),
            seed: self.options.seed,
            mission: self.mission.name.clone(),
            plan_times_s: self.plan_times_s,
            makespan_steps: self.plan.makespan_steps,
            observed,
            at_goal: vehicles.at_goal,
            max_goal_error_m: vehicles.max_goal_error_m,
            still_armed: vehicles.still_armed,
            flight_wall_s: flown.wall_s,
            cpu: CpuUse {
                wall_s: flown.wall_s,
                total_s: flown.total_cpu_s,
                sitl_s: flown.sitl_cpu_s,
                watch_s: watched.own_cpu_s,
                peak_total_share: watched.peak_total_share,
                peak_controller_share: watched.peak_controller_share,
            },
            setpoints: vehicles.setpoints,
            worst_vehicle_p99_s: vehicles.worst_vehicle_p99_s,
            link: vehicles.link,
            controller_link_losses: log
                .as_ref()
                .map_or(0, |l| l.drones.iter().map(|d| d.link_losses).sum()),
            ticks: flown.ticks,
            min_separation_telemetry_m: summary.map_or(f64::INFINITY, |s| s.min_separation_m),
            min_separation_truth_m: watched.min_separation_m,
            safety_distance_m: self.mission.limits.safety_distance_m,
            scaled_telemetry_truth: watched.min_scaled_separation.map(|truth| {
                let telemetry = summary
                    .and_then(|s| s.min_scaled_separation)
                    .unwrap_or(f64::INFINITY);
                (telemetry, truth)
            }),
            peak_rss_bytes: resources::peak_rss_bytes().unwrap_or(0),
            flight_max_rss_bytes: watched.max_rss_bytes,
            fds_before: self.fds[0],
            fds_max: watched.max_fds,
            fds_after: self.fds[1],
            log,
            failures: Vec::new(),
        };
        report::vehicle_and_separation_failures(&report, &mut failures);
        report.failures = failures;
        report
    }
}

/// How the flight ended in words, and its log if it ran to its end; a flight
/// that failed or hit `limit` adds why to `failures`.
fn outcome(
    result: Result<Result<FlightLog, FlyError>, tokio::time::error::Elapsed>,
    limit: Duration,
    failures: &mut Vec<String>,
) -> (String, Option<FlightLog>) {
    match result {
        Err(_) => {
            failures.push(format!("did not finish within {limit:?}"));
            ("timed out".to_string(), None)
        }
        Ok(Err(e)) => {
            let text = e.to_string();
            failures.push(format!("flight failed: {text}"));
            (
                format!("failed: {}", text.lines().next().unwrap_or_default()),
                None,
            )
        }
        Ok(Ok(log)) => (report::describe(&log), Some(log)),
    }
}
