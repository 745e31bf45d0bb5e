//! Whether every drone can reach, from its pad, every formation its group flies.

use super::report::Report;
use crate::mission::types::{Group, Stage};
use crate::world::{Voxel, VoxelGrid};
use std::collections::HashMap;

/// Drones move only within the connected component of free space their pad lies in
/// (obstacles standing on the ground may split the pad layer), so a group can fill
/// a formation exactly when, component by component, the drones there can be
/// matched to the formation's voxels there: the largest matching is the sum over
/// components of the smaller count (Hall's condition on a union of complete
/// bipartite graphs), and it must cover every drone, or with spares (fewer voxels
/// than drones) every voxel. Checked for the group's starts, and for its goals and
/// every stage's goals for it as the planner's legs ask for them: with the spares'
/// holds (a drone walled in with its pad needs a target of its own there too).
///
/// When formations keep out of the pad layer (`formations_use_pad_layer` false),
/// each formation after the starts must also be reachable from the one before it
/// within the world's own voxels.
pub(super) fn check_reachability(
    airspace: &VoxelGrid,
    formations_use_pad_layer: bool,
    groups: &[Group],
    stages: &[Stage],
    report: &mut Report,
) {
    let label = airspace.components();
    let world_only = (!formations_use_pad_layer).then(|| {
        let grid = airspace.without_pad_layer();
        let labels = grid.components();
        (grid, labels)
    });
    for (gi, g) in groups.iter().enumerate() {
        let pads: Vec<Voxel> = g.drones.iter().map(|d| d.pad_voxel()).collect();
        let starts: Vec<Voxel> = g.drones.iter().filter_map(|d| d.start).collect();
        let mut sets: Vec<(String, Vec<Voxel>)> = vec![
            (format!("groups[{gi}].drones"), starts),
            (format!("groups[{gi}].goals"), g.formation_targets(&g.goals)),
        ];
        for (si, s) in stages.iter().enumerate() {
            if let Some(Some(goals)) = s.goals.get(gi) {
                let path = format!("stages[{si}].goals.{}", g.name);
                sets.push((path, g.formation_targets(goals)));
            }
        }
        let mut previous: Option<&[Voxel]> = None;
        for (path, set) in &sets {
            if set.is_empty() {
                continue;
            }
            let mut problem = unmatched(airspace, &label, &pads, set, g.drones.len())
                .map(|walled| (walled, "from the pads"));
            if let (None, Some((grid, labels)), Some(from)) = (&problem, &world_only, previous) {
                problem = unmatched(grid, labels, from, set, g.drones.len())
                    .map(|walled| (walled, "from the formation before, within the world's voxels (formations_use_pad_layer is false)"));
            }
            if let Some(((reachable, walled), from)) = problem {
                let which = if walled.is_empty() {
                    "obstacles split the drones from too many of them".to_string()
                } else {
                    format!("walled off by obstacles: {}", walled.join(", "))
                };
                report.add(
                    path,
                    format!(
                        "group {:?}: only {reachable} of these voxels can be reached {from}, for {} drone(s); {which}",
                        g.name,
                        g.drones.len(),
                    ),
                );
            }
            previous = Some(set);
        }
    }
}

/// When the drones at `from` (one per drone; a formation's voxels, at least one per
/// drone, stand for where the drones may be) cannot be matched to enough of `to` in
/// `grid` (components `label`), how many can and which voxels of `to` no drone reaches.
fn unmatched(
    grid: &VoxelGrid,
    label: &[u32],
    from: &[Voxel],
    to: &[Voxel],
    drones: usize,
) -> Option<(usize, Vec<String>)> {
    let component = |v: &Voxel| grid.cell(*v).map(|c| label[c]).filter(|&l| l != u32::MAX);
    let mut at: HashMap<u32, usize> = HashMap::new();
    for c in from.iter().filter_map(component) {
        *at.entry(c).or_default() += 1;
    }
    let mut wanted: HashMap<u32, usize> = HashMap::new();
    for c in to.iter().filter_map(component) {
        *wanted.entry(c).or_default() += 1;
    }
    let matched: usize = wanted
        .iter()
        .map(|(c, &n)| n.min(at.get(c).copied().unwrap_or(0)).min(drones))
        .sum();
    let needed = drones.min(to.len()).min(from.len());
    if matched >= needed {
        return None;
    }
    let walled = to
        .iter()
        .filter(|v| component(v).is_none_or(|c| !at.contains_key(&c)))
        .map(|v| v.to_string())
        .collect();
    Some((matched, walled))
}
