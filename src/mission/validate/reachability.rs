//! Whether every drone can reach, from its pad, every formation its group flies.

use super::report::Report;
use crate::mission::types::{Group, Stage};
use crate::world::{Voxel, VoxelGrid};

/// Every pad lies in the pad layer, which is one connected region of free space, so
/// every drone starts in the same component; a group can fill a formation exactly
/// when that component holds at least as many of the formation's voxels as the group
/// has drones (Hall's condition on a complete bipartite graph). Checked for the
/// group's starts, its goals and every stage's goals for it.
pub(super) fn check_reachability(
    airspace: &VoxelGrid,
    groups: &[Group],
    stages: &[Stage],
    report: &mut Report,
) {
    let label = airspace.components();
    let component = |v: Voxel| airspace.cell(v).map(|c| label[c]);
    for (gi, g) in groups.iter().enumerate() {
        let Some(home) = g.drones.first().and_then(|d| component(d.pad_voxel())) else {
            continue;
        };
        let starts: Vec<Voxel> = g.drones.iter().filter_map(|d| d.start).collect();
        let mut sets: Vec<(String, &[Voxel])> = vec![
            (format!("groups[{gi}].drones"), &starts[..]),
            (format!("groups[{gi}].goals"), &g.goals[..]),
        ];
        for (si, s) in stages.iter().enumerate() {
            if let Some(Some(goals)) = s.goals.get(gi) {
                sets.push((format!("stages[{si}].goals.{}", g.name), &goals[..]));
            }
        }
        for (path, set) in sets {
            if set.is_empty() {
                continue;
            }
            let reachable = set.iter().filter(|&&v| component(v) == Some(home)).count();
            // Every drone needs one; with spares (fewer goals than drones) every goal.
            if reachable < g.drones.len().min(set.len()) {
                let walled: Vec<String> = set
                    .iter()
                    .filter(|&&v| component(v) != Some(home))
                    .map(|v| v.to_string())
                    .collect();
                report.add(
                    path,
                    format!(
                        "group {:?}: only {reachable} of these voxels can be reached from the pads, for {} drone(s); walled off by obstacles: {}",
                        g.name,
                        g.drones.len(),
                        walled.join(", ")
                    ),
                );
            }
        }
    }
}
