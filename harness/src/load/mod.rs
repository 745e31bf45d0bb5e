//! The load benchmark: plan and fly an N-drone mission on N bundled SITL vehicles
//! in one process, and measure what the load costs and whether the flight stays
//! correct under it.
//!
//! The vehicles run on their own tokio runtime (threads named [`SITL_THREAD`]) and
//! the controller on another, so the process's CPU time splits by thread: SITL
//! threads, the truth watcher ([`WATCH_THREAD`], this benchmark's own measuring),
//! and everything else, which is the controller. CPU times come from
//! [`crate::resources`] (the kernel's accounting of user + system time), so this
//! is Linux-only; elsewhere they read as zero.
//!
//! Setpoint timing is measured where a vehicle receives it
//! ([`Swarm::setpoint_intervals`](swarmctl_sitl::Swarm::setpoint_intervals)).
//! Separation is measured from telemetry (the flight log) and from the
//! simulator's true positions over the whole flight.
//!
//! The mission ([`load_mission`]) puts every start on its own x,y column in the
//! lowest layer and every goal on its own column, so vertical takeoff and landing
//! bring no two drones together and the benchmark measures load, not that known
//! limitation.

mod flight;
mod mission;
mod report;
mod table;
mod vehicles;
mod watch;

pub use flight::fly_load;
pub use mission::load_mission;
pub use report::{CpuUse, LoadReport};
pub use table::markdown_table;

use crate::HarnessError;
use std::time::{Duration, Instant};
use swarmctl::mission::Mission;
use swarmctl::plan::{self, DiscretePlan, PlanOptions};
use swarmctl_sitl::Flavour;

/// Name of the SITL runtime's threads (Linux keeps 15 bytes of a thread name).
pub const SITL_THREAD: &str = "load-sitl";
/// Name of the controller runtime's worker threads.
pub const CONTROLLER_THREAD: &str = "load-controller";
/// Name of the thread that samples true positions and resources.
pub const WATCH_THREAD: &str = "load-watch";
/// Sliding window for the busiest stretch of the flight, seconds: long enough to
/// smooth one slow tick, short enough to show a burst (all landing at once).
pub const PEAK_WINDOW_S: usize = 5;
/// A vehicle resting this close (horizontally, metres) to the point below its goal
/// is at its goal.
pub const AT_GOAL_TOLERANCE_M: f64 = 0.3;

/// What to fly.
#[derive(Debug, Clone)]
pub struct LoadOptions {
    /// Drones, one bundled SITL vehicle each (1–254 in one process; through
    /// relays, up to 5000).
    pub vehicles: usize,
    /// Seeds the mission (and the planner's tie-breaking).
    pub seed: u64,
    /// Which autopilot the SITL vehicles imitate (their mode and arming dialects
    /// differ, so the controller's cost does too).
    pub flavour: Flavour,
    /// How many times to plan (the report gives the median time); the first plan flies.
    pub plan_runs: usize,
    /// The whole flight must end within this.
    pub limit: Duration,
    /// Separate the drones by an ellipsoid of this height instead of the 0.25 m
    /// sphere (its horizontal radius stays 0.25 m): the separations are then
    /// judged scaled (`world::Separation`).
    pub vertical_separation_m: Option<f64>,
}

impl LoadOptions {
    /// `vehicles` PX4 vehicles on the mission of `seed`, planned once, with ten
    /// minutes for the flight (200 vehicles take about three).
    pub fn new(vehicles: usize, seed: u64) -> Self {
        Self {
            vehicles,
            seed,
            flavour: Flavour::Px4,
            plan_runs: 1,
            limit: Duration::from_secs(600),
            vertical_separation_m: None,
        }
    }
}

/// Builds the mission for `options` and plans it `plan_runs` times (at least
/// once): the mission, the first plan, and every run's wall time in seconds.
pub fn plan_load(options: &LoadOptions) -> Result<(Mission, DiscretePlan, Vec<f64>), HarnessError> {
    let file = load_mission(
        options.vehicles,
        options.seed,
        options.vertical_separation_m,
    )?;
    let mission =
        swarmctl::mission::validate(&file).map_err(|problems| HarnessError::MissionInvalid {
            mission: file.name.clone(),
            problems,
        })?;
    let plan_options = PlanOptions {
        seed: options.seed,
        ..Default::default()
    };
    let (plan, first_s) = timed_plan(&mission, &plan_options)?;
    let mut times_s = vec![first_s];
    for _ in 1..options.plan_runs {
        times_s.push(timed_plan(&mission, &plan_options)?.1);
    }
    Ok((mission, plan, times_s))
}

/// One planning run and its wall time, seconds.
fn timed_plan(
    mission: &Mission,
    options: &PlanOptions,
) -> Result<(DiscretePlan, f64), HarnessError> {
    let started = Instant::now();
    let solution = plan::solve(mission, options).map_err(|source| HarnessError::Planning {
        mission: mission.name.clone(),
        source,
    })?;
    Ok((solution.plan, started.elapsed().as_secs_f64()))
}

/// Plans and flies the load mission and measures it. Call it outside any tokio
/// runtime: it builds its own two.
pub fn run_load(options: &LoadOptions) -> Result<LoadReport, HarnessError> {
    let (mission, plan, plan_times_s) = plan_load(options)?;
    fly_load(&mission, &plan, plan_times_s, options)
}
