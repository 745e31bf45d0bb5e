//! Formations an ellipsoidal separation cannot hold: two cells of one formation
//! stacked in a column within the ellipsoid's vertical reach (see
//! [`crate::world::VerticalReach`]). No plan can put drones in both at once, so the
//! mission is refused here, naming both cells, rather than by the planner.

use super::report::Report;
use crate::mission::types::{Group, Limits, Stage};
use crate::world::{Voxel, VoxelGrid};

/// Reports stacked pairs among the starts, among the groups' goals, and among each
/// stage's goals. Does nothing for a sphere.
pub(super) fn check_stacking(
    airspace: &VoxelGrid,
    limits: &Limits,
    groups: &[Group],
    stages: &[Stage],
    report: &mut Report,
) {
    let Some(vertical_m) = limits.vertical_separation_m else {
        return;
    };
    let reach = limits.vertical_reach(airspace);
    if reach.is_trivial(airspace) {
        return;
    }
    let why = format!(
        "inside the ellipsoid's vertical reach ({:.2} m: {vertical_m:.2} m + 2 × {:.2} m tracking error): no two drones may hold both at once (move one, or lower limits.separation.vertical_m or limits.tracking_error_m)",
        reach.reach_m, limits.tracking_error_m
    );
    let starts: Vec<(String, Voxel)> = groups
        .iter()
        .enumerate()
        .flat_map(|(gi, g)| {
            g.drones.iter().enumerate().filter_map(move |(di, d)| {
                d.start
                    .map(|v| (format!("groups[{gi}].drones[{di}].start"), v))
            })
        })
        .collect();
    let goals: Vec<(String, Voxel)> = groups
        .iter()
        .enumerate()
        .flat_map(|(gi, g)| {
            g.goals
                .iter()
                .map(move |&v| (format!("groups[{gi}].goals"), v))
        })
        .collect();
    let mut formations = vec![starts, goals];
    for (si, stage) in stages.iter().enumerate() {
        formations.push(
            stage
                .goals
                .iter()
                .enumerate()
                .flat_map(|(gi, goals)| {
                    goals
                        .iter()
                        .flatten()
                        .map(move |&v| (format!("stages[{si}].goals[{gi}]"), v))
                })
                .collect(),
        );
    }
    for cells in &formations {
        for (i, (path, a)) in cells.iter().enumerate() {
            for (other, b) in &cells[i + 1..] {
                if reach.related(airspace, *a, *b) {
                    let apart_m = (airspace.center_m(*a).z - airspace.center_m(*b).z).abs();
                    report.add(
                        path.as_str(),
                        format!("{a} and {b} ({other}) are stacked {apart_m:.2} m apart in one column, {why}"),
                    );
                }
            }
        }
    }
}
