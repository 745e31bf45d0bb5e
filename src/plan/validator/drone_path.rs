//! One drone's path on its own, whatever the other drones do.

use super::owner::{Owner, Start};
use super::violation::PlanViolation;
use crate::mission::Mission;
use crate::plan::discrete_plan::DronePlan;

/// The drone's path on its own: length, start, end, free voxels, unit moves. Returns
/// the step from which it stays at its last voxel (`None` for an empty path).
pub(super) fn path(
    mission: &Mission,
    d: &DronePlan,
    owner: &Owner,
    expected_len: usize,
    violations: &mut Vec<PlanViolation>,
) -> Option<usize> {
    let id = &d.id;
    if d.path.len() != expected_len {
        violations.push(PlanViolation::PathLength {
            id: id.clone(),
            len: d.path.len(),
            expected: expected_len,
        });
    }
    let (Some(&first), Some(&last)) = (d.path.first(), d.path.last()) else {
        return None;
    };
    match owner.start {
        None => violations.push(PlanViolation::NoStart(id.clone())),
        Some(Start::Pad(expected)) if first != expected => {
            violations.push(PlanViolation::WrongStart {
                id: id.clone(),
                expected,
                found: first,
            });
        }
        Some(Start::Live(expected)) if first != expected => {
            violations.push(PlanViolation::WrongLiveStart {
                id: id.clone(),
                expected,
                found: first,
            });
        }
        Some(_) => {}
    }
    if last != d.goal {
        violations.push(PlanViolation::MissesGoal {
            id: id.clone(),
            goal: d.goal,
            found: last,
        });
    }
    for (step, &voxel) in d.path.iter().enumerate() {
        if !mission.airspace.is_free(voxel) {
            violations.push(PlanViolation::NotFree {
                id: id.clone(),
                step,
                voxel,
                in_obstacle: mission.airspace.contains(voxel),
            });
        }
    }
    for (step, pair) in d.path.windows(2).enumerate() {
        let (from, to) = (pair[0], pair[1]);
        let moved = from.x.abs_diff(to.x) + from.y.abs_diff(to.y) + from.z.abs_diff(to.z);
        if moved > 1 {
            violations.push(PlanViolation::Jump {
                id: id.clone(),
                step,
                from,
                to,
            });
        }
    }
    let mut arrival = d.path.len();
    while arrival > 0 && d.path[arrival - 1] == last {
        arrival -= 1;
    }
    Some(arrival)
}
