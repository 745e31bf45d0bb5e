//! Conflicts between drones on the voxel grid: two in one voxel, two trading
//! places, or three or more moving round a loop in one step.

use super::violation::PlanViolation;
use crate::plan::discrete_plan::DronePlan;
use crate::world::Voxel;
use std::collections::{HashMap, HashSet};

/// Two drones in one voxel at a step, or trading places within a step.
pub(super) fn meetings_and_swaps(common: &[&DronePlan], len: usize) -> Vec<PlanViolation> {
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
pub(super) fn rotations(drones: &[&DronePlan], len: usize) -> Vec<PlanViolation> {
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
