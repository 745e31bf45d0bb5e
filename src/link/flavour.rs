//! PX4 and ArduPilot speak the same messages but name their modes differently.
//! Everything flavour-specific about commanding a vehicle lives here.

use mavlink::dialects::common::MavAutopilot;
use serde::{Deserialize, Serialize};

/// The autopilot family a vehicle announced in its HEARTBEAT.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Flavour {
    /// PX4: takes off and flies on our setpoints in OFFBOARD.
    Px4,
    /// ArduPilot Copter: takes off by command in GUIDED, then follows our setpoints.
    Ardupilot,
}

/// A mode request as MAV_CMD_DO_SET_MODE parameters 2 and 3.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeRequest {
    /// DO_SET_MODE param2: PX4's main mode, or ArduPilot's mode number.
    pub param2: f32,
    /// DO_SET_MODE param3: PX4's sub mode (0 for ArduPilot).
    pub param3: f32,
    /// The HEARTBEAT custom_mode that confirms the vehicle is in this mode.
    pub custom_mode: u32,
}

/// PX4 encodes modes as `main << 16 | sub << 24`.
const fn px4(main: u8, sub: u8) -> ModeRequest {
    ModeRequest {
        param2: main as f32,
        param3: sub as f32,
        custom_mode: (main as u32) << 16 | (sub as u32) << 24,
    }
}

/// ArduPilot Copter modes are plain numbers.
const fn copter(mode: u8) -> ModeRequest {
    ModeRequest {
        param2: mode as f32,
        param3: 0.0,
        custom_mode: mode as u32,
    }
}

impl Flavour {
    /// Detects the family from a HEARTBEAT's autopilot field; `None` for anything else
    /// (a GCS, a companion computer, or an autopilot we do not know how to fly).
    pub fn from_autopilot(autopilot: MavAutopilot) -> Option<Self> {
        match autopilot {
            MavAutopilot::MAV_AUTOPILOT_PX4 => Some(Flavour::Px4),
            MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA => Some(Flavour::Ardupilot),
            _ => None,
        }
    }

    /// The mode in which the vehicle follows our SET_POSITION_TARGET stream.
    pub fn external_control_mode(self) -> ModeRequest {
        match self {
            Flavour::Px4 => px4(6, 0),       // OFFBOARD
            Flavour::Ardupilot => copter(4), // GUIDED
        }
    }

    /// A mode that holds position without our stream.
    pub fn hold_mode(self) -> ModeRequest {
        match self {
            Flavour::Px4 => px4(4, 3),        // AUTO.LOITER
            Flavour::Ardupilot => copter(17), // BRAKE
        }
    }

    /// The mode that lands where the vehicle is.
    pub fn land_mode(self) -> ModeRequest {
        match self {
            Flavour::Px4 => px4(4, 6),       // AUTO.LAND
            Flavour::Ardupilot => copter(9), // LAND
        }
    }

    /// Whether `custom_mode` is one the autopilot enters by itself to bring a
    /// vehicle home or down (land, return): a failsafe we never fight.
    pub fn is_failsafe_mode(self, custom_mode: u32) -> bool {
        let rtl = match self {
            Flavour::Px4 => px4(4, 5),       // AUTO.RTL
            Flavour::Ardupilot => copter(6), // RTL
        };
        custom_mode == self.land_mode().custom_mode || custom_mode == rtl.custom_mode
    }

    /// ArduPilot must take off with MAV_CMD_NAV_TAKEOFF in GUIDED and only accepts
    /// position targets once flying; PX4 in OFFBOARD climbs on our setpoints.
    pub fn takes_off_by_command(self) -> bool {
        matches!(self, Flavour::Ardupilot)
    }
}

impl std::fmt::Display for Flavour {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Flavour::Px4 => "px4",
            Flavour::Ardupilot => "ardupilot",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn px4_custom_modes_match_the_heartbeat_encoding() {
        assert_eq!(
            Flavour::Px4.external_control_mode().custom_mode,
            0x0006_0000
        );
        assert_eq!(Flavour::Px4.hold_mode().custom_mode, 0x0304_0000);
        assert_eq!(Flavour::Px4.land_mode().custom_mode, 0x0604_0000);
    }

    #[test]
    fn ardupilot_modes_are_copter_numbers() {
        assert_eq!(Flavour::Ardupilot.external_control_mode().custom_mode, 4);
        assert_eq!(Flavour::Ardupilot.land_mode().custom_mode, 9);
    }

    #[test]
    fn failsafe_modes_are_land_and_return() {
        assert!(Flavour::Px4.is_failsafe_mode(0x0504_0000));
        assert!(Flavour::Px4.is_failsafe_mode(0x0604_0000));
        assert!(!Flavour::Px4.is_failsafe_mode(0x0006_0000));
        assert!(Flavour::Ardupilot.is_failsafe_mode(6));
        assert!(Flavour::Ardupilot.is_failsafe_mode(9));
        assert!(!Flavour::Ardupilot.is_failsafe_mode(4));
    }
}
