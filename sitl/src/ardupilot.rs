//! ArduPilot Copter specifics: custom-mode numbers.

use crate::mode::FlightMode;

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
pub fn custom_mode(mode: FlightMode) -> u32 {
    match mode {
        FlightMode::Manual => copter_mode::STABILIZE,
        FlightMode::Hold => copter_mode::LOITER,
        FlightMode::Takeoff | FlightMode::Offboard | FlightMode::Guided => copter_mode::GUIDED,
        FlightMode::Land => copter_mode::LAND,
        FlightMode::ReturnToLaunch => copter_mode::RTL,
    }
}

/// Flight mode requested by MAV_CMD_DO_SET_MODE param 2; `None` if the mock does not fly it.
pub fn mode_from_request(custom: f32) -> Option<FlightMode> {
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
pub fn armable(mode: FlightMode) -> bool {
    !matches!(mode, FlightMode::Land | FlightMode::ReturnToLaunch)
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
