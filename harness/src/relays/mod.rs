//! The relay load benchmark (`swarmctl bench load --via zenoh --relays K`): the
//! load mission flown through K relay processes (the `swarmctl relay --sitl`
//! command, each with its share of the bundled vehicles) by a controller in
//! this process, over Zenoh on loopback.
//!
//! Measured as the load benchmark measures, each where it happens: setpoint
//! intervals where the vehicles receive them (each relay reports its
//! vehicles'), separation from telemetry (the flight log) and from the
//! simulators' truth (the relays publish it; a [`TruthWatch`] here compares the
//! whole swarm), CPU time and peak memory per process (the relays' as the
//! kernel counted them when they exited). [`markdown_table`] sets the run beside
//! a baseline flown the way the load benchmark flies it, when there is one.
//!
//! Split by concept: this file flies, `process` starts, stops and reads the
//! relay processes, `table` reports.

mod process;
mod table;

pub use process::{RelayIntervals, RelayReport};
pub use table::markdown_table;

use crate::load::{self, LoadOptions};
use crate::{HarnessError, resources};
use process::RelayProcess;
use std::path::Path;
use std::time::{Duration, Instant};
use swarmctl::fly::{self, FlightLog};
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;
use swarmctl_relay::truth::{TruthReport, TruthWatch};
use swarmctl_relay::{KeySpace, RelayLinks, Role, ZenohEndpoints};

/// A relay's MAVLink network holds at most this many vehicles (system ids 1–254).
pub const RELAY_CAPACITY: usize = 254;

/// The flight through relays, measured.
#[derive(Debug)]
pub struct RelayRun {
    /// Drones flown.
    pub drones: usize,
    /// What each relay reported, in relay order.
    pub relays: Vec<RelayReport>,
    /// The flight log; `None` when the flight ran out of time.
    pub log: Option<FlightLog>,
    /// What the simulators' truth showed.
    pub truth: TruthReport,
    /// Planning times of the runs, seconds.
    pub plan_times_s: Vec<f64>,
    /// CPU time of this process (the controller) over the flight, seconds.
    pub controller_cpu_s: f64,
    /// Peak resident memory of this process, bytes.
    pub controller_peak_rss_bytes: u64,
    /// Wall time of the flight, seconds.
    pub wall_s: f64,
}

impl RelayRun {
    /// The flight completed within its limits, by telemetry and by the truth.
    pub fn passed(&self, mission: &Mission) -> bool {
        self.log.as_ref().is_some_and(|l| {
            let s = &l.summary;
            s.completed && s.safety_held && s.speed_held
        }) && truth_held(&self.truth, mission)
    }
}

/// The truth kept the separation (scaled, under an ellipsoid) and the speed limit.
fn truth_held(truth: &TruthReport, mission: &Mission) -> bool {
    let l = &mission.limits;
    let separated = match truth.min_scaled_separation {
        Some(scaled) => scaled >= 1.0,
        None => truth.min_separation_m >= l.safety_distance_m,
    };
    separated && truth.top_speed_mps <= l.max_speed_mps * 1.05
}

/// Refuses a split of `vehicles` into `relays` that leaves a relay more than
/// [`RELAY_CAPACITY`] vehicles (or no relay at all).
pub fn check_shares(vehicles: usize, relays: usize) -> Result<(), HarnessError> {
    if relays == 0 || vehicles.div_ceil(relays) > RELAY_CAPACITY {
        return Err(HarnessError::RelayShares {
            vehicles,
            relays,
            needed: vehicles.div_ceil(RELAY_CAPACITY),
        });
    }
    Ok(())
}

/// Flies `plan` (the load mission of `options`, planned in `plan_times_s`)
/// through `relays` relay processes, each `swarmctl relay --sitl` run by the
/// program `swarmctl` (the CLI passes itself): starts them, flies, stops them
/// and reads their reports.
pub fn fly_through_relays(
    mission: &Mission,
    plan: &DiscretePlan,
    plan_times_s: Vec<f64>,
    relays: usize,
    options: &LoadOptions,
    swarmctl: &Path,
) -> Result<RelayRun, HarnessError> {
    let ids: Vec<String> = plan.drones.iter().map(|d| d.id.clone()).collect();
    check_shares(ids.len(), relays)?;
    let dir = std::env::temp_dir().join(format!("swarmctl-bench-relays-{}", std::process::id()));
    let io = |what: &str, path: &Path| {
        let what = format!("{what} {}", path.display());
        move |source| HarnessError::Io { what, source }
    };
    std::fs::create_dir_all(&dir).map_err(io("cannot create", &dir))?;
    let mission_path = dir.join("mission.yaml");
    let file = load::load_mission(
        options.vehicles,
        options.seed,
        options.vertical_separation_m,
    )?;
    std::fs::write(&mission_path, swarmctl::mission::to_yaml(&file))
        .map_err(io("cannot write", &mission_path))?;
    let port = free_port().map_err(io("no free port on", Path::new("127.0.0.1")))?;
    let mut children = Vec::new();
    for (k, share) in ids.chunks(ids.len().div_ceil(relays)).enumerate() {
        children.push(RelayProcess::start(
            swarmctl,
            &mission_path,
            &dir,
            k,
            share,
            port,
            options.flavour,
        )?);
    }
    let runtime = tokio::runtime::Runtime::new().map_err(|source| HarnessError::RuntimeStart {
        runtime: "controller",
        source,
    })?;
    let cpu_before_s = resources::process_cpu_s().unwrap_or(0.0);
    let started = Instant::now();
    let flown = runtime.block_on(fly_watched(mission, plan, &ids, port, options));
    let wall_s = started.elapsed().as_secs_f64();
    let controller_cpu_s = resources::process_cpu_s().unwrap_or(0.0) - cpu_before_s;
    let mut reports = Vec::new();
    for child in children {
        reports.push(child.stop()?);
    }
    let _ = std::fs::remove_dir_all(&dir);
    let (log, truth) = flown?;
    Ok(RelayRun {
        drones: ids.len(),
        relays: reports,
        log,
        truth,
        plan_times_s,
        controller_cpu_s,
        controller_peak_rss_bytes: resources::peak_rss_bytes().unwrap_or(0),
        wall_s,
    })
}

/// The controller: waits for the relays, flies with the truth watched.
async fn fly_watched(
    mission: &Mission,
    plan: &DiscretePlan,
    ids: &[String],
    port: u16,
    options: &LoadOptions,
) -> Result<(Option<FlightLog>, TruthReport), HarnessError> {
    let zenoh = ZenohEndpoints {
        role: Role::Router,
        listen: vec![format!("tcp/127.0.0.1:{port}")],
        connect: Vec::new(),
    };
    let links = RelayLinks::connect(
        &zenoh,
        &mission.name,
        ids,
        Duration::from_secs(120),
        |_, _| {},
    )
    .await?;
    let l = &mission.limits;
    let ellipsoid = l.is_ellipsoid().then(|| l.separation());
    let truth = TruthWatch::start(
        links.session(),
        &KeySpace::new(&mission.name),
        ellipsoid,
        10.0,
    )
    .await?;
    let mut fly_options = fly::FlyOptions::new(links.vehicle_links());
    fly_options.ready_timeout = Duration::from_secs(60);
    let (_abort, abort_rx) = tokio::sync::watch::channel(false);
    let flown = tokio::time::timeout(
        options.limit,
        fly::fly(mission, plan, &fly_options, abort_rx),
    )
    .await;
    let report = truth.report();
    drop(truth);
    links.close().await;
    let log = match flown {
        Ok(result) => Some(result?),
        Err(_) => None,
    };
    Ok((log, report))
}

fn free_port() -> std::io::Result<u16> {
    let listener = std::net::TcpListener::bind("127.0.0.1:0")?;
    Ok(listener.local_addr()?.port())
}
