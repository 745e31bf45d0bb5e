//! The mission file as written by users (YAML), before validation.
//!
//! Every struct denies unknown fields so a typo (`strat:` for `start:`) is an error,
//! never a silently ignored setting. Coordinates are signed here so that a negative
//! coordinate is reported as "outside the world" rather than as a type error.

use serde::{Deserialize, Serialize};

/// A voxel coordinate as written in a file, `[x, y, z]`.
pub type RawVoxel = [i64; 3];

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionFile {
    pub name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    pub world: WorldSpec,
    pub limits: LimitsSpec,
    #[serde(default)]
    pub link: LinkSpec,
    pub groups: Vec<GroupSpec>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSpec {
    /// Voxels along x (east), y (north), z (up).
    pub dimensions: [i64; 3],
    pub voxel_size_m: f64,
    /// ENU position of the centre of voxel [0, 0, 0].
    #[serde(default)]
    pub origin_m: [f64; 3],
    #[serde(default)]
    pub obstacles: Vec<ObstacleSpec>,
}

/// One blocked voxel, or an inclusive box of them.
///
/// Deserialised by hand rather than `#[serde(untagged)]`, which would hide the index
/// of the bad entry and the reason it was rejected.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum ObstacleSpec {
    Cell(RawVoxel),
    Box(BoxSpec),
}

impl<'de> Deserialize<'de> for ObstacleSpec {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ObstacleVisitor;
        impl<'de> serde::de::Visitor<'de> for ObstacleVisitor {
            type Value = ObstacleSpec;

            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a voxel [x, y, z] or a box { min: [x, y, z], max: [x, y, z] }")
            }

            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> Result<Self::Value, A::Error> {
                RawVoxel::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))
                    .map(ObstacleSpec::Cell)
            }

            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<Self::Value, A::Error> {
                BoxSpec::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(ObstacleSpec::Box)
            }
        }
        deserializer.deserialize_any(ObstacleVisitor)
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    pub min: RawVoxel,
    pub max: RawVoxel,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitsSpec {
    pub max_speed_mps: f64,
    pub max_accel_mps2: f64,
    pub safety_distance_m: f64,
}

/// Which autopilot firmware the vehicles run; decides offboard (PX4) or guided (ArduPilot).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Autopilot {
    #[default]
    Px4,
    Ardupilot,
}

impl std::fmt::Display for Autopilot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Autopilot::Px4 => "px4",
            Autopilot::Ardupilot => "ardupilot",
        })
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinkSpec {
    #[serde(default)]
    pub autopilot: Autopilot,
    #[serde(default = "default_setpoint_rate_hz")]
    pub setpoint_rate_hz: f64,
    /// A vehicle silent for this long counts as lost.
    #[serde(default = "default_link_timeout_s")]
    pub link_timeout_s: f64,
    /// MAVLink 2 signing: where the swarm's secret key is kept (never the key).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub signing: Option<SigningSpec>,
}

/// Where a mission's MAVLink 2 signing key comes from: exactly one of the two.
/// The key itself never appears in a mission file, a log or a message.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SigningSpec {
    /// A file holding the 32-byte key as 64 hex digits; relative paths are
    /// relative to the mission file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub key_file: Option<std::path::PathBuf>,
    /// An environment variable holding the key as 64 hex digits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub key_env: Option<String>,
}

impl Default for LinkSpec {
    fn default() -> Self {
        Self {
            autopilot: Autopilot::default(),
            setpoint_rate_hz: default_setpoint_rate_hz(),
            link_timeout_s: default_link_timeout_s(),
            signing: None,
        }
    }
}

fn default_setpoint_rate_hz() -> f64 {
    20.0
}

fn default_link_timeout_s() -> f64 {
    3.0
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupSpec {
    pub name: String,
    pub drones: Vec<DroneSpec>,
    pub goals: Vec<RawVoxel>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DroneSpec {
    pub id: String,
    pub start: RawVoxel,
    /// MAVLink address, e.g. `udpout:127.0.0.1:14541`; none means the bundled simulator.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub endpoint: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub system_id: Option<i64>,
}
