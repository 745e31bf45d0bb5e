//! Flying one scenario: start the bundled SITL with the scenario's faults, fly
//! the mission under an overall limit, and sample the simulator's true positions
//! meanwhile.

use super::cases::Scenario;
use super::judge::Flown;
use super::report::ScenarioReport;
use crate::HarnessError;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;
use swarmctl::fly;
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;
use swarmctl::world::Separation;
use swarmctl_sitl::Swarm;
use swarmctl_sitl::faults::{FaultSpec, parse_fault};
use swarmctl_sitl::truth;

/// Flies `scenario` once with an overall `limit`.
pub async fn run_scenario(
    mission: &Mission,
    plan: &DiscretePlan,
    scenario: &Scenario,
    limit: Duration,
) -> Result<ScenarioReport, HarnessError> {
    let faults: Vec<FaultSpec> = scenario
        .faults
        .iter()
        .map(|f| parse_fault(f))
        .collect::<Result<_, _>>()?;
    let configs = swarmctl_bundled::vehicle_configs(mission, plan, scenario.flavour, &faults)?;
    let (swarm, links) = swarmctl_bundled::start(configs, mission.link.setpoint_rate_hz).await?;
    let mut options = swarmctl_bundled::fly_options(links);
    options.replan = scenario.replan;
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let started = std::time::Instant::now();
    let done = AtomicBool::new(false);
    let flight = async {
        let result = tokio::time::timeout(limit, fly::fly(mission, plan, &options, abort_rx)).await;
        done.store(true, Ordering::Relaxed);
        result
    };
    let ellipsoid = mission
        .limits
        .is_ellipsoid()
        .then(|| mission.limits.separation());
    let (result, (truth_m, truth_scaled, ever_airborne)) =
        tokio::join!(flight, watch_truth(&swarm, ellipsoid, &done));
    let duration_s = started.elapsed().as_secs_f64();
    let still_armed = swarm.armed_system_ids();
    swarm.shutdown().await;
    let flown = Flown {
        result,
        truth_m,
        truth_scaled,
        ever_airborne,
        still_armed,
        duration_s,
    };
    Ok(flown.judge(mission, scenario, limit))
}

/// Samples the simulator's true positions at 50 Hz until `done`: the smallest
/// distance between two airborne vehicles, and whether anyone left the ground.
async fn watch_truth(
    swarm: &Swarm,
    ellipsoid: Option<Separation>,
    done: &AtomicBool,
) -> (f64, Option<f64>, bool) {
    let mut min_m = f64::INFINITY;
    let mut min_scaled = ellipsoid.map(|_| f64::INFINITY);
    let mut ever_airborne = false;
    let mut airborne = Vec::with_capacity(swarm.len());
    while !done.load(Ordering::Relaxed) {
        truth::airborne_positions(swarm, &mut airborne);
        min_m = min_m.min(truth::min_separation_m(&airborne));
        if let (Some(e), Some(min)) = (&ellipsoid, &mut min_scaled) {
            *min = min.min(truth::min_scaled_separation(&airborne, |d| e.scaled(d)));
        }
        ever_airborne |= !airborne.is_empty();
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    (min_m, min_scaled, ever_airborne)
}
