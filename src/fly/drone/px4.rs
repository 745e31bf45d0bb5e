//! PX4 takeoff: stream a ground hold, switch to OFFBOARD, then climb to the start
//! voxel on our own setpoints along a rest-to-rest vertical profile. Also the
//! way back into OFFBOARD after PX4's offboard-loss failsafe left it.

use super::DroneRun;
use crate::fly::command::Command;
use crate::fly::follower::Setpoint;
use crate::fly::log::LogEvent;
use crate::fly::phase::{FailReason, Phase, Request};
use crate::fly::settings::LoopSettings;
use crate::link::Flavour;
use crate::trajectory::Profile;
use std::time::{Duration, Instant};

/// PX4 accepts OFFBOARD only once setpoints are streaming: this long of a ground
/// hold comes first.
const STREAM_BEFORE_OFFBOARD: Duration = Duration::from_millis(500);

impl DroneRun {
    /// Holds on the ground where the vehicle is until OFFBOARD is in, then climbs.
    pub(super) fn enter_offboard(
        &mut self,
        now: Instant,
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) {
        let start_m = self.route.start_m;
        let ground = self
            .telemetry
            .position_m
            .map_or([start_m[0], start_m[1], 0.0], |p| p);
        if self.last_setpoint.is_none() {
            self.last_setpoint = Some(Setpoint::rest(ground));
        }
        let Phase::EnterOffboard { since, request } = &mut self.phase else {
            return;
        };
        if matches!(request, Request::NotSent) {
            if now.duration_since(*since) > STREAM_BEFORE_OFFBOARD {
                *request = Request::Sent;
                self.send(Command::EnterExternalControl);
            }
            return;
        }
        match request.take_done() {
            None => {}
            Some(Ok(())) => {
                let from_z_m = self.last_setpoint.map_or(0.0, |s| s.position_m[2]);
                self.phase = Phase::Climb { t0: now, from_z_m };
            }
            Some(Err(e)) => self.fail(FailReason::Offboard(e), since_arm_s, events),
        }
    }

    /// Climbs along the vertical profile; above its pad once the profile is
    /// done and telemetry has settled there.
    pub(super) fn climb(&mut self, settings: &LoopSettings, now: Instant) {
        let Phase::Climb { t0, from_z_m } = self.phase else {
            return;
        };
        let start_m = self.route.start_m;
        let height_m = start_m[2] - from_z_m;
        let profile = Profile::new(height_m.abs(), settings.limits);
        let tau = now.duration_since(t0).as_secs_f64();
        let sign = height_m.signum();
        let s = profile.state_at(tau);
        self.last_setpoint = Some(Setpoint {
            position_m: [start_m[0], start_m[1], from_z_m + sign * s.x_m],
            velocity_mps: [0.0, 0.0, sign * s.v_mps],
            acceleration_mps2: [0.0, 0.0, sign * s.a_mps2],
        });
        if tau >= profile.duration_s() && self.settled_at(start_m, settings.settle_tolerance_m) {
            self.phase = Phase::AtStart;
        }
    }

    /// PX4 leaves OFFBOARD when our stream stops for a second (a cut link) and
    /// holds, then lands by itself; once telemetry is back, ask for OFFBOARD again.
    /// The follower stays paused until the vehicle is back, then resumes from rest.
    /// ArduPilot stays in GUIDED on a lost stream, so it needs nothing here.
    pub(super) fn resume_external_control(&mut self, since_arm_s: f64, events: &mut Vec<LogEvent>) {
        if self.flavour != Flavour::Px4 {
            return;
        }
        match &mut self.resume {
            Request::NotSent => {
                let current = self.session.state().custom_mode;
                // Land and return are the autopilot's own failsafes: never fight them
                // (`contingency` takes the drone out of the plan instead).
                if self.flavour.is_failsafe_mode(current) {
                    return;
                }
                let mode = self.flavour.external_control_mode();
                let out_of_mode = current != mode.custom_mode;
                if out_of_mode && !self.telemetry.link_lost && !self.telemetry.stale {
                    events.push(LogEvent::new(
                        since_arm_s,
                        Some(&self.id),
                        "vehicle left OFFBOARD (offboard-loss failsafe): re-entering it",
                    ));
                    self.resume = Request::Sent;
                    self.send(Command::ResumeExternalControl);
                }
            }
            Request::Sent => {}
            done @ Request::Done(_) => {
                let message = match done.take_done() {
                    Some(Err(e)) => format!("OFFBOARD re-entry failed (will retry): {e}"),
                    _ => "back in OFFBOARD: resuming".to_string(),
                };
                events.push(LogEvent::new(since_arm_s, Some(&self.id), &message));
            }
        }
    }

    /// A PX4 re-entry into OFFBOARD is in flight (the follower waits for it).
    pub(super) fn resuming(&self) -> bool {
        !matches!(self.resume, Request::NotSent)
    }
}
