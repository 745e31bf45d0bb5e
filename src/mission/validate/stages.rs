//! Formation stages and the landing mode: stage names, holds and goals (checked like
//! the groups' own goals), and whether `below_goal` can descend straight down.

use super::pads::blocked_below;
use super::report::Report;
use super::world::GroundCells;
use super::world::{Bounds, free_voxel};
use crate::mission::schema::{Landing, StageSpec};
use crate::mission::types::{Group, Stage};
use crate::world::{Voxel, VoxelGrid};
use std::collections::HashMap;

/// Checks every stage against the groups, in file order.
pub(super) fn check_stages(
    specs: &[StageSpec],
    groups: &[Group],
    world: &VoxelGrid,
    bounds: &Bounds,
    report: &mut Report,
) -> Vec<Stage> {
    let mut names: HashMap<&str, usize> = HashMap::new();
    specs
        .iter()
        .enumerate()
        .map(|(si, spec)| {
            let spath = format!("stages[{si}]");
            if spec.name.trim().is_empty() {
                report.add(format!("{spath}.name"), "must not be empty");
            } else if let Some(first) = names.insert(&spec.name, si) {
                report.add(
                    format!("{spath}.name"),
                    format!("stage name {:?} is already used by stages[{first}]", spec.name),
                );
            }
            let hold_s = spec.hold_s.unwrap_or(0.0);
            if !(hold_s.is_finite() && hold_s >= 0.0) {
                report.add(
                    format!("{spath}.hold_s"),
                    format!("{hold_s} s is not a hold time (give seconds, 0 or more)"),
                );
            }
            for name in spec.goals.keys() {
                if !groups.iter().any(|g| &g.name == name) {
                    let known: Vec<&str> = groups.iter().map(|g| g.name.as_str()).collect();
                    report.add(
                        format!("{spath}.goals.{name}"),
                        format!(
                            "no group is named {name:?} (the groups are {})",
                            known.join(", ")
                        ),
                    );
                }
            }
            let mut used: HashMap<Voxel, String> = HashMap::new();
            let goals = groups
                .iter()
                .map(|g| {
                    let raw = spec.goals.get(&g.name)?;
                    let gpath = format!("{spath}.goals.{}", g.name);
                    if raw.is_empty() {
                        report.add(
                            gpath.clone(),
                            format!(
                                "group {:?} has no goals in stage {:?}; give at least one, or leave the group out of the stage (it stays where it is)",
                                g.name, spec.name,
                            ),
                        );
                    }
                    let voxels = raw
                        .iter()
                        .enumerate()
                        .filter_map(|(ki, &r)| {
                            let kpath = format!("{gpath}[{ki}]");
                            let v = free_voxel(world, bounds, &kpath, r, report)?;
                            if let Some(first) = used.insert(v, kpath.clone()) {
                                report.add(
                                    kpath,
                                    format!("goal {v} is already used in this stage by {first}"),
                                );
                            }
                            Some(v)
                        })
                        .collect::<Vec<Voxel>>();
                    for hold in g.spare_holds(voxels.len()) {
                        if voxels.contains(&hold) {
                            report.add(
                                gpath.clone(),
                                format!(
                                    "group {:?} has fewer goals than drones in stage {:?}, so its last drones are spares and hold at their starts, but {hold} is one of the stage's goals",
                                    g.name, spec.name
                                ),
                            );
                        }
                    }
                    Some(voxels)
                })
                .collect();
            Stage {
                name: spec.name.clone(),
                hold_s,
                goals,
            }
        })
        .collect()
}

/// `below_goal` landing descends straight down from the last formation: no two of
/// its targets (per group, its last goals and its spares' holds: wherever a drone
/// may be when landing starts) may share a column, and no obstacle may stand below
/// any of them.
pub(super) fn check_landing(
    landing: Landing,
    final_targets: &[Vec<Voxel>],
    world: &VoxelGrid,
    ground: &GroundCells,
    report: &mut Report,
) {
    if landing != Landing::BelowGoal {
        return;
    }
    let mut columns: HashMap<[i32; 2], Voxel> = HashMap::new();
    for &goal in final_targets.iter().flatten() {
        if let Some(other) = columns.insert([goal.x, goal.y], goal) {
            report.add(
                "landing",
                format!(
                    "below_goal needs every last goal (and every spare's hold) in a column of its own, but {other} and {goal} share column [{}, {}] (use group_pads or own_pad)",
                    goal.x, goal.y
                ),
            );
        }
        if let Some(block) = blocked_below(world, ground, goal) {
            report.add(
                "landing",
                format!(
                    "below_goal needs a free column below every last goal (and every spare's hold), but obstacle {block} is below goal {goal} (use group_pads or own_pad)"
                ),
            );
        }
    }
}
