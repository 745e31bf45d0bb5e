//! The mission's legs against the plan's: names, holds, steps, and where every
//! drone stands when each leg ends.

use super::owner::Owner;
use super::violation::PlanViolation;
use crate::mission::Mission;
use crate::plan::discrete_plan::DiscretePlan;
use crate::world::Voxel;
use std::collections::{HashMap, HashSet};

/// Every leg of the mission, in order, against the plan's: the same names and holds,
/// steps that add up, and at each leg's last step every drone on a target the leg
/// allows it (shared targets: any of the group's; own targets: its own, where own
/// targets may depend on where the previous leg left it).
pub(super) fn legs(
    mission: &Mission,
    from_leg: usize,
    plan: &DiscretePlan,
    owners: &HashMap<&str, Owner>,
    violations: &mut Vec<PlanViolation>,
) {
    let wanted: Vec<_> = mission.legs().into_iter().skip(from_leg).collect();
    let names = |v: Vec<&str>| v.join(", ");
    if wanted.len() != plan.legs.len()
        || wanted
            .iter()
            .zip(&plan.legs)
            .any(|(w, p)| w.name != p.name || w.kind != p.kind)
    {
        violations.push(PlanViolation::Legs(format!(
            "the mission flies [{}], the plan [{}]",
            names(wanted.iter().map(|l| l.name.as_str()).collect()),
            names(plan.legs.iter().map(|l| l.name.as_str()).collect())
        )));
        return;
    }
    let mut previous_end = 0usize;
    for (w, p) in wanted.iter().zip(&plan.legs) {
        let end = p.end_step as usize;
        if end < previous_end || end > plan.makespan_steps as usize {
            violations.push(PlanViolation::Legs(format!(
                "leg {:?} ends at step {end}, before the previous leg (step {previous_end}) or after the makespan",
                p.name
            )));
            return;
        }
        if (w.hold_s - p.hold_s).abs() > 1e-9 {
            violations.push(PlanViolation::Legs(format!(
                "leg {:?} holds {} s in the plan but {} s in the mission",
                p.name, p.hold_s, w.hold_s
            )));
        }
        let mut taken: HashSet<(usize, Voxel)> = HashSet::new();
        for d in &plan.drones {
            let Some(owner) = owners.get(d.id.as_str()) else {
                continue;
            };
            let (gi, di) = owner.at;
            let (Some(&found), Some(&before)) = (d.path.get(end), d.path.get(previous_end)) else {
                continue;
            };
            let expected = match &w.targets[gi] {
                crate::mission::Targets::Any(set) => (!set.contains(&found))
                    .then(|| format!("not a target of group {:?}", owner.group)),
                crate::mission::Targets::Own(own) => own
                    .get(di)
                    .filter(|&&v| v != found)
                    .map(|v| format!("not its own target {v}")),
                crate::mission::Targets::Stay => (found != before)
                    .then(|| format!("not where it was at step {previous_end}, {before}")),
                crate::mission::Targets::BelowCurrent => {
                    let below = Voxel::new(before.x, before.y, -1);
                    (found != below)
                        .then(|| format!("not the pad-layer cell below {before}, {below}"))
                }
            };
            let expected = expected.or_else(|| {
                (!taken.insert((gi, found)))
                    .then(|| "a target another drone also ends on".to_string())
            });
            if let Some(expected) = expected {
                violations.push(PlanViolation::MissesLegTarget {
                    id: d.id.clone(),
                    leg: p.name.clone(),
                    step: end,
                    found,
                    expected,
                });
            }
            if !w.pad_layer_open {
                // The pad layer is z = -1 (below voxel layer 0), whatever the grid.
                let low = (previous_end..=end)
                    .find_map(|step| d.path.get(step).filter(|v| v.z < 0).map(|&v| (step, v)));
                if let Some((step, voxel)) = low {
                    violations.push(PlanViolation::InPadLayer {
                        id: d.id.clone(),
                        leg: p.name.clone(),
                        step,
                        voxel,
                    });
                }
            }
        }
        previous_end = end;
    }
    if previous_end != plan.makespan_steps as usize {
        violations.push(PlanViolation::Legs(format!(
            "the last leg ends at step {previous_end}, the plan's makespan is {}",
            plan.makespan_steps
        )));
    }
}
