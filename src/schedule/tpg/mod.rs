//! The Temporal Plan Graph: events along each drone's path, their order, and the
//! cross-drone precedences with safety markers (see the module docs of
//! [`schedule`](super) for the safety argument).
//!
//! This file holds the graph itself. Building it is split by concept: `build`
//! checks the limits, places the markers and assembles the graph; `events` turns
//! one drone's path into its visits and events; `handover` orders the visits of
//! each voxel (and, under an ellipsoid, of cells within vertical reach) with
//! type-2 edges; `holds` adds the edges that make a stage's hold.

mod build;
mod events;
mod handover;
mod holds;

pub use build::{build, build_with};

use crate::world::Voxel;
use serde::{Deserialize, Serialize};

/// What happens at an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    /// The drone is at its start voxel centre, at rest, at time zero or later.
    Start,
    /// Safety marker δ after leaving the previous centre: from here on the drone
    /// *holds* the voxel it is moving into (it is within `hold_radius_m` of its centre).
    Enter,
    /// Safety marker δ before the next centre: from here on the drone no longer holds
    /// the voxel it came from.
    Leave,
    /// The drone is at the centre of the voxel it moved into.
    Arrive,
}

/// One event of one drone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Event {
    /// Start, marker or arrival.
    pub kind: EventKind,
    /// The voxel the event is about: entered (`Enter`, `Arrive`), released (`Leave`),
    /// or the start voxel (`Start`).
    pub voxel: Voxel,
    /// The discrete step at which the move containing this event ends (0 for `Start`).
    pub step: u32,
    /// Where the event happens, ENU metres.
    pub position_m: [f64; 3],
    /// Path length from the start voxel centre to this event, metres.
    pub distance_m: f64,
    /// The drone is at rest here: start, goal, a turn, or a wait in the discrete plan.
    pub rest: bool,
}

/// Names one event: the drone's index in the plan and the event's index in its list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct EventId {
    /// The drone's index in the plan (and in the TPG's `drones`).
    pub drone: u32,
    /// The event's index in that drone's event list.
    pub index: u32,
}

/// A cross-drone precedence: the drone of `to` may move past `to` only `delay_s`
/// after the drone of `from` has reached `from`.
///
/// Type-2 edges hand a voxel over: `from` is the previous holder's `Leave` marker,
/// `to` the next holder's `Enter` marker, `delay_s` zero. Hold edges make a stage's
/// hold: `from` is where a drone comes to rest in the formation, `to` where another
/// (or the same) drone rests in it, `delay_s` the stage's hold.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CrossEdge {
    /// The earlier event.
    pub from: EventId,
    /// The event that waits for it.
    pub to: EventId,
    /// The voxel handed over (type-2), or where `to`'s drone holds the formation.
    pub voxel: Voxel,
    /// Seconds that must pass after `from` before `to` is passed (0 for type-2 edges).
    #[serde(default)]
    pub delay_s: f64,
}

/// One drone's events in path order (type-1 edges join consecutive events).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TpgDrone {
    /// The drone's id in the mission.
    pub id: String,
    /// Its events, starting with `Start`.
    pub events: Vec<Event>,
}

/// The Temporal Plan Graph with safety markers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Tpg {
    /// The mission's voxel edge length, metres.
    pub voxel_size_m: f64,
    /// The separation the markers keep between setpoints, metres: the mission's
    /// safety distance plus twice its tracking error (see
    /// [`Limits::setpoint_separation_m`](crate::mission::Limits::setpoint_separation_m));
    /// at most `voxel_size_m`.
    pub separation_m: f64,
    /// The mission's safety distance, metres: what real drones keep while each
    /// stays within the tracking error of its setpoint.
    pub safety_distance_m: f64,
    /// δ = (voxel size − separation) / 2: where markers sit, from each end of a move.
    pub marker_offset_m: f64,
    /// (voxel size + separation) / 2: a drone holds a voxel while its path distance
    /// to that visit of the voxel's centre is below this.
    pub hold_radius_m: f64,
    /// Under an ellipsoid: where the markers sit on vertical moves, from each end
    /// (see [`VerticalReach`](crate::world::VerticalReach)); horizontal moves keep
    /// `marker_offset_m`. `None` for a sphere, whose markers sit
    /// `(length − separation) / 2` from each end of every move.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical_marker_m: Option<f64>,
    /// Speed limit the schedule's runs obey, m/s.
    pub max_speed_mps: f64,
    /// Acceleration limit the schedule's runs obey, m/s².
    pub max_accel_mps2: f64,
    /// Jerk limit the schedule's runs obey, m/s³.
    pub max_jerk_mps3: f64,
    /// Every drone's events, in plan order.
    pub drones: Vec<TpgDrone>,
    /// Type-2 edges, sorted by target event.
    pub cross_edges: Vec<CrossEdge>,
    /// The period setpoints are streamed at, seconds: how far ahead of a gate a
    /// flight decides on it (see `decision_lead`); 0 budgets no decision.
    #[serde(default)]
    pub setpoint_period_s: f64,
}

impl Tpg {
    /// The speed, acceleration and jerk limits of the schedule's runs.
    pub fn kinematics(&self) -> crate::profile::Kinematics {
        crate::profile::Kinematics {
            max_speed_mps: self.max_speed_mps,
            max_accel_mps2: self.max_accel_mps2,
            max_jerk_mps3: self.max_jerk_mps3,
        }
    }

    /// Number of events over all drones.
    pub fn event_count(&self) -> usize {
        self.drones.iter().map(|d| d.events.len()).sum()
    }
}
