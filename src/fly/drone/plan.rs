//! Following the plan: observed progress from telemetry, the first closed gate
//! ahead, and the follower's commanded motion up to it.

use super::{DroneRun, SwarmTick};
use crate::fly::follower::Hold;
use crate::fly::gate::{Progress, closed_gate};
use crate::fly::lateness::EventLateness;
use crate::fly::path::distance_m;
use crate::fly::phase::Phase;
use crate::fly::settings::LoopSettings;
use std::time::Instant;

/// Telemetry at most this many setpoint periods old is fresh enough to trust the
/// vehicle on its setpoint: a sample or two in flight, no more.
const FRESH_TELEMETRY_PERIODS: f64 = 3.0;

impl DroneRun {
    /// Folds telemetry into observed progress, while the drone is in the plan and
    /// we can see it, recording when each event was reached against the schedule;
    /// then, if the vehicle is trusted right now (see [`DroneRun::trusted`]),
    /// releases the events passed by the setpoint its newest sample was found
    /// within the tracking bound of. The follower starts a run
    /// only once telemetry has settled within `settings.settle_tolerance_m` of the
    /// previous run's end, so that end counts as reached within the same tolerance.
    pub fn observe_progress(
        &mut self,
        t_s: f64,
        settings: &LoopSettings,
        now: Instant,
        since_arm_s: f64,
    ) {
        let observed = matches!(
            self.phase,
            Phase::Flying | Phase::AtGoal | Phase::Retiring { .. }
        );
        self.trusted_now = false;
        if !observed || self.telemetry.link_lost || self.telemetry.stale {
            return;
        }
        let Some(p) = self.telemetry.position_m else {
            return;
        };
        let arc = self.follower.arc_m(&self.route, t_s);
        let run = self.follower.run_index();
        let before = self.progress.reached;
        self.progress
            .observe(&self.route, p, (arc, run), t_s, settings.settle_tolerance_m);
        for (i, e) in self
            .route
            .events
            .iter()
            .enumerate()
            .take(self.progress.reached)
            .skip(before)
        {
            self.lateness.push(EventLateness {
                event: i,
                kind: e.kind,
                voxel: e.voxel,
                scheduled_s: e.reach_s,
                reached_s: t_s,
                flight_s: since_arm_s,
            });
        }
        self.trusted_now = self.trusted(settings, now);
        if self.trusted_now
            && let Some(arc_m) = self.tracking.compared_arc_m(&self.telemetry)
        {
            self.progress.release_commanded(&self.route, arc_m, t_s);
        }
    }

    /// Whether the vehicle can be taken to be where its setpoint is, within the
    /// tracking bound `e`, so that events its setpoint passed may be released
    /// before telemetry reaches them: it flies on our setpoints (in the plan, not
    /// re-entering offboard, its setpoint not held for straying), its newest
    /// position is at most [`FRESH_TELEMETRY_PERIODS`] setpoint periods old, and it
    /// lies within `e` of the setpoint streamed before it. Never with no bound
    /// (`e = 0`): then only telemetry releases.
    fn trusted(&self, settings: &LoopSettings, now: Instant) -> bool {
        let bound_m = settings.tracking_error_m;
        let fresh_s = FRESH_TELEMETRY_PERIODS / settings.setpoint_rate_hz;
        let fresh = self
            .telemetry
            .position_received
            .is_some_and(|t| now.saturating_duration_since(t).as_secs_f64() <= fresh_s);
        matches!(self.phase, Phase::Flying | Phase::AtGoal)
            && bound_m > 0.0
            && fresh
            && !self.resuming()
            && !self.follower.holding_for_tracking()
            && self.tracking_distance_m().is_some_and(|e| e <= bound_m)
    }

    /// Brakes the setpoint and holds it while the vehicle is further from it than the
    /// mission's tracking error (see `Follower::hold_for_tracking`), counting the
    /// holds. Not while paused or aborting, which brake anyway, nor with a zero bound,
    /// which no vehicle keeps.
    fn enforce_tracking(&mut self, settings: &LoopSettings, dt_s: f64, braking: bool) {
        let bound_m = settings.tracking_error_m;
        let straying =
            !braking && bound_m > 0.0 && self.tracking_distance_m().is_some_and(|e| e > bound_m);
        if straying {
            if !self.follower.holding_for_tracking() {
                self.tracking.holds += 1;
            }
            self.tracking.hold_s += dt_s;
        }
        self.follower.hold_for_tracking(straying);
    }

    /// Moves the commanded motion on to the first closed gate (from everyone's
    /// observed `progress`), counting gate waits; at its goal once the route is
    /// done and telemetry has settled there.
    pub fn step_plan(&mut self, settings: &LoopSettings, tick: SwarmTick, progress: &[Progress]) {
        if !matches!(self.phase, Phase::Flying) && !self.phase.retiring_on_our_setpoints() {
            self.progress.clear_commitments();
            return;
        }
        let SwarmTick {
            t_s,
            dt_s,
            aborting,
            swarm_paused,
        } = tick;
        if aborting {
            self.follower.halt();
        }
        let arc = self.follower.arc_m(&self.route, t_s);
        let (gate, blocker) = closed_gate(
            &self.route,
            &mut self.gating.passed_events,
            progress,
            arc,
            t_s,
        );
        let rest_point = self.follower.setpoint(&self.route, t_s).position_m;
        let settled = self
            .telemetry
            .position_m
            .is_some_and(|p| distance_m(p, rest_point) <= settings.settle_tolerance_m);
        let paused =
            self.telemetry.link_lost || self.telemetry.stale || self.resuming() || swarm_paused;
        let was_gated = self.follower.hold == Hold::Gate;
        self.follower.set_paused(paused);
        self.enforce_tracking(settings, dt_s, paused || aborting);
        let setpoint = self.follower.step(&self.route, t_s, dt_s, gate, settled);
        self.streamed_arc_m = self.follower.arc_m(&self.route, t_s);
        // Others may fly through gates this drone's setpoint is committed to open
        // in time, while its vehicle is trusted (see `gate::Progress::commit`).
        if self.trusted_now && matches!(self.phase, Phase::Flying) && !aborting {
            let (route, follower) = (&self.route, &self.follower);
            self.progress
                .commit(route, |arc_m| follower.latest_pass_s(route, arc_m, t_s));
        } else {
            self.progress.clear_commitments();
        }
        // A paused drone waits for its own link, not for a TPG predecessor.
        let gated = self.follower.hold == Hold::Gate && !aborting && !paused;
        self.gating.count(gated, was_gated, blocker, dt_s);
        self.last_setpoint = Some(setpoint);
        if matches!(self.phase, Phase::Flying)
            && self.follower.finished(&self.route)
            && self.settled_at(self.route.goal_m(), settings.settle_tolerance_m)
        {
            self.phase = Phase::AtGoal;
        }
    }
}
