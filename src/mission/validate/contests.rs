//! Whether every leg can end with each drone on a target of its own, across groups.

use super::report::Report;
use crate::mission::contest::contested;
use crate::mission::legs::{LegKind, Targets};
use crate::mission::types::Mission;
use crate::world::Voxel;

/// Refuses a mission in which some leg asks groups for more of the voxels their
/// targets share than there are (see [`contested`]): a goal of a group without
/// starts on another group's start, a stage goal where a spare holds or where a
/// group the stage leaves out stays; under an ellipsoid, two voxels that must both
/// be taken stacked within its vertical reach. The planner would search such a leg
/// until its deadline.
///
/// Where a group stays, or lands below where it is, its drones may be on any of the
/// voxels its previous leg offered it; taking all of them as possible makes this a
/// necessary condition, so nothing that could be planned is refused.
pub(super) fn check_leg_targets(mission: &Mission, report: &mut Report) {
    let groups = &mission.groups;
    let reach = mission.limits.vertical_reach(&mission.airspace);
    // Where each group's drones may be: at first above their pads.
    let mut may_be: Vec<Vec<Voxel>> = groups
        .iter()
        .map(|g| g.drones.iter().map(|d| d.pad_voxel()).collect())
        .collect();
    for leg in mission.legs() {
        // One demand per group (or per drone, for targets of its own).
        let mut sets: Vec<(usize, Vec<Voxel>, String)> = Vec::new();
        for ((targets, g), at) in leg.targets.iter().zip(groups).zip(&mut may_be) {
            let n = g.drones.len();
            let group = format!("group {}", g.name);
            match targets {
                Targets::Any(t) => {
                    sets.push((n, t.clone(), group));
                    *at = t.clone();
                }
                Targets::Stay => sets.push((n, at.clone(), group)),
                Targets::BelowCurrent => {
                    *at = at.iter().map(|v| v.pad_below()).collect();
                    sets.push((n, at.clone(), group));
                }
                Targets::Own(own) => {
                    for (d, &v) in g.drones.iter().zip(own) {
                        sets.push((1, vec![v], format!("drone {}", d.id)));
                    }
                    *at = own.clone();
                }
            }
        }
        let demands: Vec<(usize, &[Voxel])> = sets.iter().map(|(n, t, _)| (*n, &t[..])).collect();
        let stacked = |a: Voxel, b: Voxel| reach.related(&mission.airspace, a, b);
        let Some(contest) = contested(&demands, &stacked) else {
            continue;
        };
        let who: Vec<&str> = contest
            .demands
            .iter()
            .map(|&i| sets[i].2.as_str())
            .collect();
        let voxels: Vec<String> = contest.voxels.iter().map(ToString::to_string).collect();
        let path = match leg.kind {
            LegKind::Takeoff | LegKind::Formation => "groups".to_string(),
            LegKind::Stage => mission
                .stages
                .iter()
                .position(|s| s.name == leg.name)
                .map_or("stages".to_string(), |i| format!("stages[{i}].goals")),
            LegKind::Landing => "landing".to_string(),
        };
        let problem = if contest.stacked {
            format!(
                "they must take {} at once, stacked within the separation's vertical reach ({:.2} m)",
                voxels.join(" and "),
                reach.reach_m
            )
        } else {
            format!(
                "they compete for {} and there are too few of those",
                voxels.join(", ")
            )
        };
        report.add(
            path,
            format!(
                "leg {:?}: {} cannot all end it on targets of their own: {problem} (a goal of one is where another must be then: its start, a spare's hold, or where it stays); give them other goals",
                leg.name,
                who.join(" and "),
            ),
        );
    }
}
