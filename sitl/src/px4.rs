//! The PX4 imitation: custom-mode encoding (`main << 16 | sub << 24`), OFFBOARD
//! on a setpoint stream, the takeoff-altitude rule (param7 AMSL, else
//! MIS_TAKEOFF_ALT), LAND on a critical battery, and its parameter table.

use crate::config::VehicleConfig;
use crate::fence::FenceRule;
use crate::imitation::{Imitation, ModeRequestError};
use crate::mode::FlightMode;
use crate::params::Params;
use crate::vehicle::Vehicle;
use mavlink::dialects::common::{MavAutopilot, MavProtocolCapability, MavResult};

/// PX4 main mode numbers (`px4_custom_mode.h`).
pub mod main_mode {
    /// Manual.
    pub const MANUAL: u8 = 1;
    /// Altitude control.
    pub const ALTCTL: u8 = 2;
    /// Position control.
    pub const POSCTL: u8 = 3;
    /// Auto modes; the sub mode says which.
    pub const AUTO: u8 = 4;
    /// Acro.
    pub const ACRO: u8 = 5;
    /// Offboard.
    pub const OFFBOARD: u8 = 6;
    /// Stabilized.
    pub const STABILIZED: u8 = 7;
}

/// PX4 AUTO sub mode numbers.
pub mod auto_sub_mode {
    /// Ready.
    pub const READY: u8 = 1;
    /// Takeoff.
    pub const TAKEOFF: u8 = 2;
    /// Loiter, shown as "Hold".
    pub const LOITER: u8 = 3;
    /// Mission.
    pub const MISSION: u8 = 4;
    /// Return to launch.
    pub const RTL: u8 = 5;
    /// Land.
    pub const LAND: u8 = 6;
}

/// Default of PX4's MIS_TAKEOFF_ALT parameter, metres above home.
pub const DEFAULT_TAKEOFF_ALT_M: f32 = 2.5;

/// PX4's default landing descent speed (MPC_LAND_SPEED), m/s.
pub const DEFAULT_LAND_SPEED_MPS: f32 = 0.7;

/// HEARTBEAT custom_mode for a flight mode.
fn custom_mode(mode: FlightMode) -> u32 {
    let (main, sub) = match mode {
        FlightMode::Manual => (main_mode::POSCTL, 0),
        FlightMode::Hold => (main_mode::AUTO, auto_sub_mode::LOITER),
        FlightMode::Takeoff => (main_mode::AUTO, auto_sub_mode::TAKEOFF),
        FlightMode::Offboard | FlightMode::Guided => (main_mode::OFFBOARD, 0),
        FlightMode::Land => (main_mode::AUTO, auto_sub_mode::LAND),
        FlightMode::ReturnToLaunch => (main_mode::AUTO, auto_sub_mode::RTL),
    };
    (u32::from(main) << 16) | (u32::from(sub) << 24)
}

/// Flight mode requested by MAV_CMD_DO_SET_MODE params 2 (main) and 3 (sub).
fn mode_from_request(main: f32, sub: f32) -> Result<FlightMode, ModeRequestError> {
    let main = to_u8(main).ok_or(ModeRequestError::Unknown)?;
    let sub = to_u8(sub).unwrap_or(0);
    match (main, sub) {
        (main_mode::POSCTL, _) => Ok(FlightMode::Manual),
        (main_mode::OFFBOARD, _) => Ok(FlightMode::Offboard),
        (main_mode::AUTO, auto_sub_mode::LOITER) => Ok(FlightMode::Hold),
        (main_mode::AUTO, auto_sub_mode::TAKEOFF) => Ok(FlightMode::Takeoff),
        (main_mode::AUTO, auto_sub_mode::LAND) => Ok(FlightMode::Land),
        (main_mode::AUTO, auto_sub_mode::RTL) => Ok(FlightMode::ReturnToLaunch),
        (main_mode::AUTO, auto_sub_mode::READY | auto_sub_mode::MISSION)
        | (main_mode::MANUAL | main_mode::ALTCTL | main_mode::ACRO | main_mode::STABILIZED, _) => {
            Err(ModeRequestError::Unsupported)
        }
        _ => Err(ModeRequestError::Unknown),
    }
}

/// The PX4 firmware.
pub(crate) struct Px4;

impl Imitation for Px4 {
    fn name(&self) -> &'static str {
        "PX4"
    }

    fn aliases(&self) -> &'static [&'static str] {
        &["px4"]
    }

    fn heartbeat_autopilot(&self) -> MavAutopilot {
        MavAutopilot::MAV_AUTOPILOT_PX4
    }

    /// Version words are major << 24 | minor << 16 | patch << 8 | 255 (release).
    fn version(&self) -> (MavProtocolCapability, u32) {
        (
            MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_BYTEWISE,
            0x010F_00FF,
        )
    }

    fn boot_mode(&self) -> FlightMode {
        FlightMode::Hold
    }

    fn custom_mode(&self, mode: FlightMode) -> u32 {
        custom_mode(mode)
    }

    fn mode_request_of(&self, custom_mode: u32) -> (f32, f32) {
        (
            ((custom_mode >> 16) & 0xff) as f32,
            (custom_mode >> 24) as f32,
        )
    }

    fn mode_from_request(&self, param2: f32, param3: f32) -> Result<FlightMode, ModeRequestError> {
        mode_from_request(param2, param3)
    }

    fn armable(&self, _mode: FlightMode) -> bool {
        true
    }

    fn prearm_failure_text(&self) -> &'static str {
        "Preflight Fail: simulated check failure (refuse-arm fault)"
    }

    fn low_battery_text(&self) -> &'static str {
        "Low battery level! Return advised"
    }

    fn critical_battery_failsafe(&self) -> (&'static str, FlightMode) {
        ("Critical battery level! Landing", FlightMode::Land)
    }

    fn takes_setpoint(&self, _vehicle: &Vehicle) -> bool {
        true
    }

    fn takeoff(&self, v: &mut Vehicle, p7: f32) -> MavResult {
        if !v.armed {
            return v.refuse(MavResult::MAV_RESULT_DENIED, "Takeoff denied: disarmed");
        }
        // PX4's param7 is an AMSL altitude; NaN means MIS_TAKEOFF_ALT.
        let height_m = if p7.is_finite() {
            (f64::from(p7) - v.home.alt_amsl_m) as f32
        } else {
            v.params.takeoff_alt_m()
        };
        if height_m < 0.5 {
            return v.refuse(
                MavResult::MAV_RESULT_DENIED,
                "Takeoff denied: altitude below home (PX4 param7 is AMSL)",
            );
        }
        v.takeoff_height_m = Some(height_m);
        v.set_mode(FlightMode::Takeoff);
        MavResult::MAV_RESULT_ACCEPTED
    }

    fn fence(&self, params: &Params) -> Option<FenceRule> {
        fence(params)
    }

    fn params(&self, config: &VehicleConfig) -> Vec<(&'static str, f32)> {
        vec![
            ("MIS_TAKEOFF_ALT", DEFAULT_TAKEOFF_ALT_M),
            ("COM_OF_LOSS_T", 1.0),
            ("COM_DISARM_LAND", 2.0),
            ("MPC_XY_VEL_MAX", config.max_speed_mps),
            ("MPC_ACC_HOR_MAX", config.max_accel_mps2),
            // PX4's default position gains (1/s), which swarmctl reads to taper
            // its acceleration feed-forward by the velocity clamp.
            ("MPC_XY_P", 0.95),
            ("MPC_Z_P", 1.0),
            // PX4's defaults. The mock descends at MPC_LAND_SPEED from any
            // height (PX4 descends at MPC_Z_V_AUTO_DN above MPC_LAND_ALT2, which
            // mock missions never reach).
            ("MPC_LAND_SPEED", DEFAULT_LAND_SPEED_MPS),
            ("MPC_LAND_CRWL", 0.3),
            ("MPC_Z_V_AUTO_DN", 1.5),
            ("MPC_Z_V_AUTO_UP", 3.0),
            ("MPC_Z_VEL_MAX_DN", 1.5),
            ("MPC_Z_VEL_MAX_UP", 3.0),
            ("MAV_SYS_ID", f32::from(config.system_id)),
            // PX4's geofence defaults: no distances, action hold. GF_ACTION is an
            // INT32, kept bit for bit in the float (byte-wise encoding).
            ("GF_MAX_HOR_DIST", 0.0),
            ("GF_MAX_VER_DIST", 0.0),
            ("GF_ACTION", f32::from_bits(2)),
        ]
    }
}

/// PX4's geofence: `GF_MAX_HOR_DIST` and `GF_MAX_VER_DIST` from home (0: none);
/// `GF_ACTION` 0 none, 1 warns, 2 holds, 3 returns, 4 (terminate) and 5 land.
pub(crate) fn fence(params: &Params) -> Option<FenceRule> {
    let action = params.get("GF_ACTION").map(|a| a.to_bits() as i32)?;
    let action = match action {
        1 => None,
        2 => Some(FlightMode::Hold),
        3 => Some(FlightMode::ReturnToLaunch),
        4 | 5 => Some(FlightMode::Land),
        _ => return None,
    };
    let rule = FenceRule {
        radius_m: crate::fence::limit(params.get("GF_MAX_HOR_DIST")),
        max_altitude_m: crate::fence::limit(params.get("GF_MAX_VER_DIST")),
        action,
        breach_text: "Geofence violation",
    };
    (rule.radius_m.is_some() || rule.max_altitude_m.is_some()).then_some(rule)
}

/// A float command parameter as a small integer, if it is one.
fn to_u8(value: f32) -> Option<u8> {
    (value.is_finite() && (0.0..=255.0).contains(&value) && value.fract() == 0.0)
        .then_some(value as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn custom_modes_match_px4_encoding() {
        assert_eq!(custom_mode(FlightMode::Offboard), 0x0006_0000);
        assert_eq!(custom_mode(FlightMode::Takeoff), 0x0204_0000);
        assert_eq!(custom_mode(FlightMode::Hold), 0x0304_0000);
        assert_eq!(custom_mode(FlightMode::Land), 0x0604_0000);
        assert_eq!(custom_mode(FlightMode::ReturnToLaunch), 0x0504_0000);
    }

    #[test]
    fn mode_requests_round_trip_and_reject() {
        for mode in [
            FlightMode::Hold,
            FlightMode::Takeoff,
            FlightMode::Offboard,
            FlightMode::Land,
            FlightMode::ReturnToLaunch,
            FlightMode::Manual,
        ] {
            let cm = custom_mode(mode);
            let main = ((cm >> 16) & 0xff) as f32;
            let sub = ((cm >> 24) & 0xff) as f32;
            assert_eq!(mode_from_request(main, sub), Ok(mode));
        }
        assert_eq!(
            mode_from_request(1.0, 0.0),
            Err(ModeRequestError::Unsupported)
        );
        assert_eq!(mode_from_request(42.0, 0.0), Err(ModeRequestError::Unknown));
        assert_eq!(
            mode_from_request(f32::NAN, 0.0),
            Err(ModeRequestError::Unknown)
        );
    }
}
