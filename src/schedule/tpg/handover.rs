//! Type-2 edges: each voxel handed over from one visitor to the next (and, under an
//! ellipsoid, between cells within vertical reach), conflicts the plan should not
//! contain rejected, and edges another edge already implies dropped.

use super::events::{Visit, invalid};
use super::{CrossEdge, EventId};
use crate::plan::DiscretePlan;
use crate::schedule::ScheduleError;
use crate::world::{VerticalReach, VoxelGrid};

/// Type-2 candidates: for every visit of a voxel, an edge from the previous visitor's
/// `Leave` marker to this visitor's `Enter` marker. Consecutive visits suffice: earlier
/// visitors are ordered before the previous one already.
///
/// Under an ellipsoid a visit also waits for the latest earlier visitor of every
/// cell stacked with it (within the vertical reach): those are held like the cell
/// itself.
pub(super) fn cross_candidates(
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
pub(super) fn minimal_edges(mut edges: Vec<CrossEdge>) -> Vec<CrossEdge> {
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
