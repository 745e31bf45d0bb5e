//! An independent check of a plan against its mission.
//!
//! Written from the problem statement alone and sharing no code with the solver, so a
//! bug in one is not silently repeated in the other.

use super::discrete_plan::DiscretePlan;
use crate::mission::Mission;
use crate::world::Voxel;
use std::collections::{HashMap, HashSet};

/// One way a plan breaks its mission.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanViolation {
    #[error("drone {0:?} is in the plan but not in the mission, or appears twice")]
    UnknownDrone(String),
    #[error("drone {0:?} of the mission has no path")]
    MissingDrone(String),
    #[error("drone {id:?} is listed in group {found:?} but belongs to {expected:?}")]
    WrongGroup {
        id: String,
        expected: String,
        found: String,
    },
    #[error("drone {id:?}: path has {len} entries, expected makespan + 1 = {expected}")]
    PathLength {
        id: String,
        len: usize,
        expected: usize,
    },
    #[error("drone {id:?}: path starts at {found} instead of its start {expected}")]
    WrongStart {
        id: String,
        expected: Voxel,
        found: Voxel,
    },
    #[error("drone {id:?}: goal {goal} is not a goal of group {group:?}")]
    ForeignGoal {
        id: String,
        group: String,
        goal: Voxel,
    },
    #[error("goal {goal} of group {group:?} is assigned to more than one drone")]
    GoalTwice { group: String, goal: Voxel },
    #[error("drone {id:?}: path ends at {found}, not at its goal {goal}")]
    MissesGoal {
        id: String,
        goal: Voxel,
        found: Voxel,
    },
    #[error("drone {id:?}: step {step} at {voxel} is outside the world or inside an obstacle")]
    NotFree {
        id: String,
        step: usize,
        voxel: Voxel,
    },
    #[error("drone {id:?}: jumps from {from} to {to} at step {step}")]
    Jump {
        id: String,
        step: usize,
        from: Voxel,
        to: Voxel,
    },
    #[error("drones {a:?} and {b:?} are both in {voxel} at step {step}")]
    VertexConflict {
        a: String,
        b: String,
        voxel: Voxel,
        step: usize,
    },
    #[error("drones {a:?} and {b:?} swap {from} and {to} between steps {step} and {}", step + 1)]
    SwapConflict {
        a: String,
        b: String,
        from: Voxel,
        to: Voxel,
        step: usize,
    },
    #[error(
        "drones {} rotate between steps {step} and {}: each enters the voxel the next leaves, which no drone can fly safely",
        drones.join(", "), step + 1
    )]
    Rotation { drones: Vec<String>, step: usize },
    #[error("reported makespan {reported} but the last drone arrives at step {actual}")]
    Makespan { reported: u32, actual: u32 },
    #[error("reported sum of costs {reported} but the arrival steps add up to {actual}")]
    SumOfCosts { reported: u64, actual: u64 },
}

/// Every way `plan` breaks `mission`; empty means the plan is valid.
pub fn validate_plan(mission: &Mission, plan: &DiscretePlan) -> Result<(), Vec<PlanViolation>> {
    let mut violations = Vec::new();
    let expected_len = plan.makespan_steps as usize + 1;

    let mut owner: HashMap<&str, (&str, Voxel, &[Voxel])> = HashMap::new();
    for group in &mission.groups {
        for drone in &group.drones {
            owner.insert(&drone.id, (&group.name, drone.start, &group.goals));
        }
    }
    let mut seen = HashSet::new();
    let mut goals_taken: HashSet<(&str, Voxel)> = HashSet::new();
    let mut latest_arrival = 0u32;
    let mut arrivals_total = 0u64;
    for d in &plan.drones {
        let id = d.id.clone();
        let Some(&(group, start, goals)) = owner.get(d.id.as_str()) else {
            violations.push(PlanViolation::UnknownDrone(id));
            continue;
        };
        if !seen.insert(d.id.as_str()) {
            violations.push(PlanViolation::UnknownDrone(id));
            continue;
        }
        if d.group != group {
            violations.push(PlanViolation::WrongGroup {
                id: id.clone(),
                expected: group.to_string(),
                found: d.group.clone(),
            });
        }
        if !goals.contains(&d.goal) {
            violations.push(PlanViolation::ForeignGoal {
                id: id.clone(),
                group: group.to_string(),
                goal: d.goal,
            });
        } else if !goals_taken.insert((group, d.goal)) {
            violations.push(PlanViolation::GoalTwice {
                group: group.to_string(),
                goal: d.goal,
            });
        }
        if d.path.len() != expected_len {
            violations.push(PlanViolation::PathLength {
                id: id.clone(),
                len: d.path.len(),
                expected: expected_len,
            });
        }
        let (Some(&first), Some(&last)) = (d.path.first(), d.path.last()) else {
            continue;
        };
        if first != start {
            violations.push(PlanViolation::WrongStart {
                id: id.clone(),
                expected: start,
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
        latest_arrival = latest_arrival.max(arrival as u32);
        arrivals_total += arrival as u64;
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
    for step in 0..expected_len {
        let mut here: HashMap<Voxel, &str> = HashMap::new();
        for d in &common {
            if let Some(other) = here.insert(d.path[step], &d.id) {
                violations.push(PlanViolation::VertexConflict {
                    a: other.to_string(),
                    b: d.id.clone(),
                    voxel: d.path[step],
                    step,
                });
            }
        }
        if step + 1 == expected_len {
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

/// Cycles of three or more drones moving in one step, each into the voxel the next
/// one leaves (two-drone cycles are swaps, reported above).
fn rotations(drones: &[&super::discrete_plan::DronePlan], len: usize) -> Vec<PlanViolation> {
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
