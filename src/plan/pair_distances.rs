//! Exact move counts between one cell and another, by A* under the Manhattan
//! distance: what the bottleneck bound needs for a group of a few drones.
//!
//! The bound asks, for every goal of a group, how far each of its drones is. A
//! breadth-first ball from the goal answers for all of them at once, but a
//! group of 20 drones spread over the world makes every ball the whole world
//! (14,400 cells each at 1,000 drones in 50 groups on 40×40×10: a third of a
//! first plan's time). A* from the goal to one drone expands little more than
//! the cells along a shortest way where obstacles leave straight ways, so 20
//! searches per goal cost a fraction of one ball. Behind walls A* widens
//! towards a ball itself; the bound then goes back to balls (see
//! `lower_bound`), so a maze costs no more than before.

use super::space::{Marks, Space};

/// What a capped search found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Reach {
    /// The least number of moves.
    Moves(u32),
    /// More moves than the cap (or maybe no way at all beyond it).
    Beyond,
    /// No way: the search ran out of cells within the cap.
    Never,
}

/// A* searches sharing scratch space ([`Marks`]), the open set is a bucket queue over the
/// integer estimate `f = g + h` (last in, first out within a bucket, so ties go
/// deepest first and a straight way is followed without widening).
pub(super) struct PairSearch {
    /// The cells this search has reached, and their moves then.
    seen: Marks,
    moves: Vec<u32>,
    /// Open cells with their moves, by `f` less the start's estimate.
    buckets: Vec<Vec<(u32, u32)>>,
    /// Cells expanded, over every search: what the searches cost.
    expanded: usize,
}

impl PairSearch {
    pub(super) fn new(cells: usize) -> Self {
        Self {
            seen: Marks::new(cells),
            moves: vec![0; cells],
            buckets: Vec::new(),
            expanded: 0,
        }
    }

    /// Cells expanded so far, over every search.
    pub(super) fn expanded(&self) -> usize {
        self.expanded
    }

    /// The moves from `from` to `to` in `space` (other drones ignored), if at
    /// most `cap`.
    pub(super) fn moves_between(&mut self, space: &Space, from: u32, to: u32, cap: u32) -> Reach {
        let floor = space.manhattan(from, to);
        if floor > cap {
            return Reach::Beyond;
        }
        self.seen.next_search();
        let levels = (cap - floor) as usize + 1;
        if self.buckets.len() < levels {
            self.buckets.resize_with(levels, Vec::new);
        }
        self.seen.mark(from);
        self.moves[from as usize] = 0;
        self.buckets[0].push((from, 0));
        let mut beyond = false;
        let mut answer = None;
        'levels: for level in 0..levels {
            while let Some((c, g)) = self.buckets[level].pop() {
                if g > self.moves[c as usize] {
                    continue; // reached by fewer moves since
                }
                if c == to {
                    answer = Some(g);
                    break 'levels;
                }
                self.expanded += 1;
                for &n in &space.moves(c)[1..] {
                    let g_next = g + 1;
                    if self.seen.is_marked(n) && self.moves[n as usize] <= g_next {
                        continue;
                    }
                    self.seen.mark(n);
                    self.moves[n as usize] = g_next;
                    // A consistent estimate: f never falls along a move.
                    let f = g_next + space.manhattan(n, to);
                    if f > cap {
                        beyond = true;
                    } else {
                        self.buckets[(f - floor) as usize].push((n, g_next));
                    }
                }
            }
        }
        for bucket in &mut self.buckets[..levels] {
            bucket.clear();
        }
        match answer {
            Some(g) => Reach::Moves(g),
            None if beyond => Reach::Beyond,
            None => Reach::Never,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::space::NONE;
    use crate::world::{Voxel, VoxelGrid};
    use proptest::prelude::*;

    proptest! {
        /// Equal to breadth-first distances wherever they are within the cap;
        /// beyond it, or walled off, said so.
        #[test]
        fn equals_breadth_first_search(
            blocked in proptest::collection::vec(any::<bool>(), 7 * 6 * 3),
            pairs in proptest::collection::vec((0usize..126, 0usize..126), 1..12),
            cap in 0u32..20,
        ) {
            let mut grid = VoxelGrid::new([7, 6, 3], 1.0, [0.0; 3]);
            let voxel = |i: usize| Voxel::new((i % 7) as i32, ((i / 7) % 6) as i32, (i / 42) as i32);
            for (i, &b) in blocked.iter().enumerate() {
                if b && i % 2 == 0 {
                    grid.block(voxel(i));
                }
            }
            let space = Space::new(&grid, 1);
            let mut search = PairSearch::new(space.len());
            for (a, b) in pairs {
                let (Some(a), Some(b)) = (grid.cell(voxel(a)), grid.cell(voxel(b))) else {
                    continue;
                };
                let (a, b) = (space.compact(a), space.compact(b));
                if a == NONE || b == NONE {
                    continue;
                }
                let bfs = space.distances(&[a])[b as usize];
                let expected = match bfs {
                    NONE => None,
                    d if d <= cap => Some(Reach::Moves(d)),
                    _ => Some(Reach::Beyond),
                };
                let got = search.moves_between(&space, a, b, cap);
                match expected {
                    Some(e) => prop_assert_eq!(got, e),
                    // Walled off: never reached, whichever way the cap reads it.
                    None => prop_assert!(matches!(got, Reach::Beyond | Reach::Never)),
                }
            }
        }
    }
}
