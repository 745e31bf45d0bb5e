//! The phase machine: the transitions that depend on commands and telemetry
//! (dispatched to the takeoff, landing and hand-over steps), and those the loop
//! and the contingencies ask for (start, lost, rejoined, retiring, landed).

use super::DroneRun;
use crate::fly::autopilot::{TakeoffStep, TakeoffTick};
use crate::fly::follower::Setpoint;
use crate::fly::log::LogEvent;
use crate::fly::phase::{FailReason, Phase, RetireStage, Retirement};
use crate::fly::settings::LoopSettings;
use std::time::Instant;

impl DroneRun {
    /// Phase transitions that depend on commands and telemetry rather than the plan.
    pub fn advance(
        &mut self,
        settings: &LoopSettings,
        now: Instant,
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) {
        match &self.phase {
            Phase::TakingOff(_) => self.take_off(settings, now, since_arm_s, events),
            Phase::AtStart => self.last_setpoint = Some(self.hold_start()),
            // Out of the airspace, out of external control is its own fence's
            // doing (PX4 holds, then lands): never taken back (`contingency`).
            Phase::Flying | Phase::AtGoal if self.outside_airspace_m(settings).is_some() => {}
            Phase::Flying | Phase::AtGoal => self.resume_external_control(since_arm_s, events),
            phase if phase.retiring_on_our_setpoints() => {
                self.resume_external_control(since_arm_s, events);
            }
            Phase::HandedOver { .. } => self.request_hold(),
            Phase::Landing { .. } => self.land(since_arm_s, events),
            Phase::Lost { .. }
            | Phase::AwaitLanding
            | Phase::Retiring { .. }
            | Phase::Landed
            | Phase::Failed(_) => {}
        }
    }

    /// One tick of the takeoff its autopilot does: commands it asks for go out,
    /// a refusal gives the drone up, and at the start voxel it waits for everyone.
    fn take_off(
        &mut self,
        settings: &LoopSettings,
        now: Instant,
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) {
        let Phase::TakingOff(takeoff) = &mut self.phase else {
            return;
        };
        let landed_state = self.session.state().landed_state;
        let (telemetry, settling) = (&self.telemetry, &mut self.settling);
        let mut settled_at = |point_m, tolerance_m| settling.at(telemetry, point_m, tolerance_m);
        let mut tick = TakeoffTick {
            now,
            settings,
            start_m: self.route.start_m,
            position_m: self.telemetry.position_m,
            landed_state,
            setpoint: &mut self.last_setpoint,
            settled_at: &mut settled_at,
        };
        match takeoff.step(&mut tick) {
            TakeoffStep::Continue => {}
            TakeoffStep::Send(command) => self.send(command),
            TakeoffStep::AtStart => self.phase = Phase::AtStart,
            TakeoffStep::Refused { step, error } => {
                self.fail(FailReason::Takeoff { step, error }, since_arm_s, events);
            }
        }
    }

    /// A setpoint holding above the pad (where the route begins).
    pub(super) fn hold_start(&self) -> Setpoint {
        Setpoint::rest(self.route.start_m)
    }

    /// Gives up on the drone for `reason`, logging it.
    pub(super) fn fail(
        &mut self,
        reason: FailReason,
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) {
        events.push(LogEvent::new(
            since_arm_s,
            Some(&self.id),
            &reason.to_string(),
        ));
        self.phase = Phase::Failed(reason);
    }

    /// Everyone is at the start: the plan clock runs.
    pub fn start_plan(&mut self) {
        self.phase = Phase::Flying;
    }

    /// Silent for too long: given up for now; its commanded motion pauses.
    pub fn mark_lost(&mut self) {
        self.follower.set_paused(true);
        self.phase = Phase::Lost {
            was_at_goal: matches!(self.phase, Phase::AtGoal),
        };
    }

    /// Heard again after being lost: back where it was in the plan.
    pub fn rejoin_plan(&mut self) {
        if let Phase::Lost { was_at_goal } = self.phase {
            self.phase = if was_at_goal {
                Phase::AtGoal
            } else {
                Phase::Flying
            };
        }
    }

    /// Leaves the plan early for `why`: brakes and starts down at `stage`.
    pub fn retire(&mut self, why: Retirement, stage: RetireStage) {
        self.follower.halt();
        self.membership.retired = Some(why);
        self.phase = Phase::Retiring { stage };
    }

    /// Moves a retiring drone to `stage` (waiting for its column, halting again).
    pub fn set_retire_stage(&mut self, stage: RetireStage) {
        if matches!(self.phase, Phase::Retiring { .. }) {
            self.phase = Phase::Retiring { stage };
        }
    }

    /// Its autopilot brought it down and disarmed it.
    pub fn mark_landed(&mut self) {
        self.phase = Phase::Landed;
    }
}
