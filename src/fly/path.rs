//! A drone's route as one-dimensional progress along its polyline.
//!
//! Every trajectory the scheduler produces is a sequence of straight rest-to-rest
//! runs, and every TPG event lies on that polyline. Measuring both the commanded
//! position and the observed position as *arc length* along the route turns
//! "has the drone passed this event?" into a comparison of two numbers, which is
//! what the gating needs.

use crate::schedule::{EventId, EventKind, ExecutionDrone};
use crate::trajectory::{DroneTrajectory, Profile};
use crate::world::Voxel;

/// One straight run of the route (ENU metres).
#[derive(Debug, Clone, PartialEq)]
pub struct RouteRun {
    /// Where the run starts (at rest).
    pub from_m: [f64; 3],
    /// Where the run ends (at rest).
    pub to_m: [f64; 3],
    /// Straight-line length of the run, metres.
    pub length_m: f64,
    /// Arc length of the route at `from_m`.
    pub arc_start_m: f64,
    /// When the schedule starts this run (mission seconds). Runs never start earlier.
    pub scheduled_start_s: f64,
    /// The scheduled speed profile (used for the planned duration only).
    pub profile: Profile,
}

impl RouteRun {
    /// Unit direction from `from_m` to `to_m`.
    pub fn unit(&self) -> [f64; 3] {
        if self.length_m <= 0.0 {
            return [0.0; 3];
        }
        std::array::from_fn(|i| (self.to_m[i] - self.from_m[i]) / self.length_m)
    }

    /// The point `x_m` metres along the run.
    pub fn point_m(&self, x_m: f64) -> [f64; 3] {
        let u = self.unit();
        std::array::from_fn(|i| self.from_m[i] + u[i] * x_m)
    }

    /// Distance along the run of `position_m`'s projection, clamped to the run.
    pub fn project_m(&self, position_m: [f64; 3]) -> f64 {
        let u = self.unit();
        let along: f64 = (0..3)
            .map(|i| (position_m[i] - self.from_m[i]) * u[i])
            .sum();
        along.clamp(0.0, self.length_m)
    }
}

/// One TPG event placed on the route.
#[derive(Debug, Clone, PartialEq)]
pub struct RouteEvent {
    /// Start, marker or arrival: where a drone may stop and what it holds there
    /// (see `fly::replan`).
    pub kind: EventKind,
    /// The voxel the event is about (as in the TPG).
    pub voxel: Voxel,
    /// The discrete step at which the move containing the event ends.
    pub step: u32,
    /// Where the event lies, ENU metres.
    pub position_m: [f64; 3],
    /// Arc length along the route where the event lies, metres.
    pub arc_m: f64,
    /// When the schedule reaches it, seconds on the plan clock (for the status view).
    pub reach_s: f64,
    /// Events of other drones that must be observed reached before this drone may
    /// move past `arc_m`.
    pub after: Vec<EventId>,
    /// Seconds to wait after the last of `after` was observed reached (a stage's hold).
    pub hold_s: f64,
}

/// A drone's whole route: runs and events, both ordered along the path.
#[derive(Debug, Clone, PartialEq)]
pub struct Route {
    /// The drone's mission id.
    pub id: String,
    /// The pad-layer cell above the drone's pad, where takeoff ends and the route begins.
    pub start_m: [f64; 3],
    /// The straight runs, in order; empty for a drone that stays put.
    pub runs: Vec<RouteRun>,
    /// Its TPG events, in order along the route.
    pub events: Vec<RouteEvent>,
}

impl Route {
    /// Joins a drone's trajectory and its gated events.
    pub fn new(trajectory: &DroneTrajectory, execution: &ExecutionDrone) -> Self {
        let mut arc_m = 0.0;
        let runs: Vec<RouteRun> = trajectory
            .runs
            .iter()
            .map(|r| {
                let run = RouteRun {
                    from_m: r.from_m,
                    to_m: r.to_m,
                    length_m: r.profile.length_m,
                    arc_start_m: arc_m,
                    scheduled_start_s: r.start_s,
                    profile: r.profile,
                };
                arc_m += r.profile.length_m;
                run
            })
            .collect();
        let events = execution
            .events
            .iter()
            .map(|e| RouteEvent {
                kind: e.kind,
                voxel: e.voxel,
                step: e.step,
                position_m: e.position_m,
                arc_m: event_arc_m(&runs, e.reach_s, e.position_m),
                reach_s: e.reach_s,
                after: e.after.clone(),
                hold_s: e.hold_s,
            })
            .collect();
        Route {
            id: trajectory.id.clone(),
            start_m: trajectory.start_m,
            runs,
            events,
        }
    }

    /// Total route length.
    pub fn length_m(&self) -> f64 {
        self.runs.last().map_or(0.0, |r| r.arc_start_m + r.length_m)
    }

    /// Arc length at plan-clock time `t_s` if every run starts when scheduled and
    /// nobody waits: where a drone on schedule is (benchmarks and tests freeze a
    /// swarm there).
    pub fn scheduled_arc_m(&self, t_s: f64) -> f64 {
        self.runs
            .iter()
            .rev()
            .find(|r| r.scheduled_start_s <= t_s)
            .map_or(0.0, |r| {
                r.arc_start_m + r.profile.distance_at_m(t_s - r.scheduled_start_s)
            })
    }

    /// Where the route ends (the goal voxel centre).
    pub fn goal_m(&self) -> [f64; 3] {
        self.runs.last().map_or(self.start_m, |r| r.to_m)
    }
}

/// Every drone's route (plan order): the checked plan's trajectories, the very
/// runs its samples were taken from, joined with its execution graph. Nothing is
/// scheduled again here: what flies is what was checked.
pub fn routes(checked: &crate::compiled::CheckedPlan) -> Vec<Route> {
    joined(checked.trajectories(), &checked.compiled().execution)
}

/// Each drone's trajectory joined with its gated events (plan order).
pub(super) fn joined(
    trajectories: &crate::trajectory::Trajectories,
    execution: &crate::schedule::ExecutionPlan,
) -> Vec<Route> {
    trajectories
        .drones
        .iter()
        .zip(&execution.drones)
        .map(|(t, e)| Route::new(t, e))
        .collect()
}

/// Straight-line distance between two ENU points, metres.
pub fn distance_m(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Arc length of an event: on the run in progress at its scheduled time (or the
/// last finished one), projected onto that run.
fn event_arc_m(runs: &[RouteRun], reach_s: f64, position_m: [f64; 3]) -> f64 {
    const TIME_EPS_S: f64 = 1e-6;
    let k = runs.partition_point(|r| r.scheduled_start_s <= reach_s + TIME_EPS_S);
    match k.checked_sub(1) {
        None => 0.0,
        Some(k) => runs[k].arc_start_m + runs[k].project_m(position_m),
    }
}
