//! One drone's path as the TPG sees it: its maximal stays in one voxel (visits)
//! and its events — `Start`, then the `Enter` and `Leave` markers and the `Arrive`
//! of every move, with where it comes to rest.

use super::{Event, EventKind};
use crate::schedule::ScheduleError;
use crate::world::{Voxel, VoxelGrid};

/// One maximal stay of a drone in one voxel.
pub(super) struct Visit {
    pub(super) voxel: Voxel,
    pub(super) first_step: u32,
    pub(super) last_step: u32,
    /// The `Enter` marker of the move into this visit (none for the start visit).
    pub(super) enter: u32,
    /// The `Leave` marker of the move out of this visit (none for the final visit).
    pub(super) leave: Option<u32>,
}

/// A malformed plan, for `drone`.
pub(super) fn invalid(drone: &str, reason: String) -> ScheduleError {
    ScheduleError::InvalidPlan {
        drone: drone.to_string(),
        reason,
    }
}

/// Events and visits of one drone: `Start`, then `Enter`, `Leave`, `Arrive` per move.
pub(super) fn drone_events(
    world: &VoxelGrid,
    makespan_steps: u32,
    drone: &crate::plan::DronePlan,
    marker_m: &dyn Fn(f64, bool) -> f64,
) -> Result<(Vec<Event>, Vec<Visit>), ScheduleError> {
    let path = &drone.path;
    if path.len() != makespan_steps as usize + 1 {
        return Err(invalid(
            &drone.id,
            format!(
                "path has {} entries, expected makespan_steps + 1 = {}",
                path.len(),
                u64::from(makespan_steps) + 1
            ),
        ));
    }
    let mut visits: Vec<Visit> = Vec::new();
    for (step, &voxel) in path.iter().enumerate() {
        let step = step as u32;
        if !world.is_free(voxel) {
            return Err(invalid(
                &drone.id,
                format!("voxel {voxel} at step {step} is outside the world or blocked"),
            ));
        }
        match visits.last_mut() {
            Some(last) if last.voxel == voxel => last.last_step = step,
            Some(last) if last.voxel.manhattan(voxel) != 1 => {
                return Err(invalid(
                    &drone.id,
                    format!("jumps from {} to {voxel} at step {step}", last.voxel),
                ));
            }
            _ => visits.push(Visit {
                voxel,
                first_step: step,
                last_step: step,
                enter: 0,
                leave: None,
            }),
        }
    }
    let mut events = Vec::with_capacity(3 * visits.len().saturating_sub(1) + 1);
    let start = world.center_m(visits[0].voxel);
    events.push(Event {
        kind: EventKind::Start,
        voxel: visits[0].voxel,
        step: 0,
        position_m: start.into(),
        distance_m: 0.0,
        rest: true,
    });
    let mut distance_m = 0.0;
    for k in 1..visits.len() {
        let (from, to) = (visits[k - 1].voxel, visits[k].voxel);
        let (a, b) = (world.center_m(from), world.center_m(to));
        let s = (b - a).norm();
        let delta = marker_m(s, from.z != to.z);
        let dir = (b - a) / s;
        let step = visits[k].first_step;
        let at = |offset_m: f64| -> [f64; 3] { (a + dir * offset_m).into() };
        let base = events.len() as u32;
        visits[k].enter = base;
        visits[k - 1].leave = Some(base + 1);
        events.push(Event {
            kind: EventKind::Enter,
            voxel: to,
            step,
            position_m: at(delta),
            distance_m: distance_m + delta,
            rest: false,
        });
        events.push(Event {
            kind: EventKind::Leave,
            voxel: from,
            step,
            position_m: at(s - delta),
            distance_m: distance_m + s - delta,
            rest: false,
        });
        distance_m += s;
        // At rest on arrival at the goal, before a turn, and where the plan waits.
        let turns = visits
            .get(k + 1)
            .is_none_or(|next| direction(to, next.voxel) != direction(from, to));
        let waits = visits[k].last_step > visits[k].first_step;
        events.push(Event {
            kind: EventKind::Arrive,
            voxel: to,
            step,
            position_m: b.into(),
            distance_m,
            rest: turns || waits,
        });
    }
    Ok((events, visits))
}

fn direction(from: Voxel, to: Voxel) -> [i64; 3] {
    [
        i64::from(to.x) - i64::from(from.x),
        i64::from(to.y) - i64::from(from.y),
        i64::from(to.z) - i64::from(from.z),
    ]
}
