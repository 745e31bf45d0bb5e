//! What goes out to the vehicle: commands, each in its own task with its result
//! handed back to whatever phase waits for it, and the setpoint stream (NED on the
//! wire) in the phases that fly on our setpoints.

use super::DroneRun;
use crate::fly::command::{Command, CommandError, Request};
use crate::fly::feedforward;
use crate::fly::phase::Phase;
use crate::link::frames;

impl DroneRun {
    /// Starts `command` in its own task; its result comes back through the loop's
    /// inbox to [`DroneRun::deliver`].
    pub(super) fn send(&self, command: Command) {
        self.commands.spawn(
            self.index,
            command,
            self.session.clone(),
            self.flavour.modes(),
        );
    }

    /// Hands a finished command's result to whatever waits for it. A result that
    /// nobody waits for any more (the phase moved on, as an abort does to a
    /// takeoff) is dropped, as the command's task was.
    pub fn deliver(&mut self, command: Command, result: Result<(), CommandError>) {
        let waiting = match (command, &mut self.phase) {
            (Command::ResumeExternalControl, _) => &mut self.resume,
            (Command::Land, Phase::Landing { request })
            | (Command::Hold, Phase::HandedOver { request }) => request,
            (command, Phase::TakingOff(takeoff)) => match takeoff.waiting_for(command) {
                Some(request) => request,
                None => return,
            },
            _ => return,
        };
        if matches!(waiting, Request::Sent) {
            *waiting = Request::Done(result);
        }
    }

    /// Whether this drone gets our setpoint stream this tick.
    fn streaming(&self) -> bool {
        match self.phase {
            Phase::TakingOff(ref takeoff) => takeoff.streams(self.last_setpoint.is_some()),
            Phase::AtStart
            | Phase::Flying
            | Phase::AtGoal
            | Phase::AwaitLanding
            | Phase::Lost { .. } => true,
            ref phase => phase.retiring_on_our_setpoints(),
        }
    }

    /// Sends the drone its setpoint (NED on the wire) if it is streaming.
    pub async fn stream_setpoint(&self) {
        if !self.streaming() {
            return;
        }
        if let Some(s) = self.last_setpoint {
            let accel_mps2 = feedforward::acceleration_to_send(
                &s,
                self.telemetry.position_m,
                self.speed_clamp.as_ref(),
            );
            // A failed send is one missed setpoint; the vehicle's own timeout and our
            // link-loss detection deal with a link that stays down.
            let _ = self
                .session
                .send_setpoint(
                    self.placed.frame.local_from_mission(s.position_m),
                    frames::ned_f32_from_enu(s.velocity_mps),
                    frames::ned_f32_from_enu(accel_mps2),
                )
                .await;
        }
    }
}
