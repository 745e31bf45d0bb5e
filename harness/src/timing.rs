//! `swarmctl bench timing`: how long plan execution takes against the schedule
//! on the bundled simulator, whose vehicles track their setpoints within
//! centimetres — so every second beyond the plan is the executor's.
//!
//! Each mission is planned once and flown `runs` times, each flight on a fresh
//! simulated swarm; the simulator's true positions are sampled meanwhile, so the
//! table's separation and speed are measured, not reported by the flight.

use crate::HarnessError;
use crate::stats::median;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;
use swarmctl::fly::{self, FlightLog};
use swarmctl::mission::Mission;
use swarmctl::plan::{self, DiscretePlan};
use swarmctl_sitl::{Swarm, truth};

/// One flight of one mission.
#[derive(Debug, Clone)]
pub struct TimingFlight {
    /// Plan execution, seconds (`None`: it never finished).
    pub executed_s: Option<f64>,
    /// The flight log, for lateness and gating figures.
    pub log: FlightLog,
    /// Smallest true distance between two airborne vehicles, metres.
    pub truth_min_separation_m: f64,
    /// Highest true speed of any vehicle, metres per second.
    pub truth_max_speed_mps: f64,
}

/// Every flight of one mission.
#[derive(Debug, Clone)]
pub struct TimingReport {
    /// The mission's name.
    pub mission: String,
    /// Drones flown.
    pub drones: usize,
    /// The schedule's makespan, seconds.
    pub planned_s: f64,
    /// The mission's safety distance, metres.
    pub safety_distance_m: f64,
    /// The mission's speed limit, metres per second.
    pub speed_limit_mps: f64,
    /// The flights, in order.
    pub flights: Vec<TimingFlight>,
}

impl TimingReport {
    /// Median plan execution over the flights that finished, seconds.
    pub fn median_executed_s(&self) -> Option<f64> {
        let done: Vec<f64> = self.flights.iter().filter_map(|f| f.executed_s).collect();
        (!done.is_empty()).then(|| median(&done))
    }

    /// Median execution over planned (`None` if no flight finished).
    pub fn ratio(&self) -> Option<f64> {
        Some(self.median_executed_s()? / self.planned_s)
    }

    /// Every flight completed, and the simulator's truth kept the safety distance
    /// and the speed limit (within the summary's tolerance).
    pub fn safe_and_complete(&self) -> bool {
        self.flights.iter().all(|f| {
            f.log.summary.succeeded()
                && f.truth_min_separation_m >= self.safety_distance_m
                && f.truth_max_speed_mps <= self.speed_limit_mps * (1.0 + fly::SPEED_TOLERANCE)
        })
    }
}

/// Plans `mission` once and flies it `runs` times on the bundled simulator, each
/// flight given at most `limit`.
pub async fn time_mission(
    mission: &Mission,
    runs: usize,
    limit: Duration,
) -> Result<TimingReport, HarnessError> {
    let plan = plan::solve(mission, &plan::PlanOptions::default())
        .map_err(|source| HarnessError::Planning {
            mission: mission.name.clone(),
            source,
        })?
        .plan;
    let mut flights = Vec::new();
    for _ in 0..runs {
        flights.push(fly_once(mission, &plan, limit).await?);
    }
    let planned_s = flights
        .first()
        .map_or(0.0, |f| f.log.summary.planned_makespan_s);
    Ok(TimingReport {
        mission: mission.name.clone(),
        drones: mission.drone_count(),
        planned_s,
        safety_distance_m: mission.limits.safety_distance_m,
        speed_limit_mps: mission.limits.max_speed_mps,
        flights,
    })
}

async fn fly_once(
    mission: &Mission,
    plan: &DiscretePlan,
    limit: Duration,
) -> Result<TimingFlight, HarnessError> {
    let flavour = swarmctl_bundled::flavour(mission.link.autopilot);
    let configs = swarmctl_bundled::vehicle_configs(mission, plan, flavour, &[])?;
    let (swarm, links) = swarmctl_bundled::start(configs, mission.link.setpoint_rate_hz).await?;
    let options = swarmctl_bundled::fly_options(links);
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let done = AtomicBool::new(false);
    let flight = async {
        let result = tokio::time::timeout(limit, fly::fly(mission, plan, &options, abort_rx)).await;
        done.store(true, Ordering::Relaxed);
        result
    };
    let (result, (min_m, max_speed_mps)) = tokio::join!(flight, watch(&swarm, &done));
    swarm.shutdown().await;
    let log = result.map_err(|_| HarnessError::FlightUnfinished {
        mission: mission.name.clone(),
        limit_s: limit.as_secs_f64(),
    })??;
    Ok(TimingFlight {
        executed_s: log.summary.executed_makespan_s,
        log,
        truth_min_separation_m: min_m,
        truth_max_speed_mps: max_speed_mps,
    })
}

/// Samples the simulator's true positions and velocities at 50 Hz until `done`:
/// the smallest distance between two airborne vehicles and the highest speed.
async fn watch(swarm: &Swarm, done: &AtomicBool) -> (f64, f64) {
    let mut min_m = f64::INFINITY;
    let mut max_speed_mps: f64 = 0.0;
    let mut airborne = Vec::with_capacity(swarm.len());
    while !done.load(Ordering::Relaxed) {
        truth::airborne_positions(swarm, &mut airborne);
        min_m = min_m.min(truth::min_separation_m(&airborne));
        for i in 0..swarm.len() {
            let v = swarm.snapshot(i).velocity_ned_mps;
            let speed = v.iter().map(|c| f64::from(*c).powi(2)).sum::<f64>().sqrt();
            max_speed_mps = max_speed_mps.max(speed);
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    (min_m, max_speed_mps)
}

/// The table `swarmctl bench timing` prints: per mission the plan, the median
/// execution and its ratio, lateness and gating waits (the median flight's), and
/// what the simulator's truth measured over all flights.
pub fn markdown_table(reports: &[TimingReport]) -> String {
    let mut out = String::from(
        "| mission | drones | planned | executed (median) | ratio | lateness p50 / p95 / max | gating waits (longest) | min separation, truth | max speed, truth | safe and complete |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in reports {
        let median_flight = median_flight(r);
        let lateness = median_flight
            .and_then(|f| f.log.summary.lateness.as_ref())
            .map_or("–".to_string(), |l| {
                format!("{:.2} / {:.2} / {:.2} s", l.p50_s, l.p95_s, l.max_s)
            });
        let waits = median_flight.map_or("–".to_string(), |f| {
            let s = &f.log.summary;
            match &s.longest_gating_wait {
                Some((id, longest_s)) => format!("{} ({longest_s:.1} s, {id})", s.gating_waits),
                None => s.gating_waits.to_string(),
            }
        });
        let min_sep = r
            .flights
            .iter()
            .map(|f| f.truth_min_separation_m)
            .fold(f64::INFINITY, f64::min);
        let max_speed = r
            .flights
            .iter()
            .map(|f| f.truth_max_speed_mps)
            .fold(0.0, f64::max);
        out += &format!(
            "| {} | {} | {:.1} s | {} | {} | {lateness} | {waits} | {min_sep:.3} m (≥ {:.3}) | {max_speed:.2} m/s (≤ {:.2}) | {} |\n",
            r.mission,
            r.drones,
            r.planned_s,
            r.median_executed_s()
                .map_or("not finished".to_string(), |s| format!("{s:.1} s")),
            r.ratio().map_or("–".to_string(), |x| format!("{x:.3}×")),
            r.safety_distance_m,
            r.speed_limit_mps,
            if r.safe_and_complete() { "yes" } else { "NO" },
        );
    }
    out
}

/// The flight whose execution is the median one (the lower of two middles).
fn median_flight(r: &TimingReport) -> Option<&TimingFlight> {
    let mut done: Vec<&TimingFlight> = r
        .flights
        .iter()
        .filter(|f| f.executed_s.is_some())
        .collect();
    done.sort_by(|a, b| {
        a.executed_s
            .partial_cmp(&b.executed_s)
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    done.get(done.len().saturating_sub(1) / 2).copied()
}
