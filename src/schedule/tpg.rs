//! The Temporal Plan Graph: events along each drone's path, their order, and the
//! cross-drone precedences with safety markers (see the module docs of
//! [`schedule`](super) for the safety argument).

use super::ScheduleError;
use crate::mission::{Limits, Mission};
use crate::plan::DiscretePlan;
use crate::world::{VerticalReach, Voxel, VoxelGrid};
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
    /// [`Limits::setpoint_separation_m`]); at most `voxel_size_m`.
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
    /// (see [`VerticalReach`]); horizontal moves keep `marker_offset_m`. `None` for
    /// a sphere, whose markers sit `(length − separation) / 2` from each end of
    /// every move.
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

/// One maximal stay of a drone in one voxel.
struct Visit {
    voxel: Voxel,
    first_step: u32,
    last_step: u32,
    /// The `Enter` marker of the move into this visit (none for the start visit).
    enter: u32,
    /// The `Leave` marker of the move out of this visit (none for the final visit).
    leave: Option<u32>,
}

/// Builds the TPG of `plan` for `mission`: events, markers and minimal type-2 edges.
///
/// Fails with a clear error if the safety distance exceeds the voxel size, if a path is
/// malformed, or if two drones meet in a voxel or swap along an edge.
pub fn build(mission: &Mission, plan: &DiscretePlan) -> Result<Tpg, ScheduleError> {
    build_with(&mission.airspace, &mission.commanded_limits(), plan)
}

/// [`build`] from a world and limits rather than a whole mission.
pub fn build_with(
    world: &VoxelGrid,
    limits: &Limits,
    plan: &DiscretePlan,
) -> Result<Tpg, ScheduleError> {
    let s = world.voxel_size_m();
    // Setpoints are kept apart by the safety distance plus both drones' tracking
    // error; everything below argues about setpoints with this `d`.
    let d = limits.setpoint_separation_m();
    if !(limits.tracking_error_m.is_finite() && limits.tracking_error_m >= 0.0) {
        return Err(ScheduleError::BadLimit {
            name: "limits.tracking_error_m",
            value: limits.tracking_error_m,
        });
    }
    for (name, value) in [
        ("world.voxel_size_m", s),
        ("limits.safety_distance_m", limits.safety_distance_m),
        ("limits.max_speed_mps", limits.max_speed_mps),
        ("limits.max_accel_mps2", limits.max_accel_mps2),
        ("limits.max_jerk_mps3", limits.max_jerk_mps3),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(ScheduleError::BadLimit { name, value });
        }
    }
    if d > s {
        return Err(ScheduleError::SafetyDistanceTooLarge {
            safety_distance_m: d,
            voxel_size_m: s,
        });
    }
    // Under an ellipsoid vertical spacing is kept by the vertical reach instead.
    let reach = limits.vertical_reach(world);
    if let Some(pad_z_m) = world.pad_layer_z_m().filter(|_| !limits.is_ellipsoid()) {
        let gap_m = world.center_m(Voxel::new(0, 0, 0)).z - pad_z_m;
        if gap_m < d {
            return Err(ScheduleError::SafetyDistanceTooLarge {
                safety_distance_m: d,
                voxel_size_m: gap_m,
            });
        }
    }
    let delta = 0.5 * (s - d);
    let vertical_marker_m = limits.is_ellipsoid().then_some(reach.vertical_marker_m);
    // Markers sit (length − d) / 2 from each end of a move (moves into and out of
    // the pad layer may be shorter or longer than a voxel), except on an
    // ellipsoid's vertical moves.
    let marker_m = |length_m: f64, vertical: bool| match vertical_marker_m {
        Some(sigma_m) if vertical => sigma_m,
        _ => 0.5 * (length_m - d).max(0.0),
    };
    let mut drones = Vec::with_capacity(plan.drones.len());
    let mut visits = Vec::with_capacity(plan.drones.len());
    for drone in &plan.drones {
        let (events, drone_visits) = drone_events(world, plan.makespan_steps, drone, &marker_m)?;
        drones.push(TpgDrone {
            id: drone.id.clone(),
            events,
        });
        visits.push(drone_visits);
    }
    let candidates = cross_candidates(world, plan, &visits, reach)?;
    let mut cross_edges = minimal_edges(candidates);
    cross_edges.extend(hold_edges(plan, &visits, &mut drones));
    cross_edges.sort_unstable_by_key(|e| (e.to, e.from));
    Ok(Tpg {
        voxel_size_m: s,
        separation_m: d,
        safety_distance_m: limits.safety_distance_m,
        marker_offset_m: delta,
        hold_radius_m: 0.5 * (s + d),
        vertical_marker_m,
        max_speed_mps: limits.max_speed_mps,
        max_accel_mps2: limits.max_accel_mps2,
        max_jerk_mps3: limits.max_jerk_mps3,
        drones,
        cross_edges,
    })
}

fn invalid(drone: &str, reason: String) -> ScheduleError {
    ScheduleError::InvalidPlan {
        drone: drone.to_string(),
        reason,
    }
}

/// Events and visits of one drone: `Start`, then `Enter`, `Leave`, `Arrive` per move.
fn drone_events(
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

/// Hold edges for every leg with a hold: each drone's rest event in the formation
/// (forced to be a rest) waits `hold_s` after every drone's, its own included, so
/// nobody leaves before the whole swarm has held the formation that long.
///
/// A drone whose formation cell is its last (a spare holding above a pad it lands
/// on, a drone that never moves) never leaves it: nothing of it waits, though
/// the others still wait for it to arrive. An edge into its last event would
/// ask its arrival to follow its own arrival by the hold, a cycle.
fn hold_edges(
    plan: &DiscretePlan,
    visits: &[Vec<Visit>],
    drones: &mut [TpgDrone],
) -> Vec<CrossEdge> {
    let mut edges = Vec::new();
    for leg in plan.legs.iter().filter(|l| l.hold_s > 0.0) {
        // Per drone: its rest event in the formation, the voxel, and whether it
        // ever leaves that voxel.
        let at: Vec<(u32, Voxel, bool)> = visits
            .iter()
            .map(|dv| {
                let k = dv
                    .iter()
                    .position(|v| v.first_step <= leg.end_step && leg.end_step <= v.last_step)
                    .unwrap_or(dv.len().saturating_sub(1));
                let index = if k == 0 { 0 } else { dv[k].enter + 2 };
                let voxel = dv.get(k).map_or(Voxel::new(0, 0, 0), |v| v.voxel);
                (index, voxel, k + 1 < dv.len())
            })
            .collect();
        for (i, &(index, voxel, leaves)) in at.iter().enumerate() {
            if let Some(e) = drones[i].events.get_mut(index as usize) {
                e.rest = true;
            }
            if !leaves {
                continue;
            }
            for (j, &(from, _, _)) in at.iter().enumerate() {
                edges.push(CrossEdge {
                    from: EventId {
                        drone: j as u32,
                        index: from,
                    },
                    to: EventId {
                        drone: i as u32,
                        index,
                    },
                    voxel,
                    delay_s: leg.hold_s,
                });
            }
        }
    }
    edges
}

fn direction(from: Voxel, to: Voxel) -> [i64; 3] {
    [
        i64::from(to.x) - i64::from(from.x),
        i64::from(to.y) - i64::from(from.y),
        i64::from(to.z) - i64::from(from.z),
    ]
}

/// Type-2 candidates: for every visit of a voxel, an edge from the previous visitor's
/// `Leave` marker to this visitor's `Enter` marker. Consecutive visits suffice: earlier
/// visitors are ordered before the previous one already.
///
/// Under an ellipsoid a visit also waits for the latest earlier visitor of every
/// cell stacked with it (within the vertical reach): those are held like the cell
/// itself.
fn cross_candidates(
    world: &VoxelGrid,
    plan: &DiscretePlan,
    visits: &[Vec<Visit>],
    reach: VerticalReach,
) -> Result<Vec<CrossEdge>, ScheduleError> {
    let id = |i: u32| plan.drones[i as usize].id.clone();
    // Entering visits bucketed by the step they begin, so voxels are claimed in time order.
    let mut by_step: Vec<Vec<(u32, u32)>> = vec![Vec::new(); plan.makespan_steps as usize + 1];
    for (i, dv) in visits.iter().enumerate() {
        for (k, v) in dv.iter().enumerate() {
            by_step[v.first_step as usize].push((i as u32, k as u32));
        }
    }
    let mut last: Vec<Option<(u32, u32)>> = vec![None; world.len()];
    let mut edges = Vec::new();
    for (step, entering) in by_step.iter().enumerate() {
        let step = step as u32;
        for &(j, m) in entering {
            let visit = &visits[j as usize][m as usize];
            let cell = world.cell(visit.voxel).ok_or_else(|| {
                invalid(
                    &id(j),
                    format!("voxel {} is outside the world", visit.voxel),
                )
            })?;
            if let Some((i, k)) = last[cell] {
                let prev = &visits[i as usize][k as usize];
                if prev.last_step >= step {
                    return Err(ScheduleError::VertexConflict {
                        voxel: visit.voxel,
                        step,
                        first: id(i),
                        second: id(j),
                    });
                }
                if i != j {
                    let from_voxel = visits[j as usize][m as usize - 1].voxel;
                    let prev_next = &visits[i as usize][k as usize + 1];
                    if prev_next.first_step == step && prev_next.voxel == from_voxel {
                        return Err(ScheduleError::SwapConflict {
                            from: visit.voxel,
                            to: from_voxel,
                            step,
                            first: id(i),
                            second: id(j),
                        });
                    }
                    // `prev` ended before `step`, so it is not the final visit: it has a Leave.
                    edges.extend(handover(i, prev, j, visit));
                }
            }
            for stacked in reach.related_cells(world, visit.voxel) {
                let Some((i, k)) = world.cell(stacked).and_then(|c| last[c]) else {
                    continue;
                };
                if i == j {
                    continue; // ordered by the drone's own path
                }
                let prev = &visits[i as usize][k as usize];
                if prev.last_step >= step {
                    return Err(ScheduleError::StackedConflict {
                        first_voxel: prev.voxel,
                        second_voxel: visit.voxel,
                        step,
                        first: id(i),
                        second: id(j),
                    });
                }
                edges.extend(handover(i, prev, j, visit));
            }
            last[cell] = Some((j, m));
        }
    }
    Ok(edges)
}

/// The type-2 edge from drone `i`'s `Leave` of its visit `prev` to drone `j`'s
/// `Enter` of `visit` (none if `prev` is a final visit, which has no `Leave`).
fn handover(i: u32, prev: &Visit, j: u32, visit: &Visit) -> Option<CrossEdge> {
    prev.leave.map(|leave| CrossEdge {
        from: EventId {
            drone: i,
            index: leave,
        },
        to: EventId {
            drone: j,
            index: visit.enter,
        },
        voxel: visit.voxel,
        delay_s: 0.0,
    })
}

/// Drops type-2 edges implied by another type-2 edge between the same two drones:
/// `a → b` is implied by `a' → b'` when `a'` is no earlier than `a` on the source drone
/// and `b'` no later than `b` on the target drone (own order closes the path).
fn minimal_edges(mut edges: Vec<CrossEdge>) -> Vec<CrossEdge> {
    edges.sort_unstable_by(|x, y| {
        (
            x.from.drone,
            x.to.drone,
            std::cmp::Reverse(x.from.index),
            x.to.index,
        )
            .cmp(&(
                y.from.drone,
                y.to.drone,
                std::cmp::Reverse(y.from.index),
                y.to.index,
            ))
    });
    let mut kept = Vec::with_capacity(edges.len());
    let mut group = None;
    let mut min_target = u32::MAX;
    for e in edges {
        if group != Some((e.from.drone, e.to.drone)) {
            group = Some((e.from.drone, e.to.drone));
            min_target = u32::MAX;
        }
        if e.to.index < min_target {
            min_target = e.to.index;
            kept.push(e);
        }
    }
    kept
}
