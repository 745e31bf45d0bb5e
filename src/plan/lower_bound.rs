//! A makespan lower bound that ignores collisions between drones.

use super::matching::maximum_matching;
use crate::mission::Mission;
use crate::world::{UNREACHABLE, Voxel, VoxelGrid};

/// The least makespan the first formation (starts to goals, in the mission's world,
/// without pads) can have, in steps: what the TAPF core is measured against.
///
/// Per group, the bottleneck assignment: the smallest `T` such that every drone can be
/// given a distinct goal at most `T` moves away (BFS distance, other drones ignored).
/// Any valid plan is such an assignment, so the bound never exceeds the optimum.
/// Returns `None` when some group has no complete assignment at all, or no starts.
///
/// ```
/// use swarmctl::{mission, plan};
/// let m = mission::from_yaml("
/// name: lb
/// world: { dimensions: [5, 1, 1], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 1.5] }
/// limits: { max_speed_mps: 1.0, max_accel_mps2: 1.0, safety_distance_m: 0.2 }
/// groups:
///   - { name: g, drones: [{ id: a, start: [0, 0, 0] }, { id: b, start: [1, 0, 0] }],
///       goals: [[3, 0, 0], [4, 0, 0]] }
/// ", "lb.yaml".as_ref()).unwrap();
/// assert_eq!(plan::makespan_lower_bound(&m), Some(3));
/// ```
pub fn makespan_lower_bound(mission: &Mission) -> Option<u32> {
    mission.groups.iter().try_fold(0, |acc, g| {
        let starts: Option<Vec<Voxel>> = g.drones.iter().map(|d| d.start).collect();
        group_lower_bound(&mission.world, &starts?, &g.goals).map(|lb| acc.max(lb))
    })
}

/// The bottleneck assignment value of drones at `starts` onto `goals` in `world`
/// (see [`makespan_lower_bound`]).
pub fn group_lower_bound(world: &VoxelGrid, starts: &[Voxel], goals: &[Voxel]) -> Option<u32> {
    let starts: Vec<usize> = starts.iter().filter_map(|&v| world.cell(v)).collect();
    // distance[goal][drone]: one BFS per goal.
    let distance: Vec<Vec<u32>> = goals
        .iter()
        .filter_map(|&g| world.cell(g))
        .map(|g| {
            let from_goal = world.distances_from(g);
            starts.iter().map(|&s| from_goal[s]).collect()
        })
        .collect();
    let mut thresholds: Vec<u32> = distance
        .iter()
        .flatten()
        .copied()
        .filter(|&d| d != UNREACHABLE)
        .collect();
    thresholds.sort_unstable();
    thresholds.dedup();
    let perfect_within = |t: u32| {
        let adjacency: Vec<Vec<usize>> = (0..starts.len())
            .map(|d| {
                (0..distance.len())
                    .filter(|&g| distance[g][d] <= t)
                    .collect()
            })
            .collect();
        maximum_matching(&adjacency, distance.len()) == starts.len()
    };
    // Smallest threshold with a perfect matching (matchability is monotone in t).
    let index = thresholds.partition_point(|&t| !perfect_within(t));
    thresholds.get(index).copied()
}
