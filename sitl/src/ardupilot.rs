//! The ArduPilot Copter imitation: custom-mode numbers, arming only outside
//! LAND and RTL, takeoff by command in GUIDED, targets taken only in GUIDED while
//! flying, RTL on a critical battery, and its parameter table.

use crate::config::VehicleConfig;
use crate::fence::FenceRule;
use crate::imitation::{Imitation, ModeRequestError};
use crate::mode::FlightMode;
use crate::params::Params;
use crate::vehicle::Vehicle;
use mavlink::dialects::common::{MavAutopilot, MavProtocolCapability, MavResult};

/// Copter mode numbers (`ArduCopter/mode.h`).
pub mod copter_mode {
    /// STABILIZE, the mode a Copter boots in.
    pub const STABILIZE: u32 = 0;
    /// GUIDED: follows MAVLink position/velocity targets.
    pub const GUIDED: u32 = 4;
    /// LOITER: holds position.
    pub const LOITER: u32 = 5;
    /// RTL: return to launch and land.
    pub const RTL: u32 = 6;
    /// LAND.
    pub const LAND: u32 = 9;
    /// BRAKE: stop and hold.
    pub const BRAKE: u32 = 17;
}

/// Velocity targets older than this are replaced by a stop (Copter's GUIDED timeout).
pub const VELOCITY_TIMEOUT_S: f64 = 3.0;

/// HEARTBEAT custom_mode for a flight mode.
fn custom_mode(mode: FlightMode) -> u32 {
    match mode {
        FlightMode::Manual => copter_mode::STABILIZE,
        FlightMode::Hold => copter_mode::LOITER,
        FlightMode::Takeoff | FlightMode::Offboard | FlightMode::Guided => copter_mode::GUIDED,
        FlightMode::Land => copter_mode::LAND,
        FlightMode::ReturnToLaunch => copter_mode::RTL,
    }
}

/// Flight mode requested by MAV_CMD_DO_SET_MODE param 2; `None` if the mock does not fly it.
fn mode_from_request(custom: f32) -> Option<FlightMode> {
    if !(custom.is_finite() && custom >= 0.0 && custom.fract() == 0.0) {
        return None;
    }
    match custom as u32 {
        copter_mode::STABILIZE => Some(FlightMode::Manual),
        copter_mode::GUIDED => Some(FlightMode::Guided),
        copter_mode::LOITER | copter_mode::BRAKE => Some(FlightMode::Hold),
        copter_mode::RTL => Some(FlightMode::ReturnToLaunch),
        copter_mode::LAND => Some(FlightMode::Land),
        _ => None,
    }
}

/// Whether Copter allows arming in this mode (it refuses in LAND and RTL).
fn armable(mode: FlightMode) -> bool {
    !matches!(mode, FlightMode::Land | FlightMode::ReturnToLaunch)
}

/// The ArduPilot Copter firmware.
pub(crate) struct ArduPilot;

impl Imitation for ArduPilot {
    fn name(&self) -> &'static str {
        "ArduPilot"
    }

    fn aliases(&self) -> &'static [&'static str] {
        &["ardupilot", "apm", "arducopter"]
    }

    fn heartbeat_autopilot(&self) -> MavAutopilot {
        MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA
    }

    /// Version words are major << 24 | minor << 16 | patch << 8 | 255 (release).
    fn version(&self) -> (MavProtocolCapability, u32) {
        (
            MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_C_CAST,
            0x0405_00FF,
        )
    }

    fn boot_mode(&self) -> FlightMode {
        FlightMode::Manual
    }

    fn custom_mode(&self, mode: FlightMode) -> u32 {
        custom_mode(mode)
    }

    fn mode_request_of(&self, custom_mode: u32) -> (f32, f32) {
        (custom_mode as f32, 0.0)
    }

    fn mode_from_request(&self, param2: f32, _param3: f32) -> Result<FlightMode, ModeRequestError> {
        mode_from_request(param2).ok_or(ModeRequestError::Unknown)
    }

    fn armable(&self, mode: FlightMode) -> bool {
        armable(mode)
    }

    fn prearm_failure_text(&self) -> &'static str {
        "PreArm: simulated check failure (refuse-arm fault)"
    }

    fn low_battery_text(&self) -> &'static str {
        "Low battery: Battery 1 is low"
    }

    fn critical_battery_failsafe(&self) -> (&'static str, FlightMode) {
        (
            "Battery 1 is critical! Failsafe: RTL",
            FlightMode::ReturnToLaunch,
        )
    }

    fn takes_setpoint(&self, v: &Vehicle) -> bool {
        v.mode == FlightMode::Guided && v.armed && v.airborne()
    }

    fn takeoff(&self, v: &mut Vehicle, p7: f32) -> MavResult {
        if v.mode != FlightMode::Guided {
            return v.refuse(MavResult::MAV_RESULT_FAILED, "Takeoff: not in GUIDED");
        }
        if !v.armed {
            return v.refuse(MavResult::MAV_RESULT_FAILED, "Takeoff: disarmed");
        }
        if !v.landed() {
            return v.refuse(MavResult::MAV_RESULT_FAILED, "Takeoff: already flying");
        }
        if !(p7.is_finite() && p7 > 0.0) {
            return v.refuse(
                MavResult::MAV_RESULT_FAILED,
                "Takeoff: altitude must be > 0",
            );
        }
        v.external = None;
        v.takeoff_height_m = Some(p7);
        MavResult::MAV_RESULT_ACCEPTED
    }

    fn fence(&self, params: &Params) -> Option<FenceRule> {
        fence(params)
    }

    fn params(&self, config: &VehicleConfig) -> Vec<(&'static str, f32)> {
        vec![
            ("PILOT_TKOFF_ALT", 250.0),
            ("WPNAV_SPEED", config.max_speed_mps * 100.0),
            ("WPNAV_ACCEL", config.max_accel_mps2 * 100.0),
            // The position controller's jerk limits, m/s³ (ArduCopter's defaults;
            // flight code sets them, the mock's dynamics do not read them).
            ("PSC_JERK_XY", 5.0),
            ("PSC_JERK_Z", 5.0),
            // The mock has no attitude to tilt: acceleration feed-forward acts at
            // once, so its attitude input time constant is zero.
            ("ATC_INPUT_TC", 0.0),
            ("WPNAV_ACCEL_Z", 100.0),
            ("WPNAV_SPEED_UP", 250.0),
            ("WPNAV_SPEED_DN", 150.0),
            ("LAND_SPEED", 70.0),
            ("FS_GCS_ENABLE", 0.0),
            // ArduCopter's fence defaults: off; altitude, circle and polygon;
            // RTL or land.
            ("FENCE_ENABLE", 0.0),
            ("FENCE_TYPE", 7.0),
            ("FENCE_ACTION", 1.0),
            ("FENCE_ALT_MAX", 100.0),
            ("FENCE_RADIUS", 300.0),
            ("FENCE_MARGIN", 2.0),
            ("SYSID_THISMAV", f32::from(config.system_id)),
        ]
    }
}

/// ArduCopter's fence: on with `FENCE_ENABLE`; `FENCE_TYPE` bit 1 the maximum
/// altitude, bit 2 the circle (the mock keeps no polygon); `FENCE_ACTION` 0
/// reports, 2 lands, 4 brakes, the others return (RTL).
pub(crate) fn fence(params: &Params) -> Option<FenceRule> {
    if params.get("FENCE_ENABLE") != Some(1.0) {
        return None;
    }
    let types = params.get("FENCE_TYPE").unwrap_or(0.0) as u32;
    let action = match params.get("FENCE_ACTION").map(|a| a as u32) {
        Some(0) => None,
        Some(2) => Some(FlightMode::Land),
        Some(4) => Some(FlightMode::Hold),
        _ => Some(FlightMode::ReturnToLaunch),
    };
    Some(FenceRule {
        radius_m: (types & 2 != 0)
            .then(|| crate::fence::limit(params.get("FENCE_RADIUS")))
            .flatten(),
        max_altitude_m: (types & 1 != 0)
            .then(|| crate::fence::limit(params.get("FENCE_ALT_MAX")))
            .flatten(),
        action,
        breach_text: "Fence Breached",
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_round_trip() {
        for (n, mode) in [
            (0.0, FlightMode::Manual),
            (4.0, FlightMode::Guided),
            (5.0, FlightMode::Hold),
            (6.0, FlightMode::ReturnToLaunch),
            (9.0, FlightMode::Land),
        ] {
            assert_eq!(mode_from_request(n), Some(mode));
            assert_eq!(custom_mode(mode) as f32, n);
        }
        assert_eq!(mode_from_request(17.0), Some(FlightMode::Hold));
        assert_eq!(mode_from_request(3.0), None);
        assert_eq!(mode_from_request(-1.0), None);
        assert!(!armable(FlightMode::Land));
        assert!(armable(FlightMode::Guided));
    }
}
