//! A validated mission: every field checked, coordinates inside the world.

use super::schema::Autopilot;
use crate::world::{Voxel, VoxelGrid};
use serde::{Deserialize, Serialize};

/// A mission that passed validation; the planner may trust every field.
#[derive(Debug, Clone, PartialEq)]
pub struct Mission {
    pub name: String,
    pub description: Option<String>,
    pub world: VoxelGrid,
    pub limits: Limits,
    pub link: LinkSettings,
    pub groups: Vec<Group>,
}

impl Mission {
    /// All drones, group by group, in file order.
    pub fn drones(&self) -> impl Iterator<Item = (&Group, &Drone)> {
        self.groups
            .iter()
            .flat_map(|g| g.drones.iter().map(move |d| (g, d)))
    }

    pub fn drone_count(&self) -> usize {
        self.groups.iter().map(|g| g.drones.len()).sum()
    }
}

/// Kinematic and safety limits every trajectory keeps.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Limits {
    pub max_speed_mps: f64,
    pub max_accel_mps2: f64,
    pub safety_distance_m: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinkSettings {
    pub autopilot: Autopilot,
    pub setpoint_rate_hz: f64,
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
    pub name: String,
    pub drones: Vec<Drone>,
    /// As many as drones; any drone of the group may take any of them.
    pub goals: Vec<Voxel>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Drone {
    pub id: String,
    pub start: Voxel,
    pub endpoint: Option<String>,
    pub system_id: Option<u8>,
}
