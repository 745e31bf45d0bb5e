//! Whether every drone can reach a goal of its own group through free space.

use super::report::Report;
use crate::mission::types::Group;
use crate::world::{Voxel, VoxelGrid};
use std::collections::BTreeMap;

/// Every drone must reach a distinct goal of its own group. Free space splits into
/// connected components, and within one component every drone reaches every goal, so
/// a group can be matched exactly when each component holds as many of its goals as
/// of its drones (Hall's condition on a union of complete bipartite graphs).
pub(super) fn check_reachability(world: &VoxelGrid, groups: &[Group], report: &mut Report) {
    let label = world.components();
    let component = |v: Voxel| world.cell(v).map(|c| label[c]);
    for (gi, g) in groups.iter().enumerate() {
        let mut balance: BTreeMap<Option<u32>, (Vec<usize>, usize)> = BTreeMap::new();
        for (di, d) in g.drones.iter().enumerate() {
            balance.entry(component(d.start)).or_default().0.push(di);
        }
        for &goal in &g.goals {
            balance.entry(component(goal)).or_default().1 += 1;
        }
        for (drones, goal_count) in balance.values() {
            if drones.len() <= *goal_count {
                continue;
            }
            let ids: Vec<&str> = drones.iter().map(|&di| g.drones[di].id.as_str()).collect();
            let path = if drones.len() == 1 {
                format!("groups[{gi}].drones[{}]", drones[0])
            } else {
                format!("groups[{gi}]")
            };
            let message = if *goal_count == 0 {
                format!(
                    "group {:?}: drone(s) {} can reach no goal of their group (walled off by obstacles)",
                    g.name,
                    ids.join(", ")
                )
            } else {
                format!(
                    "group {:?}: drones {} share a region of free space with only {goal_count} of the group's goals, so they cannot all reach distinct goals",
                    g.name,
                    ids.join(", ")
                )
            };
            report.add(path, message);
        }
    }
}
