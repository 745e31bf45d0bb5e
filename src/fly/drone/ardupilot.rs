//! ArduPilot takeoff: Copter takes off by command (MAV_CMD_NAV_TAKEOFF in GUIDED)
//! and climbs by itself; we stream setpoints only once it is nearly up, to
//! correct the last centimetres.

use super::DroneRun;
use crate::fly::command::Command;
use crate::fly::log::LogEvent;
use crate::fly::phase::{FailReason, Phase, Request};
use crate::fly::settings::LoopSettings;

/// Copter reports takeoff done within some 0.1–0.2 m of the target height and then
/// holds; from this close we take over with our own setpoint for the last bit.
const TAKEOFF_NEAR_M: f64 = 0.3;

/// Above this height a vehicle has certainly left the ground.
const TAKEOFF_STARTED_M: f64 = 0.2;

impl DroneRun {
    /// Sends the takeoff command, then waits for its answer.
    pub(super) fn take_off(&mut self, since_arm_s: f64, events: &mut Vec<LogEvent>) {
        let Phase::Takeoff { request } = &mut self.phase else {
            return;
        };
        if matches!(request, Request::NotSent) {
            *request = Request::Sent;
            // MAVLink's takeoff height is f32 metres; voxel heights are small.
            let height_m = self.route.start_m[2] as f32;
            self.send(Command::Takeoff { height_m });
            return;
        }
        match request.take_done() {
            None => {}
            // A lost ACK makes the retry meet a vehicle already climbing, which
            // Copter answers FAILED ("Takeoff: already flying"): telemetry decides,
            // by height or by the landed state it reports.
            Some(Err(_)) if self.taking_off() => {
                self.phase = Phase::AwaitAltitude;
            }
            Some(Err(e)) => self.fail(FailReason::Takeoff(e), since_arm_s, events),
            Some(Ok(())) => self.phase = Phase::AwaitAltitude,
        }
    }

    /// Telemetry shows the vehicle leaving the ground: above [`TAKEOFF_STARTED_M`],
    /// or EXTENDED_SYS_STATE saying it is taking off or in the air.
    fn taking_off(&self) -> bool {
        use mavlink::dialects::common::MavLandedState as L;
        let climbing = self
            .telemetry
            .position_m
            .is_some_and(|p| p[2] > TAKEOFF_STARTED_M);
        let state = self.session.state().landed_state;
        climbing
            || matches!(
                state,
                Some(L::MAV_LANDED_STATE_TAKEOFF | L::MAV_LANDED_STATE_IN_AIR)
            )
    }

    /// Copter climbs by itself; stream only once it is up, then correct the last
    /// centimetres with our setpoint.
    pub(super) fn await_altitude(&mut self, settings: &LoopSettings) {
        let start_m = self.route.start_m;
        if self
            .telemetry
            .position_m
            .is_some_and(|p| p[2] >= start_m[2] - TAKEOFF_NEAR_M)
        {
            self.last_setpoint = Some(self.hold_start());
            if self.settled_at(start_m, settings.settle_tolerance_m) {
                self.phase = Phase::AtStart;
            }
        }
    }
}
