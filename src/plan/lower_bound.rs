//! A makespan lower bound that ignores collisions between drones.

use super::matching::{matched, maximum_matching};
use crate::mission::Mission;
use crate::world::{UNREACHABLE, Voxel, VoxelGrid};
use std::collections::VecDeque;

/// The least makespan the first formation (starts to goals) can have, in steps:
/// what the TAPF core is measured against. Measured where the formation leg is
/// planned: the airspace, or the world's own voxels when the mission keeps
/// formations out of the pad layer.
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
    let world_only;
    let grid = if mission.formations_use_pad_layer {
        &mission.airspace
    } else {
        world_only = mission.airspace.without_pad_layer();
        &world_only
    };
    mission.groups.iter().try_fold(0, |acc, g| {
        let starts: Option<Vec<Voxel>> = g.drones.iter().map(|d| d.start).collect();
        let targets = g.formation_targets(&g.goals);
        group_lower_bound(grid, &starts?, &targets).map(|lb| acc.max(lb))
    })
}

/// The bottleneck assignment value of drones at `starts` onto `goals` in `world`
/// (see [`makespan_lower_bound`]).
///
/// Cheap at drone-show scale: every drone must reach *some* goal, so the farthest
/// drone's nearest goal (one multi-source search) is a floor; distances are then
/// searched from each goal only out to a radius just above it, which a perfect
/// matching within it proves enough, and the radius grows only when none exists.
/// Thousands of goals thus cost thousands of small balls, not thousands of searches
/// of the whole world.
pub fn group_lower_bound(world: &VoxelGrid, starts: &[Voxel], goals: &[Voxel]) -> Option<u32> {
    bottleneck_assignment(world, starts, goals).map(|(steps, _)| steps)
}

/// The bottleneck value of [`group_lower_bound`] with an assignment that attains
/// it: for each drone (in `starts` order) a distinct goal at most that many moves
/// away, each drone matched to its nearer goals where it can. The first plan
/// starts from it; `None` as for the bound, or if a start lies outside `world`.
pub(crate) fn bottleneck_assignment(
    world: &VoxelGrid,
    starts: &[Voxel],
    goals: &[Voxel],
) -> Option<(u32, Vec<Voxel>)> {
    let start_count = starts.len();
    let starts: Vec<usize> = starts.iter().filter_map(|&v| world.cell(v)).collect();
    if starts.len() != start_count {
        return None;
    }
    let goals: Vec<usize> = goals
        .iter()
        .filter_map(|&g| world.cell(g))
        .filter(|&g| world.is_free_cell(g))
        .collect();
    if starts.is_empty() {
        return None;
    }
    let to_goal = world.distances_from_any(&goals);
    let floor = starts
        .iter()
        .map(|&s| to_goal[s])
        .try_fold(0, |acc, d| (d != UNREACHABLE).then_some(acc.max(d)))?;
    let mut drone_at = vec![u32::MAX; world.len()];
    for (d, &s) in starts.iter().enumerate() {
        drone_at[s] = d as u32;
    }
    let mut balls = Balls::new(world.len());
    let mut radius = floor + 2;
    loop {
        // near[goal]: (drone, distance) for every drone within `radius` of it.
        let mut near = Vec::with_capacity(goals.len());
        let mut cut_short = false;
        for &g in &goals {
            let (found, truncated) = balls.search(world, g, radius, &drone_at);
            cut_short |= truncated;
            near.push(found);
        }
        let mut thresholds: Vec<u32> = near.iter().flatten().map(|&(_, d)| d).collect();
        thresholds.sort_unstable();
        thresholds.dedup();
        // Each drone's goals within `t` (nearest first when `nearest_first`).
        let adjacency_within = |t: u32, nearest_first: bool| {
            let mut adjacency: Vec<Vec<(u32, usize)>> = vec![Vec::new(); starts.len()];
            for (g, found) in near.iter().enumerate() {
                for &(d, dist) in found.iter().filter(|&&(_, dist)| dist <= t) {
                    adjacency[d as usize].push((dist, g));
                }
            }
            adjacency
                .into_iter()
                .map(|mut a| {
                    if nearest_first {
                        a.sort_unstable();
                    }
                    a.into_iter().map(|(_, g)| g).collect::<Vec<usize>>()
                })
                .collect::<Vec<_>>()
        };
        let perfect_within =
            |t: u32| maximum_matching(&adjacency_within(t, false), goals.len()) == starts.len();
        // Smallest threshold with a perfect matching (matchability is monotone in t).
        let index = thresholds.partition_point(|&t| !perfect_within(t));
        if let Some(&t) = thresholds.get(index) {
            let assigned: Option<Vec<Voxel>> = matched(&adjacency_within(t, true), goals.len())
                .into_iter()
                .map(|g| g.map(|g| world.voxel(goals[g])))
                .collect();
            return Some((t, assigned?));
        }
        if !cut_short {
            return None; // every goal's whole component was searched
        }
        radius = radius.saturating_mul(2);
    }
}

/// Breadth-first searches bounded by a radius, sharing scratch space: each visits
/// only its ball, and clearing costs the ball, not the world.
struct Balls {
    dist: Vec<u32>,
    touched: Vec<usize>,
    queue: VecDeque<usize>,
}

impl Balls {
    fn new(cells: usize) -> Self {
        Self {
            dist: vec![UNREACHABLE; cells],
            touched: Vec::new(),
            queue: VecDeque::new(),
        }
    }

    /// The drones (`drone_at[cell]`) within `radius` moves of `from`, with their
    /// distances, and whether cells lay beyond the radius.
    fn search(
        &mut self,
        world: &VoxelGrid,
        from: usize,
        radius: u32,
        drone_at: &[u32],
    ) -> (Vec<(u32, u32)>, bool) {
        let mut found = Vec::new();
        let mut truncated = false;
        self.dist[from] = 0;
        self.touched.push(from);
        self.queue.push_back(from);
        while let Some(c) = self.queue.pop_front() {
            let here = self.dist[c];
            if drone_at[c] != u32::MAX {
                found.push((drone_at[c], here));
            }
            for n in world.neighbours(c) {
                if self.dist[n] != UNREACHABLE {
                    continue;
                }
                if here == radius {
                    truncated = true;
                    continue;
                }
                self.dist[n] = here + 1;
                self.touched.push(n);
                self.queue.push_back(n);
            }
        }
        for &c in &self.touched {
            self.dist[c] = UNREACHABLE;
        }
        self.touched.clear();
        (found, truncated)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The definition, searched the slow way: whole-world distances from every goal,
    /// every threshold tried in order.
    fn bottleneck_by_definition(
        world: &VoxelGrid,
        starts: &[Voxel],
        goals: &[Voxel],
    ) -> Option<u32> {
        let distance: Vec<Vec<u32>> = goals
            .iter()
            .map(|&g| {
                let from = world.cell(g).map(|g| world.distances_from(g));
                starts
                    .iter()
                    .map(|&s| match (&from, world.cell(s)) {
                        (Some(f), Some(s)) => f[s],
                        _ => UNREACHABLE,
                    })
                    .collect()
            })
            .collect();
        (0..=world.len() as u32).find(|&t| {
            let adjacency: Vec<Vec<usize>> = (0..starts.len())
                .map(|d| (0..goals.len()).filter(|&g| distance[g][d] <= t).collect())
                .collect();
            maximum_matching(&adjacency, goals.len()) == starts.len()
        })
    }

    proptest! {
        /// The bounded-radius search finds exactly the bottleneck value, on random
        /// worlds with walls, spare goals and unreachable pockets.
        #[test]
        fn equals_the_bottleneck_by_definition(
            blocked in proptest::collection::vec(any::<bool>(), 8 * 6 * 2),
            picks in proptest::collection::vec(0usize..96, 2..20),
            drones in 1usize..8,
        ) {
            let mut world = VoxelGrid::new([8, 6, 2], 1.0, [0.0; 3]);
            let voxel = |i: usize| Voxel::new((i % 8) as i32, (i / 8 % 6) as i32, (i / 48) as i32);
            for (i, &b) in blocked.iter().enumerate() {
                if b && i % 3 == 0 {
                    world.block(voxel(i));
                }
            }
            let mut free: Vec<Voxel> = picks.iter().map(|&i| voxel(i)).collect();
            free.retain(|&v| world.cell(v).is_some_and(|c| world.is_free_cell(c)));
            free.dedup();
            let mut seen = std::collections::HashSet::new();
            free.retain(|v| seen.insert(*v));
            prop_assume!(free.len() > drones);
            let (starts, goals) = free.split_at(drones);
            prop_assert_eq!(
                group_lower_bound(&world, starts, goals),
                bottleneck_by_definition(&world, starts, goals)
            );
        }
    }
}
