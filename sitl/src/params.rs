//! A minimal parameter table: enough for ground stations to read and set the
//! parameters flight code touches (PX4's MIS_TAKEOFF_ALT above all).

use crate::config::{Flavour, VehicleConfig};
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
        let entries = match config.flavour {
            Flavour::Px4 => vec![
                Param {
                    name: "MIS_TAKEOFF_ALT",
                    value: px4::DEFAULT_TAKEOFF_ALT_M,
                },
                Param {
                    name: "COM_OF_LOSS_T",
                    value: 1.0,
                },
                Param {
                    name: "COM_DISARM_LAND",
                    value: 2.0,
                },
                Param {
                    name: "MPC_XY_VEL_MAX",
                    value: config.max_speed_mps,
                },
                Param {
                    name: "MPC_ACC_HOR_MAX",
                    value: config.max_accel_mps2,
                },
                Param {
                    name: "MPC_LAND_SPEED",
                    value: 0.7,
                },
                Param {
                    name: "MAV_SYS_ID",
                    value: f32::from(config.system_id),
                },
            ],
            Flavour::ArduPilot => vec![
                Param {
                    name: "PILOT_TKOFF_ALT",
                    value: 250.0,
                },
                Param {
                    name: "WPNAV_SPEED",
                    value: config.max_speed_mps * 100.0,
                },
                Param {
                    name: "WPNAV_ACCEL",
                    value: config.max_accel_mps2 * 100.0,
                },
                // The position controller's jerk limits, m/s³ (ArduCopter's defaults;
                // flight code sets them, the mock's dynamics do not read them).
                Param {
                    name: "PSC_JERK_XY",
                    value: 5.0,
                },
                Param {
                    name: "PSC_JERK_Z",
                    value: 5.0,
                },
                // The mock has no attitude to tilt: acceleration feed-forward acts at
                // once, so its attitude input time constant is zero.
                Param {
                    name: "ATC_INPUT_TC",
                    value: 0.0,
                },
                Param {
                    name: "WPNAV_ACCEL_Z",
                    value: 100.0,
                },
                Param {
                    name: "WPNAV_SPEED_UP",
                    value: 250.0,
                },
                Param {
                    name: "WPNAV_SPEED_DN",
                    value: 150.0,
                },
                Param {
                    name: "LAND_SPEED",
                    value: 70.0,
                },
                Param {
                    name: "FS_GCS_ENABLE",
                    value: 0.0,
                },
                Param {
                    name: "SYSID_THISMAV",
                    value: f32::from(config.system_id),
                },
            ],
        };
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
        assert_eq!(params.list().len(), 7);
    }
}
