//! ArduPilot Copter: follows our setpoints in GUIDED, takes off by command
//! (MAV_CMD_NAV_TAKEOFF in GUIDED, which it must be in before arming) and climbs
//! by itself; we stream setpoints only once it is nearly up, to correct the last
//! centimetres. It stays in GUIDED when our stream stops.

use super::flavour::{Flavour, OwnLimits, Setting};
use super::takeoff::{Takeoff, TakeoffStep, TakeoffTick};
use crate::fly::command::{Command, Request};
use crate::fly::fence::VehicleFence;
use crate::fly::follower::Setpoint;
use crate::link::{ModeRequest, ParamValue};
use crate::mission::{Autopilot, FenceAction};
use mavlink::dialects::common::{MavAutopilot, MavLandedState};

/// Copter reports takeoff done within some 0.1–0.2 m of the target height and then
/// holds; from this close we take over with our own setpoint for the last bit.
const TAKEOFF_NEAR_M: f64 = 0.3;

/// Above this height a vehicle has certainly left the ground.
const TAKEOFF_STARTED_M: f64 = 0.2;

/// ArduPilot Copter modes are plain numbers.
const fn mode(number: u8) -> ModeRequest {
    ModeRequest {
        param2: number as f32,
        param3: 0.0,
        custom_mode: number as u32,
    }
}

/// The ArduPilot Copter autopilot.
pub(super) struct ArduCopter;

impl Flavour for ArduCopter {
    fn autopilot(&self) -> Autopilot {
        Autopilot::Ardupilot
    }

    fn heartbeat_autopilot(&self) -> MavAutopilot {
        MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA
    }

    fn external_control_mode(&self) -> ModeRequest {
        mode(4) // GUIDED
    }

    fn external_control_name(&self) -> &'static str {
        "GUIDED"
    }

    fn hold_mode(&self) -> ModeRequest {
        mode(17) // BRAKE
    }

    fn land_mode(&self) -> ModeRequest {
        mode(9) // LAND
    }

    fn return_mode(&self) -> ModeRequest {
        mode(6) // RTL
    }

    fn external_control_before_arming(&self) -> bool {
        true
    }

    fn leaves_external_control_without_stream(&self) -> bool {
        false
    }

    fn takeoff(&self) -> Box<dyn Takeoff> {
        Box::new(CopterTakeoff::Command {
            request: Request::NotSent,
        })
    }

    /// ArduCopter stays within 1 % of `WPNAV_SPEED` (truth 1.01 m/s at 1 m/s,
    /// 8 vehicles): none.
    fn own_speed_overshoot(&self) -> f64 {
        0.0
    }

    /// Centimetres per second (squared), ArduCopter's units; jerk in m/s³.
    /// `LAND_SPEED` is its own landing below `LAND_ALT_LOW`, never raised.
    fn limit_parameters(&self, l: OwnLimits) -> Vec<(&'static str, Setting)> {
        vec![
            ("WPNAV_SPEED", Setting::To(100.0 * l.max_speed_mps)),
            ("WPNAV_SPEED_UP", Setting::To(100.0 * l.max_speed_mps)),
            ("WPNAV_SPEED_DN", Setting::To(100.0 * l.max_speed_mps)),
            ("WPNAV_ACCEL", Setting::To(100.0 * l.max_accel_mps2)),
            ("WPNAV_ACCEL_Z", Setting::To(100.0 * l.max_accel_mps2)),
            ("PSC_JERK_XY", Setting::To(l.max_jerk_mps3)),
            ("PSC_JERK_Z", Setting::To(l.max_jerk_mps3)),
            ("LAND_SPEED", Setting::AtMost(100.0 * l.commanded_speed_mps)),
        ]
    }

    /// `FENCE_TYPE` 3: the maximum altitude and the circle around home.
    /// `FENCE_ACTION` 2 always lands (1 would try RTL first, flying back across
    /// the swarm); 0 only reports. `FENCE_MARGIN` is the room its own avoidance
    /// keeps from the fence in pilot-flown modes: the mission's margin, so that a
    /// pilot who takes over is held at the airspace's edge. `FENCE_ENABLE` last.
    fn fence_parameters(&self, fence: &VehicleFence) -> Vec<(&'static str, ParamValue)> {
        let action = match fence.action {
            FenceAction::Land => 2.0,
            FenceAction::Report => 0.0,
        };
        vec![
            ("FENCE_TYPE", ParamValue::Real(3.0)),
            ("FENCE_ACTION", ParamValue::Real(action)),
            (
                "FENCE_ALT_MAX",
                ParamValue::Real(fence.max_altitude_m as f32),
            ),
            ("FENCE_RADIUS", ParamValue::Real(fence.radius_m as f32)),
            ("FENCE_MARGIN", ParamValue::Real(fence.margin_m as f32)),
            ("FENCE_ENABLE", ParamValue::Real(1.0)),
        ]
    }

    /// Copter smooths every attitude command with `ATC_INPUT_TC`.
    fn accel_lead_parameter(&self) -> Option<&'static str> {
        Some("ATC_INPUT_TC")
    }

    /// ArduCopter shapes its own target within `WPNAV_*` and `PSC_JERK_*`: the
    /// feed-forward cannot push it past them.
    fn position_gain_parameters(&self) -> Option<[&'static str; 2]> {
        None
    }
}

/// Where a Copter takeoff is.
#[derive(Debug)]
enum CopterTakeoff {
    /// The vehicle's own takeoff to the start altitude, commanded.
    Command {
        /// The takeoff command.
        request: Request,
    },
    /// Takeoff accepted, climbing to the start altitude.
    AwaitAltitude,
}

/// Telemetry shows the vehicle leaving the ground: above [`TAKEOFF_STARTED_M`],
/// or EXTENDED_SYS_STATE saying it is taking off or in the air.
fn taking_off(tick: &TakeoffTick<'_>) -> bool {
    use MavLandedState as L;
    let climbing = tick.position_m.is_some_and(|p| p[2] > TAKEOFF_STARTED_M);
    climbing
        || matches!(
            tick.landed_state,
            Some(L::MAV_LANDED_STATE_TAKEOFF | L::MAV_LANDED_STATE_IN_AIR)
        )
}

impl Takeoff for CopterTakeoff {
    fn step(&mut self, tick: &mut TakeoffTick<'_>) -> TakeoffStep {
        match self {
            CopterTakeoff::Command { request } => {
                if matches!(request, Request::NotSent) {
                    *request = Request::Sent;
                    // MAVLink's takeoff height is f32 metres; voxel heights are small.
                    let height_m = tick.start_m[2] as f32;
                    return TakeoffStep::Send(Command::Takeoff { height_m });
                }
                match request.take_done() {
                    None => TakeoffStep::Continue,
                    // A lost ACK makes the retry meet a vehicle already climbing,
                    // which Copter answers FAILED ("Takeoff: already flying"):
                    // telemetry decides, by height or by the landed state it reports.
                    Some(Err(_)) if taking_off(tick) => {
                        *self = CopterTakeoff::AwaitAltitude;
                        TakeoffStep::Continue
                    }
                    Some(Err(e)) => TakeoffStep::refused("takeoff", e),
                    Some(Ok(())) => {
                        *self = CopterTakeoff::AwaitAltitude;
                        TakeoffStep::Continue
                    }
                }
            }
            CopterTakeoff::AwaitAltitude => {
                // Copter climbs by itself; stream only once it is up, then correct
                // the last centimetres with our setpoint.
                let start_m = tick.start_m;
                if tick
                    .position_m
                    .is_some_and(|p| p[2] >= start_m[2] - TAKEOFF_NEAR_M)
                {
                    *tick.setpoint = Some(Setpoint::rest(start_m));
                    if (tick.settled_at)(start_m, tick.settings.settle_tolerance_m) {
                        return TakeoffStep::AtStart;
                    }
                }
                TakeoffStep::Continue
            }
        }
    }

    fn waiting_for(&mut self, command: Command) -> Option<&mut Request> {
        match (command, self) {
            (Command::Takeoff { .. }, CopterTakeoff::Command { request }) => Some(request),
            _ => None,
        }
    }

    fn streams(&self, has_setpoint: bool) -> bool {
        match self {
            CopterTakeoff::Command { .. } => false,
            CopterTakeoff::AwaitAltitude => has_setpoint,
        }
    }

    fn name(&self) -> &'static str {
        "takeoff"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_are_copter_numbers() {
        assert_eq!(ArduCopter.external_control_mode().custom_mode, 4);
        assert_eq!(ArduCopter.land_mode().custom_mode, 9);
        assert_eq!(ArduCopter.return_mode().custom_mode, 6);
    }
}
