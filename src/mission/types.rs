//! A validated mission: every field checked, coordinates inside the world.

use super::schema::Autopilot;
use crate::world::{Voxel, VoxelGrid};
use serde::{Deserialize, Serialize};

/// A mission that passed validation; the planner may trust every field.
#[derive(Debug, Clone, PartialEq)]
pub struct Mission {
    /// The mission's name, never blank; it labels logs, recordings and plan files.
    pub name: String,
    /// Free text from the file, carried along for people.
    pub description: Option<String>,
    /// The voxel world with its obstacles blocked.
    pub world: VoxelGrid,
    /// Kinematic and safety limits every trajectory keeps.
    pub limits: Limits,
    /// How the vehicles are driven over MAVLink.
    pub link: LinkSettings,
    /// At least one group; every drone has a free, unshared start and can reach a
    /// goal of its group.
    pub groups: Vec<Group>,
}

impl Mission {
    /// All drones, group by group, in file order.
    pub fn drones(&self) -> impl Iterator<Item = (&Group, &Drone)> {
        self.groups
            .iter()
            .flat_map(|g| g.drones.iter().map(move |d| (g, d)))
    }

    /// How many drones fly, over all groups.
    pub fn drone_count(&self) -> usize {
        self.groups.iter().map(|g| g.drones.len()).sum()
    }
}

/// Kinematic and safety limits every trajectory keeps.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Limits {
    /// Top speed of every drone, m/s; positive.
    pub max_speed_mps: f64,
    /// Top acceleration of every drone, m/s²; positive.
    pub max_accel_mps2: f64,
    /// Drones never come closer than this, metres (centre to centre); positive.
    pub safety_distance_m: f64,
}

/// How the vehicles are driven over MAVLink.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinkSettings {
    /// The firmware every vehicle runs; decides offboard (PX4) or guided (ArduPilot).
    pub autopilot: Autopilot,
    /// Setpoints streamed to each vehicle per second, Hz (2.5 to 100): autopilots
    /// leave offboard control when setpoints stop coming.
    pub setpoint_rate_hz: f64,
    /// A vehicle silent for this long counts as lost, seconds; positive.
    pub link_timeout_s: f64,
    /// Where the MAVLink 2 signing key is; `None` flies unsigned.
    pub signing: Option<KeySource>,
}

/// Where a signing key is read from when a flight starts (see `link::signing`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub enum KeySource {
    /// A file with 64 hex digits (a path relative to the mission file once loaded).
    File(std::path::PathBuf),
    /// An environment variable with 64 hex digits.
    Env(String),
}

/// Interchangeable drones sharing one set of goals.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Unique within the mission.
    pub name: String,
    /// At least one drone.
    pub drones: Vec<Drone>,
    /// As many as drones; any drone of the group may take any of them.
    pub goals: Vec<Voxel>,
}

/// One drone of a validated mission.
#[derive(Debug, Clone, PartialEq)]
pub struct Drone {
    /// Unique within the mission; letters, digits, '-', '_' and '.' only, so it can
    /// be written in command-line flags and file names unquoted.
    pub id: String,
    /// A free voxel no other drone starts in; the drone takes off to it.
    pub start: Voxel,
    /// MAVLink address, e.g. `udpout:127.0.0.1:14541`; `None` means the bundled
    /// simulator.
    pub endpoint: Option<String>,
    /// MAVLink system id, 1 to 254 and unique; `None` means the drone's 1-based
    /// position among all the mission's drones.
    pub system_id: Option<u8>,
}
