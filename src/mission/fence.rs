//! The mission file's `fence` section: the geofence every autopilot is given at
//! pre-flight, as written (what it becomes on each vehicle is `fly::fence`).

use serde::{Deserialize, Serialize};

/// The autopilots' own geofence: every vehicle is given, at pre-flight, a fence
/// around the mission's airspace that its autopilot enforces by itself, so that a
/// vehicle flies into no one else's airspace even when the ground station, the
/// link or the plan fails. See `fly::fence`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FenceSpec {
    /// Whether the fence is set (default true). Off: each vehicle keeps whatever
    /// fence its autopilot already has, and pre-flight says so.
    #[serde(default = "default_true")]
    pub enabled: bool,
    /// How far beyond the airspace the fence stands, metres (default 2; 0.5 to
    /// 100): room for the autopilot's tracking error and GPS drift, so that a
    /// vehicle flying its plan never touches it.
    #[serde(default = "default_fence_margin_m")]
    pub margin_m: f64,
    /// What the autopilot does when a vehicle crosses it (default `land`).
    #[serde(default)]
    pub action: FenceAction,
}

impl Default for FenceSpec {
    fn default() -> Self {
        Self {
            enabled: true,
            margin_m: default_fence_margin_m(),
            action: FenceAction::default(),
        }
    }
}

impl FenceSpec {
    /// Whether nothing was written (used to keep written missions short).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

fn default_true() -> bool {
    true
}

fn default_fence_margin_m() -> f64 {
    2.0
}

/// What an autopilot does with a vehicle that crosses its fence.
///
/// There is no "brake" choice: a braked vehicle hovers outside the airspace with
/// no plan, and PX4's hold cannot be told from its offboard-loss hold, after which
/// swarmctl asks for offboard control again; landing is the one action the
/// flight already treats as the autopilot's (`fly::contingency`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FenceAction {
    /// Land where it is, then disarm (ArduPilot `FENCE_ACTION` 2, PX4 `GF_ACTION`
    /// 5); swarmctl takes the drone out of the plan while it comes down.
    #[default]
    Land,
    /// Only warn (ArduPilot `FENCE_ACTION` 0, PX4 `GF_ACTION` 1): for a first
    /// flight in a new field, where a false breach must not bring a drone down.
    Report,
}

impl std::fmt::Display for FenceAction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FenceAction::Land => "land",
            FenceAction::Report => "report",
        })
    }
}
