//! Leaving the air: landing where the drone is (once its column is clear), or,
//! when it can never land safely, handing it to the autopilot's position hold.

use super::DroneRun;
use crate::fly::command::{Command, Request};
use crate::fly::log::LogEvent;
use crate::fly::path::distance_m;
use crate::fly::phase::{FailReason, Phase};

impl DroneRun {
    /// Plan execution is over: notes the distance to the goal and queues the
    /// drone for landing. A drone that failed anything but landing still lands
    /// (or, on the ground, disarms): nobody is left armed.
    pub fn prepare_landing(&mut self) {
        if let Some(p) = self.telemetry.position_m {
            self.final_distance_to_goal_m = Some(distance_m(p, self.route.goal_m()));
        }
        let landing_failed = matches!(self.phase, Phase::Failed(FailReason::Land(_)));
        let done = matches!(
            self.phase,
            Phase::Landed | Phase::Lost { .. } | Phase::Landing { .. }
        );
        if !done && !landing_failed {
            self.phase = Phase::AwaitLanding;
        }
    }

    /// Its column is clear: land.
    pub fn begin_landing(&mut self) {
        self.phase = Phase::Landing {
            request: Request::NotSent,
        };
    }

    /// It can never land safely: hand it to the autopilot's hold.
    pub fn hand_over(&mut self) {
        self.phase = Phase::HandedOver {
            request: Request::NotSent,
        };
    }

    /// Handed over and the hold mode answered (either way): nothing more to do.
    pub fn handed_over(&self) -> bool {
        matches!(
            self.phase,
            Phase::HandedOver {
                request: Request::Done(_)
            }
        )
    }

    /// Sends the hold-mode switch once.
    pub(super) fn request_hold(&mut self) {
        if let Phase::HandedOver { request } = &mut self.phase
            && matches!(request, Request::NotSent)
        {
            *request = Request::Sent;
            self.send(Command::Hold);
        }
    }

    /// Sends the land command, then waits for touchdown and disarm.
    pub(super) fn land(&mut self, since_arm_s: f64, events: &mut Vec<LogEvent>) {
        let Phase::Landing { request } = &mut self.phase else {
            return;
        };
        if matches!(request, Request::NotSent) {
            *request = Request::Sent;
            self.send(Command::Land);
            return;
        }
        match request.take_done() {
            None => {}
            Some(Ok(())) => self.phase = Phase::Landed,
            Some(Err(e)) => self.fail(FailReason::Land(e), since_arm_s, events),
        }
    }
}
