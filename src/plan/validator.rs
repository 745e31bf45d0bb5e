//! An independent check of a plan against its mission.
//!
//! Written from the problem statement alone and sharing no code with the solver, so a
//! bug in one is not silently repeated in the other.

use super::discrete_plan::{DiscretePlan, DronePlan};
use crate::mission::Mission;
use crate::world::Voxel;
use std::collections::{HashMap, HashSet};

/// One way a plan breaks its mission. Drones are named by id; `step` counts plan steps
/// from 0; voxels are mission grid coordinates.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanViolation {
    /// A drone id of the plan that the mission does not have, or a second path for one.
    #[error("drone {0:?} is in the plan but not in the mission, or appears twice")]
    UnknownDrone(String),
    /// A drone of the mission that the plan leaves out.
    #[error("drone {0:?} of the mission has no path")]
    MissingDrone(String),
    /// The plan files a drone under another group than the mission does.
    #[error("drone {id:?} is listed in group {found:?} but belongs to {expected:?}")]
    WrongGroup {
        /// The drone.
        id: String,
        /// Its group in the mission.
        expected: String,
        /// The group the plan gives.
        found: String,
    },
    /// A path that does not cover every step from 0 to the makespan.
    #[error("drone {id:?}: path has {len} entries, expected makespan + 1 = {expected}")]
    PathLength {
        /// The drone.
        id: String,
        /// Entries in its path.
        len: usize,
        /// `makespan_steps + 1`.
        expected: usize,
    },
    /// A path that does not start where the mission puts the drone.
    #[error("drone {id:?}: path starts at {found} instead of its start {expected}")]
    WrongStart {
        /// The drone.
        id: String,
        /// Its start in the mission.
        expected: Voxel,
        /// The path's first voxel.
        found: Voxel,
    },
    /// A drone assigned a goal its group does not have.
    #[error("drone {id:?}: goal {goal} is not a goal of group {group:?}")]
    ForeignGoal {
        /// The drone.
        id: String,
        /// Its group.
        group: String,
        /// The goal the plan assigns.
        goal: Voxel,
    },
    /// Two drones of a group assigned the same goal.
    #[error("goal {goal} of group {group:?} is assigned to more than one drone")]
    GoalTwice {
        /// The group.
        group: String,
        /// The goal assigned twice.
        goal: Voxel,
    },
    /// A path that does not end at its drone's assigned goal.
    #[error("drone {id:?}: path ends at {found}, not at its goal {goal}")]
    MissesGoal {
        /// The drone.
        id: String,
        /// Its assigned goal.
        goal: Voxel,
        /// The path's last voxel.
        found: Voxel,
    },
    /// A path through an obstacle or out of the world.
    #[error("drone {id:?}: step {step} at {voxel} is outside the world or inside an obstacle")]
    NotFree {
        /// The drone.
        id: String,
        /// The first offending step.
        step: usize,
        /// Where the path is then.
        voxel: Voxel,
    },
    /// A move between voxels that are not face neighbours.
    #[error("drone {id:?}: jumps from {from} to {to} at step {step}")]
    Jump {
        /// The drone.
        id: String,
        /// The step the move starts at.
        step: usize,
        /// Where it starts.
        from: Voxel,
        /// Where it lands.
        to: Voxel,
    },
    /// Two drones in one voxel at one step.
    #[error("drones {a:?} and {b:?} are both in {voxel} at step {step}")]
    VertexConflict {
        /// One drone.
        a: String,
        /// The other.
        b: String,
        /// The shared voxel.
        voxel: Voxel,
        /// The step they share it.
        step: usize,
    },
    /// Two drones trading places in one step (they would pass through each other).
    #[error("drones {a:?} and {b:?} swap {from} and {to} between steps {step} and {}", step + 1)]
    SwapConflict {
        /// The drone moving `from` → `to`.
        a: String,
        /// The drone moving `to` → `from`.
        b: String,
        /// Where `a` starts.
        from: Voxel,
        /// Where `b` starts.
        to: Voxel,
        /// The step the swap starts at.
        step: usize,
    },
    /// Drones following each other round a loop in one step: no precedence schedule
    /// can fly it with a safety distance.
    #[error(
        "drones {} rotate between steps {step} and {}: each enters the voxel the next leaves, which no drone can fly safely",
        drones.join(", "), step + 1
    )]
    Rotation {
        /// The drones round the loop, in order.
        drones: Vec<String>,
        /// The step the rotation starts at.
        step: usize,
    },
    /// The plan's makespan is not when its last drone arrives.
    #[error("reported makespan {reported} but the last drone arrives at step {actual}")]
    Makespan {
        /// What the plan says, steps.
        reported: u32,
        /// What its paths give, steps.
        actual: u32,
    },
    /// The plan's sum of costs is not the sum of its drones' arrival steps.
    #[error("reported sum of costs {reported} but the arrival steps add up to {actual}")]
    SumOfCosts {
        /// What the plan says, steps.
        reported: u64,
        /// What its paths give, steps.
        actual: u64,
    },
}

/// Every way `plan` breaks `mission`; empty means the plan is valid.
pub fn validate_plan(mission: &Mission, plan: &DiscretePlan) -> Result<(), Vec<PlanViolation>> {
    let mut violations = Vec::new();
    let expected_len = plan.makespan_steps as usize + 1;

    let mut owners: HashMap<&str, Owner> = HashMap::new();
    for group in &mission.groups {
        for drone in &group.drones {
            owners.insert(
                &drone.id,
                Owner {
                    group: &group.name,
                    start: drone.start,
                    goals: &group.goals,
                },
            );
        }
    }
    let mut seen = HashSet::new();
    let mut goals_taken: HashSet<(&str, Voxel)> = HashSet::new();
    let mut latest_arrival = 0u32;
    let mut arrivals_total = 0u64;
    for d in &plan.drones {
        let Some(owner) = owners.get(d.id.as_str()) else {
            violations.push(PlanViolation::UnknownDrone(d.id.clone()));
            continue;
        };
        if !seen.insert(d.id.as_str()) {
            violations.push(PlanViolation::UnknownDrone(d.id.clone()));
            continue;
        }
        assignment(d, owner, &mut goals_taken, &mut violations);
        if let Some(arrival) = path(mission, d, owner, expected_len, &mut violations) {
            latest_arrival = latest_arrival.max(arrival as u32);
            arrivals_total += arrival as u64;
        }
    }
    for group in &mission.groups {
        for drone in &group.drones {
            if !seen.contains(drone.id.as_str()) {
                violations.push(PlanViolation::MissingDrone(drone.id.clone()));
            }
        }
    }

    // Collisions, step by step, over paths of the common length.
    let common: Vec<_> = plan
        .drones
        .iter()
        .filter(|d| d.path.len() == expected_len)
        .collect();
    // Only steps the paths really hold: a hostile `makespan_steps` of 4e9 with short
    // paths must not spin here for hours.
    let expected_len = if common.is_empty() { 0 } else { expected_len };
    violations.extend(meetings_and_swaps(&common, expected_len));
    violations.extend(rotations(&common, expected_len));

    if latest_arrival != plan.makespan_steps {
        violations.push(PlanViolation::Makespan {
            reported: plan.makespan_steps,
            actual: latest_arrival,
        });
    }
    if arrivals_total != plan.sum_of_costs_steps {
        violations.push(PlanViolation::SumOfCosts {
            reported: plan.sum_of_costs_steps,
            actual: arrivals_total,
        });
    }
    if violations.is_empty() {
        Ok(())
    } else {
        Err(violations)
    }
}

/// What the mission says about one drone.
struct Owner<'m> {
    group: &'m str,
    start: Voxel,
    goals: &'m [Voxel],
}

/// The drone's group and goal against the mission's (each goal taken once per group).
fn assignment<'p>(
    d: &'p DronePlan,
    owner: &Owner<'p>,
    goals_taken: &mut HashSet<(&'p str, Voxel)>,
    violations: &mut Vec<PlanViolation>,
) {
    if d.group != owner.group {
        violations.push(PlanViolation::WrongGroup {
            id: d.id.clone(),
            expected: owner.group.to_string(),
            found: d.group.clone(),
        });
    }
    if !owner.goals.contains(&d.goal) {
        violations.push(PlanViolation::ForeignGoal {
            id: d.id.clone(),
            group: owner.group.to_string(),
            goal: d.goal,
        });
    } else if !goals_taken.insert((owner.group, d.goal)) {
        violations.push(PlanViolation::GoalTwice {
            group: owner.group.to_string(),
            goal: d.goal,
        });
    }
}

/// The drone's path on its own: length, start, end, free voxels, unit moves. Returns
/// the step from which it stays at its last voxel (`None` for an empty path).
fn path(
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
    if first != owner.start {
        violations.push(PlanViolation::WrongStart {
            id: id.clone(),
            expected: owner.start,
            found: first,
        });
    }
    if last != d.goal {
        violations.push(PlanViolation::MissesGoal {
            id: id.clone(),
            goal: d.goal,
            found: last,
        });
    }
    for (step, &voxel) in d.path.iter().enumerate() {
        if !mission.world.is_free(voxel) {
            violations.push(PlanViolation::NotFree {
                id: id.clone(),
                step,
                voxel,
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

/// Two drones in one voxel at a step, or trading places within a step.
fn meetings_and_swaps(common: &[&DronePlan], len: usize) -> Vec<PlanViolation> {
    let mut violations = Vec::new();
    for step in 0..len {
        let mut here: HashMap<Voxel, &str> = HashMap::new();
        for d in common {
            if let Some(other) = here.insert(d.path[step], &d.id) {
                violations.push(PlanViolation::VertexConflict {
                    a: other.to_string(),
                    b: d.id.clone(),
                    voxel: d.path[step],
                    step,
                });
            }
        }
        if step + 1 == len {
            break;
        }
        let moves: HashMap<(Voxel, Voxel), &str> = common
            .iter()
            .filter(|d| d.path[step] != d.path[step + 1])
            .map(|d| ((d.path[step], d.path[step + 1]), d.id.as_str()))
            .collect();
        for (&(from, to), &a) in &moves {
            if let Some(&b) = moves.get(&(to, from)).filter(|&&b| a < b) {
                violations.push(PlanViolation::SwapConflict {
                    a: a.to_string(),
                    b: b.to_string(),
                    from,
                    to,
                    step,
                });
            }
        }
    }
    violations
}

/// Cycles of three or more drones moving in one step, each into the voxel the next
/// one leaves (two-drone cycles are swaps, reported above).
fn rotations(drones: &[&DronePlan], len: usize) -> Vec<PlanViolation> {
    let mut found = Vec::new();
    for step in 0..len.saturating_sub(1) {
        let at_step: HashMap<Voxel, usize> = drones
            .iter()
            .enumerate()
            .map(|(i, d)| (d.path[step], i))
            .collect();
        // successor[i] = the drone whose voxel drone i moves into, if that one moves too.
        let successor = |i: usize| -> Option<usize> {
            let d = drones[i];
            let target = d.path[step + 1];
            if target == d.path[step] {
                return None;
            }
            let j = *at_step.get(&target)?;
            (drones[j].path[step + 1] != drones[j].path[step]).then_some(j)
        };
        let mut reported: HashSet<usize> = HashSet::new();
        for i in 0..drones.len() {
            // Walk at most n successors; a cycle through i returns to i.
            let mut members = vec![i];
            let mut current = i;
            while let Some(next) = successor(current) {
                if next == i || members.len() > drones.len() {
                    break;
                }
                members.push(next);
                current = next;
            }
            let closes = successor(current) == Some(i);
            if closes && members.len() >= 3 && members.iter().all(|m| reported.insert(*m)) {
                found.push(PlanViolation::Rotation {
                    drones: members.iter().map(|&m| drones[m].id.clone()).collect(),
                    step,
                });
            }
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{self, PlanOptions};

    /// A hostile plan file may claim any makespan; the check must stay bounded by
    /// the data it was given.
    #[test]
    fn absurd_makespan_with_short_paths_is_refused_at_once() {
        let mission = crate::mission::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/missions/swap-corridor.yaml"
        )))
        .expect("mission");
        let mut plan = plan::solve(&mission, &PlanOptions::default())
            .expect("plan")
            .plan;
        plan.makespan_steps = u32::MAX - 1;
        // Before the fix this looped ~4e9 times over the steps.
        let violations = validate_plan(&mission, &plan).expect_err("refused");
        assert!(
            violations
                .iter()
                .any(|v| matches!(v, PlanViolation::PathLength { .. })),
            "{violations:?}"
        );
    }
}
