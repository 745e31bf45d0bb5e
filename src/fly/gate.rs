//! Which events each drone has been *observed* to reach, and which gates are
//! therefore still closed for the others.
//!
//! An event counts as reached only when telemetry shows the drone at or past it
//! along its route (within [`REACH_TOLERANCE_M`], which absorbs the vehicle's
//! sensor noise at rest points) — never because the drone was merely commanded
//! there. A slow or lagging drone therefore holds up exactly the drones whose
//! events depend on it, and a drone whose link is lost holds them up until it is
//! heard again.

use super::path::Route;
use crate::schedule::EventId;

/// Telemetry within this distance short of an event counts as reaching it.
pub const REACH_TOLERANCE_M: f64 = 0.03;

/// Observed progress of one drone along its route.
#[derive(Debug, Clone, Default)]
pub struct Progress {
    /// Events `0..reached` have been observed reached.
    pub reached: usize,
    /// The run the telemetry is on (advances only when its end is observed).
    pub observed_run: usize,
    /// Observed arc length along the route (monotone).
    pub observed_arc_m: f64,
}

impl Progress {
    /// Folds in a telemetry position (ENU) given the commanded arc and run.
    pub fn observe(
        &mut self,
        route: &Route,
        position_m: [f64; 3],
        commanded_arc_m: f64,
        commanded_run: usize,
    ) {
        while let Some(run) = route.runs.get(self.observed_run) {
            let along = run.project_m(position_m);
            self.observed_arc_m = self.observed_arc_m.max(run.arc_start_m + along);
            if along >= run.length_m - REACH_TOLERANCE_M && self.observed_run < commanded_run {
                self.observed_run += 1;
            } else {
                break;
            }
        }
        let arc = self.observed_arc_m.min(commanded_arc_m);
        while let Some(e) = route.events.get(self.reached) {
            if arc >= e.arc_m - REACH_TOLERANCE_M {
                self.reached += 1;
            } else {
                break;
            }
        }
    }

    /// True if the drone's telemetry has reached event `index`.
    pub fn has_reached(&self, index: u32) -> bool {
        (index as usize) < self.reached
    }
}

/// Arc length of the first event ahead of `commanded_arc_m` whose predecessors are
/// not all reached (∞ if none), and the drone it waits for. `passed` counts the
/// events already behind the commanded position (kept by the caller, monotone).
pub fn closed_gate(
    route: &Route,
    passed: &mut usize,
    all: &[Progress],
    commanded_arc_m: f64,
) -> (f64, Option<u32>) {
    const PASSED_EPS_M: f64 = 1e-6;
    while let Some(e) = route.events.get(*passed) {
        if e.arc_m < commanded_arc_m - PASSED_EPS_M {
            *passed += 1;
        } else {
            break;
        }
    }
    for e in &route.events[*passed..] {
        if let Some(blocker) = e.after.iter().find(|id| !is_reached(all, **id)) {
            return (e.arc_m, Some(blocker.drone));
        }
    }
    (f64::INFINITY, None)
}

fn is_reached(all: &[Progress], id: EventId) -> bool {
    all.get(id.drone as usize)
        .is_some_and(|p| p.has_reached(id.index))
}
