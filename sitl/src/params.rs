//! A minimal parameter table: enough for ground stations to read and set the
//! parameters flight code touches (PX4's MIS_TAKEOFF_ALT above all).

use crate::config::VehicleConfig;
use crate::px4;
use mavlink::dialects::common::{MavMessage, MavParamType, PARAM_VALUE_DATA};

/// One named parameter. All are REAL32, so PX4's byte-wise and ArduPilot's
/// C-cast encodings coincide and clients need no special casing.
#[derive(Debug, Clone, PartialEq)]
struct Param {
    name: &'static str,
    value: f32,
}

/// The parameter table of one vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    entries: Vec<Param>,
}

impl Params {
    /// Defaults for the vehicle's flavour and limits.
    pub fn for_vehicle(config: &VehicleConfig) -> Self {
        let table = config.flavour.imitation().params(config);
        let entries = table
            .into_iter()
            .map(|(name, value)| Param { name, value })
            .collect();
        Self { entries }
    }

    /// PX4 takeoff altitude above home (MIS_TAKEOFF_ALT; for ArduPilot PILOT_TKOFF_ALT in cm).
    pub fn takeoff_alt_m(&self) -> f32 {
        if let Some(v) = self.get("MIS_TAKEOFF_ALT") {
            return v;
        }
        self.get("PILOT_TKOFF_ALT")
            .map_or(px4::DEFAULT_TAKEOFF_ALT_M, |cm| cm / 100.0)
    }

    /// Descent speed in LAND and at the end of RTL, m/s: PX4's MPC_LAND_SPEED or
    /// ArduPilot's LAND_SPEED (cm/s).
    /// A value that would not descend (zero or less) falls back to PX4's default.
    pub fn land_speed_mps(&self) -> f32 {
        let set = self
            .get("MPC_LAND_SPEED")
            .or_else(|| self.get("LAND_SPEED").map(|cm| cm / 100.0));
        set.filter(|v| *v > 0.0)
            .unwrap_or(px4::DEFAULT_LAND_SPEED_MPS)
    }

    /// Value of a parameter by name.
    pub fn get(&self, name: &str) -> Option<f32> {
        self.entries
            .iter()
            .find(|p| p.name == name)
            .map(|p| p.value)
    }

    /// Sets a known parameter; returns its PARAM_VALUE echo, or `None` for an
    /// unknown name or a non-finite value (real autopilots stay silent then too).
    pub fn set(&mut self, name: &str, value: f32) -> Option<MavMessage> {
        if !value.is_finite() {
            return None;
        }
        let index = self.entries.iter().position(|p| p.name == name)?;
        self.entries[index].value = value;
        self.value_message(index)
    }

    /// PARAM_VALUE for a name, or for an index when `index >= 0` (MAVLink's PARAM_REQUEST_READ rule).
    pub fn read(&self, name: &str, index: i16) -> Option<MavMessage> {
        let index = if index >= 0 {
            usize::try_from(index).ok()?
        } else {
            self.entries.iter().position(|p| p.name == name)?
        };
        self.value_message(index)
    }

    /// PARAM_VALUE for every parameter (answer to PARAM_REQUEST_LIST).
    pub fn list(&self) -> Vec<MavMessage> {
        (0..self.entries.len())
            .filter_map(|i| self.value_message(i))
            .collect()
    }

    fn value_message(&self, index: usize) -> Option<MavMessage> {
        let p = self.entries.get(index)?;
        Some(MavMessage::PARAM_VALUE(PARAM_VALUE_DATA {
            param_value: p.value,
            param_count: u16::try_from(self.entries.len()).unwrap_or(u16::MAX),
            param_index: u16::try_from(index).unwrap_or(u16::MAX),
            param_id: p.name.into(),
            param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Flavour;

    #[test]
    fn set_echoes_and_changes_takeoff_altitude() {
        let mut params = Params::for_vehicle(&VehicleConfig::new(3, Flavour::Px4));
        assert_eq!(params.takeoff_alt_m(), 2.5);
        let Some(MavMessage::PARAM_VALUE(echo)) = params.set("MIS_TAKEOFF_ALT", 4.0) else {
            panic!("no echo");
        };
        assert_eq!(echo.param_value, 4.0);
        assert_eq!(echo.param_id.to_str(), Ok("MIS_TAKEOFF_ALT"));
        assert_eq!(params.takeoff_alt_m(), 4.0);
        assert!(params.set("NO_SUCH_PARAM", 1.0).is_none());
        assert!(params.set("MIS_TAKEOFF_ALT", f32::NAN).is_none());
        assert!(params.read("", 0).is_some());
        assert!(params.read("", 100).is_none());
        assert_eq!(params.list().len(), 17);
    }
}
