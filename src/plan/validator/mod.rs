//! An independent check of a plan against its mission.
//!
//! Written from the problem statement alone and sharing no code with the solver, so a
//! bug in one is not silently repeated in the other. The checks are split by what
//! they look at: the drones' own paths (`drone_path`), the mission's legs (`legs`),
//! drones meeting, swapping or rotating (`conflicts`), and stacking under an
//! ellipsoidal separation (`stacking`). None of these files imports the planner.

mod conflicts;
mod drone_path;
mod legs;
mod owner;
mod stacking;
mod violation;

pub use violation::PlanViolation;

use super::discrete_plan::DiscretePlan;
use crate::mission::{Drone, Mission};
use crate::world::Voxel;
use owner::{Owner, Start};
use std::collections::{HashMap, HashSet};

/// Every way `plan` breaks `mission`; empty means the plan is valid.
pub fn validate_plan(mission: &Mission, plan: &DiscretePlan) -> Result<(), Vec<PlanViolation>> {
    let pad = |drone: &Drone| Some(Start::Pad(drone.pad_voxel()));
    check(mission, 0, &pad, plan)
}

/// Every way `plan`, the rest of a flight from leg `from_leg` of `mission` (an
/// index into `Mission::legs`), breaks it, each drone starting where `starts` (id,
/// voxel) puts it — a replan's plan against the survivors' mission it was planned
/// in (`plan::Replanned`). A drone of the mission missing from `starts` is
/// reported as a wrong start. Empty means the plan is valid.
pub fn validate_rest(
    mission: &Mission,
    from_leg: usize,
    starts: &[(&str, Voxel)],
    plan: &DiscretePlan,
) -> Result<(), Vec<PlanViolation>> {
    let start_of = |drone: &Drone| {
        let live = starts.iter().find(|s| s.0 == drone.id);
        live.map(|s| Start::Live(s.1))
    };
    check(mission, from_leg, &start_of, plan)
}

/// The checks of [`validate_plan`] and [`validate_rest`], each drone's path
/// starting at `start_of` it (`None`: no start is acceptable).
fn check(
    mission: &Mission,
    from_leg: usize,
    start_of: &dyn Fn(&Drone) -> Option<Start>,
    plan: &DiscretePlan,
) -> Result<(), Vec<PlanViolation>> {
    let mut violations = Vec::new();
    let expected_len = plan.makespan_steps as usize + 1;

    let mut owners: HashMap<&str, Owner> = HashMap::new();
    for (gi, group) in mission.groups.iter().enumerate() {
        for (di, drone) in group.drones.iter().enumerate() {
            owners.insert(
                &drone.id,
                Owner {
                    group: &group.name,
                    start: start_of(drone),
                    at: (gi, di),
                },
            );
        }
    }
    let mut seen = HashSet::new();
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
        if d.group != owner.group {
            violations.push(PlanViolation::WrongGroup {
                id: d.id.clone(),
                expected: owner.group.to_string(),
                found: d.group.clone(),
            });
        }
        if let Some(arrival) = drone_path::path(mission, d, owner, expected_len, &mut violations) {
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
    legs::legs(mission, from_leg, plan, &owners, &mut violations);

    // Collisions, step by step, over paths of the common length.
    let common: Vec<_> = plan
        .drones
        .iter()
        .filter(|d| d.path.len() == expected_len)
        .collect();
    // Only steps the paths really hold: a hostile `makespan_steps` of 4e9 with short
    // paths must not spin here for hours.
    let expected_len = if common.is_empty() { 0 } else { expected_len };
    violations.extend(conflicts::meetings_and_swaps(&common, expected_len));
    violations.extend(conflicts::rotations(&common, expected_len));
    if let Some(reach_m) = stacking::vertical_reach_m(mission) {
        violations.extend(stacking::stacking(mission, reach_m, &common, expected_len));
    }

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
