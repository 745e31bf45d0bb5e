//! What one imitated autopilot does its own way, behind one trait:
//! [`Imitation`], implemented once per firmware in its own file (`px4`,
//! `ardupilot`). The vehicle (`vehicle/`, `commands`, `setpoints`, `telemetry`,
//! `params`) is written against the trait; [`Flavour::imitation`] is the one
//! `match` that lists the firmwares.
//!
//! Adding a firmware to the simulator is one file implementing [`Imitation`] and
//! one variant of [`Flavour`] with its arm in [`Flavour::imitation`].

use crate::config::{Flavour, VehicleConfig};
use crate::fence::FenceRule;
use crate::mode::FlightMode;
use crate::params::Params;
use crate::vehicle::Vehicle;
use mavlink::dialects::common::{MavAutopilot, MavProtocolCapability, MavResult};

/// Why a mode request cannot be flown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModeRequestError {
    /// A real mode of the firmware the mock does not fly (manual modes need RC,
    /// missions are absent): refused with a reason.
    Unsupported,
    /// Not a mode of the firmware at all.
    Unknown,
}

/// One imitated autopilot firmware.
pub(crate) trait Imitation: Sync {
    /// The firmware's own name: `PX4`, `ArduPilot`.
    fn name(&self) -> &'static str;

    /// The lowercase names a command line may call it by.
    fn aliases(&self) -> &'static [&'static str];

    /// The HEARTBEAT `autopilot` field.
    fn heartbeat_autopilot(&self) -> MavAutopilot;

    /// AUTOPILOT_VERSION: the capabilities beyond those every flavour has (how
    /// parameters are encoded), and the firmware version word.
    fn version(&self) -> (MavProtocolCapability, u32);

    /// The mode the vehicle boots in.
    fn boot_mode(&self) -> FlightMode;

    /// HEARTBEAT custom_mode for a flight mode.
    fn custom_mode(&self, mode: FlightMode) -> u32;

    /// MAV_CMD_DO_SET_MODE params 2 and 3 for the deprecated SET_MODE message's
    /// `custom_mode`.
    fn mode_request_of(&self, custom_mode: u32) -> (f32, f32);

    /// The flight mode MAV_CMD_DO_SET_MODE params 2 and 3 ask for.
    fn mode_from_request(&self, param2: f32, param3: f32) -> Result<FlightMode, ModeRequestError>;

    /// Whether the firmware allows arming in `mode`.
    fn armable(&self, mode: FlightMode) -> bool;

    /// STATUSTEXT for a failing pre-arm check, in the firmware's words.
    fn prearm_failure_text(&self) -> &'static str;

    /// STATUSTEXT when the battery turns low.
    fn low_battery_text(&self) -> &'static str;

    /// What the firmware says and does when the battery turns critical in the air.
    fn critical_battery_failsafe(&self) -> (&'static str, FlightMode);

    /// Whether the vehicle takes a position target now (PX4 records every one,
    /// the stream gates OFFBOARD; Copter only in GUIDED while flying).
    fn takes_setpoint(&self, vehicle: &Vehicle) -> bool;

    /// MAV_CMD_NAV_TAKEOFF with its param7, as the firmware answers it.
    fn takeoff(&self, vehicle: &mut Vehicle, param7: f32) -> MavResult;

    /// The firmware's parameter table for a vehicle (names and defaults).
    fn params(&self, config: &VehicleConfig) -> Vec<(&'static str, f32)>;

    /// The geofence its parameters set, if it is on.
    fn fence(&self, params: &Params) -> Option<FenceRule>;
}

impl Flavour {
    /// The imitation of this firmware: the one place that lists them.
    pub(crate) fn imitation(self) -> &'static dyn Imitation {
        match self {
            Flavour::Px4 => &crate::px4::Px4,
            Flavour::ArduPilot => &crate::ardupilot::ArduPilot,
        }
    }

    /// Every firmware the simulator imitates.
    pub const ALL: [Flavour; 2] = [Flavour::Px4, Flavour::ArduPilot];
}
