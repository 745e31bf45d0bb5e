//! Back under our control after the autopilot left it: PX4 leaves OFFBOARD when
//! our stream stops for a second (a cut link) and holds, then lands by itself;
//! once telemetry is back, we ask for external control again. Autopilots that
//! stay in external control on a lost stream (ArduPilot's GUIDED) need nothing.

use super::DroneRun;
use crate::fly::command::{Command, Request};
use crate::fly::log::LogEvent;

impl DroneRun {
    /// Asks for external control again once the vehicle, heard again, is out of
    /// it and not in a failsafe of its own. The follower stays paused until the
    /// vehicle is back, then resumes from rest.
    pub(super) fn resume_external_control(&mut self, since_arm_s: f64, events: &mut Vec<LogEvent>) {
        if !self.flavour.leaves_external_control_without_stream() {
            return;
        }
        let mode_name = self.flavour.external_control_name();
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
                        &format!(
                            "vehicle left {mode_name} (offboard-loss failsafe): re-entering it"
                        ),
                    ));
                    self.resume = Request::Sent;
                    self.send(Command::ResumeExternalControl);
                }
            }
            Request::Sent => {}
            done @ Request::Done(_) => {
                let message = match done.take_done() {
                    Some(Err(e)) => format!("{mode_name} re-entry failed (will retry): {e}"),
                    _ => format!("back in {mode_name}: resuming"),
                };
                events.push(LogEvent::new(since_arm_s, Some(&self.id), &message));
            }
        }
    }

    /// A re-entry into external control is in flight (the follower waits for it).
    pub(super) fn resuming(&self) -> bool {
        !matches!(self.resume, Request::NotSent)
    }
}
