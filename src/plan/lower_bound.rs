//! A makespan lower bound that ignores collisions between drones.

use super::matching::{matched, maximum_matching};
use super::pair_distances::{PairSearch, Reach};
use super::space::{Marks, NONE, Space};
use crate::mission::Mission;
use crate::world::{Voxel, VoxelGrid};
use std::time::Instant;

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
/// away, each drone matched to its nearer goals where it can. `None` as for the
/// bound, or if a start lies outside `world` or in an obstacle.
pub(crate) fn bottleneck_assignment(
    world: &VoxelGrid,
    starts: &[Voxel],
    goals: &[Voxel],
) -> Option<(u32, Vec<Voxel>)> {
    let space = Space::new(world, 0);
    let compact = |v: Voxel| {
        world
            .cell(v)
            .map(|c| space.compact(c))
            .filter(|&c| c != NONE)
    };
    let starts: Option<Vec<u32>> = starts.iter().map(|&v| compact(v)).collect();
    let goals: Vec<u32> = goals.iter().filter_map(|&g| compact(g)).collect();
    let Bottleneck::Found(steps, assigned) =
        bottleneck_assignment_in(&space, &starts?, (&goals, &space.distances(&goals)), None)
    else {
        return None;
    };
    let voxels = assigned
        .into_iter()
        .map(|c| world.voxel(space.world_cell(c)))
        .collect();
    Some((steps, voxels))
}

/// What a search for the bottleneck assignment came to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Bottleneck {
    /// The bound, and for each drone a distinct goal (compact cells) attaining it.
    Found(u32, Vec<u32>),
    /// No complete assignment exists, or there are no drones.
    Unmatchable,
    /// The time given ran out first.
    OutOfTime,
}

/// [`bottleneck_assignment`] on the compact free cells of `space`: drones at
/// `starts`, free `goals`, the assignment in compact cells, searched until
/// `until` when one is given (at 5,000 drones landing 41 moves from their pads
/// it takes 10 s). `to_goal` is every cell's move count to its nearest goal
/// ([`Space::distances`] from `goals`; a group has it already). The first plan
/// starts from it.
pub(crate) fn bottleneck_assignment_in(
    space: &Space,
    starts: &[u32],
    (goals, to_goal): (&[u32], &[u32]),
    until: Option<Instant>,
) -> Bottleneck {
    match bottleneck_search(space, starts, (goals, to_goal), until, PAIRWISE_DRONES) {
        Ok(Some((bound, assigned))) => Bottleneck::Found(bound, assigned),
        Ok(None) => Bottleneck::Unmatchable,
        Err(OutOfTime) => Bottleneck::OutOfTime,
    }
}

/// `until` passed during a search.
struct OutOfTime;

/// See [`bottleneck_assignment_in`]; groups of up to `pairwise_drones` drones
/// are searched pair by pair.
fn bottleneck_search(
    space: &Space,
    starts: &[u32],
    (goals, to_goal): (&[u32], &[u32]),
    until: Option<Instant>,
    pairwise_drones: usize,
) -> Result<Option<(u32, Vec<u32>)>, OutOfTime> {
    let late = || until.is_some_and(|u| Instant::now() >= u);
    if starts.is_empty() {
        return Ok(None);
    }
    let floor = starts
        .iter()
        .map(|&s| to_goal[s as usize])
        .try_fold(0, |acc, d| (d != NONE).then_some(acc.max(d)));
    let Some(floor) = floor else {
        return Ok(None);
    };
    // A few drones are found sooner by A* to each than by a ball from each goal
    // that must reach the farthest of them (see `pair_distances`).
    let mut pairs = (starts.len() <= pairwise_drones).then(|| PairSearch::new(space.len()));
    let mut balls = None;
    let mut radius = floor + 2;
    loop {
        // near[goal]: (drone, distance) for every drone within `radius` of it.
        let mut near = Vec::with_capacity(goals.len());
        let mut cut_short = false;
        for (i, &g) in goals.iter().enumerate() {
            if i % 64 == 0 && late() {
                return Err(OutOfTime);
            }
            let by_pairs = pairs
                .as_mut()
                .and_then(|pairs| pairs_within(pairs, space, g, starts, radius));
            let (found, truncated) = match by_pairs {
                Some(found) => found,
                None => {
                    // Walls: A* to each drone costs more than one ball from here on.
                    pairs = None;
                    let balls = balls.get_or_insert_with(|| Balls::new(space, starts));
                    balls.search(space, g, radius)
                }
            };
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
        let timed_out = std::cell::Cell::new(false);
        let perfect_within = |t: u32| {
            // Past the time every threshold reads as enough, ending the search.
            timed_out.set(timed_out.get() || late());
            timed_out.get()
                || maximum_matching(&adjacency_within(t, false), goals.len()) == starts.len()
        };
        // Smallest threshold with a perfect matching (matchability is monotone in t).
        let index = thresholds.partition_point(|&t| !perfect_within(t));
        if timed_out.get() {
            return Err(OutOfTime);
        }
        if let Some(&t) = thresholds.get(index) {
            let assigned: Option<Vec<u32>> = matched(&adjacency_within(t, true), goals.len())
                .into_iter()
                .map(|g| g.map(|g| goals[g]))
                .collect();
            return Ok(assigned.map(|a| (t, a)));
        }
        if !cut_short {
            return Ok(None); // every goal's whole component was searched
        }
        radius = radius.saturating_mul(2);
    }
}

/// Drones per group up to which the bound searches each drone-goal pair by A*
/// rather than a ball around each goal: at 20 drones a group the balls cover
/// the world, at 500 in one group a ball finds them all sooner.
const PAIRWISE_DRONES: usize = 64;

/// [`Balls::search`] by one A* search per drone: the drones (index into
/// `starts`) within `radius` moves of `goal`, with their distances, and whether
/// any drone may lie beyond the radius. `None` once the searches have expanded
/// more cells than the world has: walls make A* widen, and one ball would cost
/// less.
fn pairs_within(
    pairs: &mut PairSearch,
    space: &Space,
    goal: u32,
    starts: &[u32],
    radius: u32,
) -> Option<(Vec<(u32, u32)>, bool)> {
    let budget = pairs.expanded() + space.len();
    let mut found = Vec::new();
    let mut beyond = false;
    for (d, &s) in starts.iter().enumerate() {
        match pairs.moves_between(space, goal, s, radius) {
            Reach::Moves(m) => found.push((d as u32, m)),
            Reach::Beyond => beyond = true,
            Reach::Never => {}
        }
        if pairs.expanded() > budget {
            return None;
        }
    }
    Some((found, beyond))
}

/// Breadth-first searches bounded by a radius for one group's drones, sharing
/// scratch space ([`Marks`]): each visits only its ball, and starting the next
/// costs nothing. The queue is walked layer by layer, so a cell's distance is
/// its layer's and is never stored.
struct Balls {
    /// Per cell, the drone (index into the starts) there, or [`NONE`].
    drone_at: Vec<u32>,
    drones: usize,
    seen: Marks,
    queue: Vec<u32>,
}

impl Balls {
    fn new(space: &Space, starts: &[u32]) -> Self {
        let mut drone_at = vec![NONE; space.len()];
        for (d, &s) in starts.iter().enumerate() {
            drone_at[s as usize] = d as u32;
        }
        Self {
            drone_at,
            drones: starts.len(),
            seen: Marks::new(space.len()),
            queue: Vec::new(),
        }
    }

    /// The drones within `radius` moves of `from`, with their distances, and
    /// whether cells lay beyond the radius. Stops once every drone is found:
    /// farther cells add nothing.
    fn search(&mut self, space: &Space, from: u32, radius: u32) -> (Vec<(u32, u32)>, bool) {
        self.seen.next_search();
        let mut found = Vec::new();
        self.queue.clear();
        self.queue.push(from);
        self.seen.mark(from);
        let (mut layer_start, mut distance) = (0, 0);
        while layer_start < self.queue.len() {
            let layer_end = self.queue.len();
            for &c in &self.queue[layer_start..layer_end] {
                let drone = self.drone_at[c as usize];
                if drone != NONE {
                    found.push((drone, distance));
                    if found.len() == self.drones {
                        return (found, false);
                    }
                }
            }
            let last = distance == radius;
            for i in layer_start..layer_end {
                let c = self.queue[i];
                for &n in &space.moves(c)[1..] {
                    if !self.seen.is_marked(n) {
                        if last {
                            return (found, true); // a cell beyond the radius
                        }
                        self.seen.mark(n);
                        self.queue.push(n);
                    }
                }
            }
            (layer_start, distance) = (layer_end, distance + 1);
        }
        (found, false) // the whole piece of the world searched
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::network::GroupCells;
    use crate::world::UNREACHABLE;
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
            let bottleneck = group_lower_bound(&world, starts, goals);
            prop_assert_eq!(bottleneck, bottleneck_by_definition(&world, starts, goals));
            // Balls alone, and pairs alone where their budget allows, agree.
            let space = Space::new(&world, 0);
            let compact = |v: &Voxel| space.compact(world.cell(*v).unwrap_or(0));
            let (cs, cg): (Vec<u32>, Vec<u32>) =
                (starts.iter().map(compact).collect(), goals.iter().map(compact).collect());
            let to_goal = space.distances(&cg);
            for pairwise_drones in [0, usize::MAX] {
                let found = bottleneck_search(&space, &cs, (&cg, &to_goal), None, pairwise_drones);
                let value = found.ok().flatten().map(|(t, _)| t);
                prop_assert_eq!(value, bottleneck, "pairwise up to {} drones", pairwise_drones);
            }
            // The nearest-goal bound a hurried leg falls back on is a bound too:
            // never above the bottleneck.
            let space = Space::new(&world, 0);
            let compact = |v: &Voxel| space.compact(world.cell(*v).unwrap_or(0));
            let cells = GroupCells::new(
                &space,
                starts.iter().map(compact).collect(),
                &goals.iter().map(compact).collect::<Vec<u32>>(),
            );
            if let Some(b) = bottleneck {
                let nearest = cells.nearest_bound();
                prop_assert!(nearest.is_some_and(|n| n <= b), "{:?} above {}", nearest, b);
            }
        }
    }

    #[test]
    fn a_search_out_of_time_says_so() {
        let world = VoxelGrid::new([6, 1, 1], 1.0, [0.0; 3]);
        let space = Space::new(&world, 0);
        let cell = |x| space.compact(world.cell(Voxel::new(x, 0, 0)).unwrap_or(0));
        let (starts, goals) = ([cell(0), cell(1)], [cell(4), cell(5)]);
        let goals = (&goals[..], &space.distances(&goals)[..]);
        assert_eq!(
            bottleneck_assignment_in(&space, &starts, goals, None),
            Bottleneck::Found(4, vec![goals.0[0], goals.0[1]])
        );
        let now = Some(Instant::now());
        assert_eq!(
            bottleneck_assignment_in(&space, &starts, goals, now),
            Bottleneck::OutOfTime
        );
    }
}
