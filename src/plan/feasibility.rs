//! Proving an instance impossible: every arrangement the drones can reach, searched
//! exhaustively while there are few.
//!
//! Any plan of the planner's model can be flown one drone at a time: in one step the
//! movers form chains (each entering the cell the next one leaves) and never cycles
//! (swaps and rotations are conflicts), so moving the front of every chain first
//! reaches the same cells. The arrangements a plan can reach are therefore exactly
//! those reached by moving one drone at a time into a free neighbouring cell — the
//! pebble-motion graph, with drones of one group interchangeable. A breadth-first
//! search of it that runs out of arrangements without one where every drone stands
//! on a goal of its group is a proof that no plan exists at any makespan. It is
//! tried only within a budget of arrangements: impossible instances are small in
//! practice (two drones that cannot pass in a corridor, a ring too full to turn),
//! and large possible ones are left to the search.

use super::network::GroupCells;
use super::space::Space;
use std::collections::{HashSet, VecDeque};

/// What the exhaustive search found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Feasibility {
    /// Some reachable arrangement has every drone on a goal of its group.
    Possible,
    /// None has: the instance has no plan. `arrangements` were reachable.
    Impossible { arrangements: u64 },
    /// The budget ran out first.
    Unknown,
}

/// Searches the arrangements of the drones of `groups` (all of them, or a subset:
/// leaving drones out only makes an instance easier, so a subset proven impossible
/// proves the whole), visiting at most `budget` of them.
pub(crate) fn check(space: &Space, groups: &[&GroupCells], budget: u64) -> Feasibility {
    // An arrangement: each group's cells, sorted, groups one after the other.
    let sizes: Vec<usize> = groups.iter().map(|g| g.starts.len()).collect();
    let mut first = Vec::with_capacity(sizes.iter().sum());
    for g in groups {
        let mut cells = g.starts.clone();
        cells.sort_unstable();
        first.extend(cells);
    }
    let at_goals = |arrangement: &[u32]| {
        let mut offset = 0;
        groups.iter().zip(&sizes).all(|(g, &n)| {
            let all = arrangement[offset..offset + n]
                .iter()
                .all(|&c| g.is_goal[c as usize]);
            offset += n;
            all
        })
    };
    let mut seen: HashSet<Box<[u32]>> = HashSet::new();
    let mut queue: VecDeque<Box<[u32]>> = VecDeque::new();
    let first: Box<[u32]> = first.into_boxed_slice();
    seen.insert(first.clone());
    queue.push_back(first);
    let mut occupied = vec![false; space.len()];
    while let Some(arrangement) = queue.pop_front() {
        if at_goals(&arrangement) {
            return Feasibility::Possible;
        }
        for &c in arrangement.iter() {
            occupied[c as usize] = true;
        }
        let mut offset = 0;
        for &n in &sizes {
            for i in offset..offset + n {
                for &to in &space.moves(arrangement[i])[1..] {
                    if occupied[to as usize] {
                        continue;
                    }
                    let mut next = arrangement.to_vec();
                    next[i] = to;
                    next[offset..offset + n].sort_unstable();
                    let next = next.into_boxed_slice();
                    if !seen.contains(&next) {
                        if seen.len() as u64 >= budget {
                            return Feasibility::Unknown;
                        }
                        seen.insert(next.clone());
                        queue.push_back(next);
                    }
                }
            }
            offset += n;
        }
        for &c in arrangement.iter() {
            occupied[c as usize] = false;
        }
    }
    Feasibility::Impossible {
        arrangements: seen.len() as u64,
    }
}

/// The smallest set of groups found impossible on their own: one group, else a pair,
/// else all of them; `None` unless the whole instance is proven impossible.
pub(crate) fn impossible_groups(
    space: &Space,
    groups: &[GroupCells],
    budget: u64,
) -> Option<(Vec<usize>, u64)> {
    let all: Vec<&GroupCells> = groups.iter().collect();
    let Feasibility::Impossible { arrangements } = check(space, &all, budget) else {
        return None;
    };
    for (a, group) in groups.iter().enumerate() {
        if let Feasibility::Impossible { arrangements } = check(space, &[group], budget) {
            return Some((vec![a], arrangements));
        }
    }
    for a in 0..groups.len() {
        for b in a + 1..groups.len() {
            if let Feasibility::Impossible { arrangements } =
                check(space, &[&groups[a], &groups[b]], budget)
            {
                return Some((vec![a, b], arrangements));
            }
        }
    }
    Some(((0..groups.len()).collect(), arrangements))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::{Voxel, VoxelGrid};

    #[test]
    fn two_drones_cannot_swap_ends_of_a_corridor_without_a_pocket() {
        let grid = VoxelGrid::new([6, 1, 1], 1.0, [0.0; 3]);
        let space = Space::new(&grid, 0);
        let v = |x| Voxel::new(x, 0, 0);
        let groups = [
            GroupCells::from_voxels(&space, &grid, &[v(0)], &[v(5)]),
            GroupCells::from_voxels(&space, &grid, &[v(5)], &[v(0)]),
        ];
        let found = impossible_groups(&space, &groups, 100_000);
        assert_eq!(
            found,
            Some((vec![0, 1], 15)),
            "6 × 5 / 2 ordered pairs in line"
        );
    }

    #[test]
    fn a_pocket_makes_the_corridor_possible() {
        let mut grid = VoxelGrid::new([6, 1, 2], 1.0, [0.0; 3]);
        for x in [0, 1, 3, 4, 5] {
            grid.block(Voxel::new(x, 0, 1));
        }
        let space = Space::new(&grid, 0);
        let v = |x| Voxel::new(x, 0, 0);
        let groups = [
            GroupCells::from_voxels(&space, &grid, &[v(0)], &[v(5)]),
            GroupCells::from_voxels(&space, &grid, &[v(5)], &[v(0)]),
        ];
        let both: Vec<&GroupCells> = groups.iter().collect();
        assert_eq!(check(&space, &both, 100_000), Feasibility::Possible);
    }

    #[test]
    fn a_full_ring_cannot_turn() {
        let (space, groups) = GroupCells::full_ring();
        let found = impossible_groups(&space, &groups, 100_000);
        assert_eq!(found, Some((vec![0, 1], 1)), "no drone can move at all");
    }

    #[test]
    fn the_budget_gives_up_without_a_verdict() {
        let grid = VoxelGrid::new([6, 6, 1], 1.0, [0.0; 3]);
        let space = Space::new(&grid, 0);
        let v = |x, y| Voxel::new(x, y, 0);
        let groups = [
            GroupCells::from_voxels(&space, &grid, &[v(0, 0), v(1, 0)], &[v(5, 5), v(4, 5)]),
            GroupCells::from_voxels(&space, &grid, &[v(5, 5), v(4, 5)], &[v(0, 0), v(1, 0)]),
        ];
        let both: Vec<&GroupCells> = groups.iter().collect();
        assert_eq!(check(&space, &both, 10), Feasibility::Unknown);
    }
}
