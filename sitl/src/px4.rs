//! PX4 specifics: custom-mode encoding (`main << 16 | sub << 24`) and the
//! takeoff-altitude rule.

use crate::mode::FlightMode;

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
pub fn custom_mode(mode: FlightMode) -> u32 {
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

/// Why a PX4 mode request cannot be mapped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModeRequestError {
    /// A real PX4 mode the mock does not fly (manual modes need RC, missions are absent).
    Unsupported,
    /// Not a PX4 mode at all.
    Unknown,
}

/// Flight mode requested by MAV_CMD_DO_SET_MODE params 2 (main) and 3 (sub).
pub fn mode_from_request(main: f32, sub: f32) -> Result<FlightMode, ModeRequestError> {
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
