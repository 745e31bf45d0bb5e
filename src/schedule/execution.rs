//! What the flight executor needs to gate each drone on the others: per drone, its
//! events with positions and scheduled times, the cross-drone events each waits for,
//! and the slack each can absorb.

use super::solve::Schedule;
use super::tpg::{EventId, EventKind, Tpg};
use crate::world::Voxel;
use serde::{Deserialize, Serialize};

/// One event as the executor sees it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExecutionEvent {
    /// Start, marker or arrival (see [`EventKind`]).
    pub kind: EventKind,
    /// The voxel the event is about (as in the TPG's [`Event`](super::Event)).
    pub voxel: Voxel,
    /// The discrete step at which the move containing the event ends (0 for `Start`).
    #[serde(default)]
    pub step: u32,
    /// Where the event happens, ENU metres: what the executor compares telemetry with.
    pub position_m: [f64; 3],
    /// Scheduled time at which the drone reaches the event's position.
    pub reach_s: f64,
    /// Scheduled time at which it moves on past it.
    pub leave_s: f64,
    /// Delay of the departure that does not move the makespan.
    pub slack_s: f64,
    /// Events of other drones that must have been *reached* before this drone may move
    /// past this event's position.
    pub after: Vec<EventId>,
    /// Seconds that must pass after the last of `after` was reached before this drone
    /// moves past: a stage's hold (0 elsewhere).
    #[serde(default)]
    pub hold_s: f64,
}

/// One drone's gated event list.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExecutionDrone {
    /// The drone's id in the mission.
    pub id: String,
    /// Its events in path order.
    pub events: Vec<ExecutionEvent>,
}

/// The TPG and schedule in the form the flight executor consumes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExecutionPlan {
    /// When the last drone comes to rest at its goal if nobody is delayed, seconds.
    pub makespan_s: f64,
    /// Every drone, in plan order (an [`EventId`]'s `drone` indexes this list).
    pub drones: Vec<ExecutionDrone>,
}

/// Joins a TPG and its schedule into per-drone gated event lists.
pub fn execution_plan(tpg: &Tpg, schedule: &Schedule) -> ExecutionPlan {
    let mut drones: Vec<ExecutionDrone> = tpg
        .drones
        .iter()
        .zip(&schedule.drones)
        .map(|(d, s)| ExecutionDrone {
            id: d.id.clone(),
            events: d
                .events
                .iter()
                .zip(&s.events)
                .map(|(e, t)| ExecutionEvent {
                    kind: e.kind,
                    voxel: e.voxel,
                    step: e.step,
                    position_m: e.position_m,
                    reach_s: t.reach_s,
                    leave_s: t.leave_s,
                    slack_s: t.slack_s,
                    after: Vec::new(),
                    hold_s: 0.0,
                })
                .collect(),
        })
        .collect();
    for edge in &tpg.cross_edges {
        let to = &mut drones[edge.to.drone as usize].events[edge.to.index as usize];
        to.after.push(edge.from);
        to.hold_s = to.hold_s.max(edge.delay_s);
    }
    ExecutionPlan {
        makespan_s: schedule.makespan_s,
        drones,
    }
}
