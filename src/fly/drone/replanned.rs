//! Joining and leaving a plan, as the contingencies and replans ask: retired
//! and released drones, the new route a replan splices in, and a drone a replan
//! flies on without.

use super::DroneRun;
use crate::fly::follower::Setpoint;
use crate::fly::gate::Progress;
use crate::fly::path::Route;
use crate::fly::phase::{Phase, Retirement};

impl DroneRun {
    /// Why it left the plan early, if it did.
    pub fn retired(&self) -> Option<Retirement> {
        self.membership.retired
    }

    /// Retired, down, and its remaining events released.
    pub fn released(&self) -> bool {
        self.membership.released
    }

    /// Flies `route` from here on, a replan's: the old route's progress, gates and
    /// commanded motion are gone (the follower starts at rest at the route's start,
    /// where the freeze left it).
    pub fn splice(&mut self, route: Route) {
        self.route = route;
        self.follower = self.follower.restarted();
        self.progress = Progress::default();
        self.streamed_arc_m = 0.0;
        self.tracking.forget_arcs();
        self.gating.restart();
        self.settling.restart();
        if matches!(self.phase, Phase::AtGoal) {
            self.phase = Phase::Flying;
        }
    }

    /// A replan flies on without it.
    pub fn leave_plan(&mut self) {
        self.membership.left_plan = true;
    }

    /// A replan flies on without it (lost, or retired and down).
    pub fn left_plan(&self) -> bool {
        self.membership.left_plan
    }

    /// Heard again after a replan left it out: it holds where it is and lands
    /// once its column is clear (nobody was planned into it).
    pub fn land_out_of_plan(&mut self) {
        if let Some(p) = self.telemetry.position_m {
            self.last_setpoint = Some(Setpoint::rest(p));
        }
        self.phase = Phase::AwaitLanding;
    }

    /// A retired drone that is down: its remaining events no longer hold anyone
    /// up when `ground_clear`. Marks it released either way (once).
    pub fn release_events(&mut self, ground_clear: bool) {
        self.membership.released = true;
        if ground_clear {
            self.progress.release_all(self.route.events.len());
        }
    }
}
