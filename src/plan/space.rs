//! The free voxels as a compact graph, shared by every low-level search.

use crate::world::{Cell, VerticalReach, VoxelGrid};
use rand::SeedableRng;
use rand::seq::SliceRandom;
use std::collections::VecDeque;

/// "No cell" in compact indices.
pub(crate) const NONE: u32 = u32::MAX;

/// Free cells numbered densely, each with its moves (itself first: the wait).
///
/// The order of the other moves is shuffled by the seed, so ties between equally good
/// paths break differently for different seeds but identically for the same one.
#[derive(Debug, Clone)]
pub(crate) struct Space {
    world_of: Vec<Cell>,
    compact_of: Vec<u32>,
    offsets: Vec<u32>,
    moves: Vec<u32>,
    /// Per cell, its grid coordinates (voxel indices), for distance estimates.
    points: Vec<[i32; 3]>,
    /// Per cell, the free cells of its column within an ellipsoid's vertical reach
    /// (see [`VerticalReach`]): no two drones may be in related cells at one step.
    /// Empty for a sphere.
    stacked: Vec<Vec<u32>>,
}

impl Space {
    pub(crate) fn new(world: &VoxelGrid, seed: u64) -> Self {
        let world_of: Vec<Cell> = (0..world.len())
            .filter(|&c| world.is_free_cell(c))
            .collect();
        let mut compact_of = vec![NONE; world.len()];
        for (i, &c) in world_of.iter().enumerate() {
            compact_of[c] = i as u32;
        }
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut offsets = Vec::with_capacity(world_of.len() + 1);
        let mut moves = Vec::with_capacity(world_of.len() * 7);
        for (i, &c) in world_of.iter().enumerate() {
            offsets.push(moves.len() as u32);
            moves.push(i as u32);
            let start = moves.len();
            moves.extend(world.neighbours(c).map(|n| compact_of[n]));
            moves[start..].shuffle(&mut rng);
        }
        offsets.push(moves.len() as u32);
        let points = world_of.iter().map(|&c| world.voxel(c).into()).collect();
        Self {
            points,
            world_of,
            compact_of,
            offsets,
            moves,
            stacked: Vec::new(),
        }
    }

    /// [`Space::new`] for drones separated by an ellipsoid of vertical `reach`:
    /// cells of one column within it are related.
    pub(crate) fn with_reach(world: &VoxelGrid, seed: u64, reach: VerticalReach) -> Self {
        let mut space = Self::new(world, seed);
        if reach.is_trivial(world) {
            return space;
        }
        space.stacked = space
            .world_of
            .iter()
            .map(|&c| {
                reach
                    .related_cells(world, world.voxel(c))
                    .into_iter()
                    .filter_map(|v| world.cell(v))
                    .map(|cell| space.compact_of[cell])
                    .filter(|&i| i != NONE)
                    .collect()
            })
            .collect();
        space
    }

    /// Whether any two distinct cells are related by a vertical reach.
    pub(crate) fn has_stacking(&self) -> bool {
        !self.stacked.is_empty()
    }

    /// The cells related to `c` by the vertical reach (not `c` itself).
    pub(crate) fn stacked(&self, c: u32) -> &[u32] {
        self.stacked.get(c as usize).map_or(&[], Vec::as_slice)
    }

    pub(crate) fn len(&self) -> usize {
        self.world_of.len()
    }

    /// Where a drone at `c` can be one step later: `c` itself, then its free neighbours.
    pub(crate) fn moves(&self, c: u32) -> &[u32] {
        let c = c as usize;
        &self.moves[self.offsets[c] as usize..self.offsets[c + 1] as usize]
    }

    pub(crate) fn compact(&self, world_cell: Cell) -> u32 {
        self.compact_of[world_cell]
    }

    /// The grid coordinates of cell `c`.
    pub(crate) fn point(&self, c: u32) -> [i32; 3] {
        self.points[c as usize]
    }

    /// Moves between cells `a` and `b` were there no obstacles: a move changes
    /// one coordinate by one, so never more than the moves around them.
    pub(crate) fn manhattan(&self, a: u32, b: u32) -> u32 {
        let (a, b) = (self.point(a), self.point(b));
        (0..3).map(|k| a[k].abs_diff(b[k])).sum()
    }

    pub(crate) fn world_cell(&self, c: u32) -> Cell {
        self.world_of[c as usize]
    }

    /// Move counts from the nearest of `sources` to every cell.
    pub(crate) fn distances(&self, sources: &[u32]) -> Vec<u32> {
        let mut dist = vec![NONE; self.len()];
        let mut queue = VecDeque::with_capacity(self.len());
        for &s in sources {
            if dist[s as usize] == NONE {
                dist[s as usize] = 0;
                queue.push_back(s);
            }
        }
        while let Some(c) = queue.pop_front() {
            let next = dist[c as usize] + 1;
            for &m in &self.moves(c)[1..] {
                if dist[m as usize] == NONE {
                    dist[m as usize] = next;
                    queue.push_back(m);
                }
            }
        }
        dist
    }
}

/// Per cell, whether the current search has reached it, for searches that run
/// one after another over the same space: a search's cells are marked with its
/// number, so starting the next costs nothing rather than clearing the last.
#[derive(Debug, Clone)]
pub(crate) struct Marks {
    seen: Vec<u32>,
    search: u32,
}

impl Marks {
    pub(crate) fn new(cells: usize) -> Self {
        Self {
            seen: vec![0; cells],
            search: 0,
        }
    }

    /// Forgets every cell: the next search begins.
    pub(crate) fn next_search(&mut self) {
        self.search = self.search.wrapping_add(1);
        if self.search == 0 {
            // After 2³² searches the numbers wrap: clear them all once.
            self.seen.fill(0);
            self.search = 1;
        }
    }

    pub(crate) fn is_marked(&self, c: u32) -> bool {
        self.seen[c as usize] == self.search
    }

    pub(crate) fn mark(&mut self, c: u32) {
        self.seen[c as usize] = self.search;
    }
}
