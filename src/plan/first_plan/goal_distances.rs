//! Distances to one goal at a time, searched only as far as they are asked for.

use crate::plan::space::Space;
use std::collections::{HashMap, VecDeque};
use std::hash::{BuildHasherDefault, Hasher};

/// No way to the goal.
pub(crate) const FAR: u16 = u16::MAX;

/// Cells known, summed over goals, past which the tables give up (about 2 GB):
/// the first plan then declines and the exact search plans alone.
const MAX_ENTRIES: usize = 200_000_000;

/// One breadth-first search per goal, run lazily: a question about a cell the
/// search has not reached resumes it until it has (LaCAM's lazy distance table).
/// A drone's questions are about the cells around it, which lie about as far from
/// its goal as it is, so each goal's search covers the ball out to its drone, not
/// the world: 5,000 goals in a 100×100×20 world would need 2 GB as whole tables.
/// Drones trade goals within their group as they go, so a search may be resumed
/// from another drone's side.
pub(crate) struct GoalDistances<'a> {
    space: &'a Space,
    /// Per cell: the index of its goal's search in `searches`, if begun.
    search_of: Vec<u32>,
    searches: Vec<Search>,
    /// Cells known, over every search.
    entries: usize,
    /// Searches kept in dense tables, and the cells they may cover together
    /// (see [`DENSE_CELLS`]).
    dense: usize,
    dense_cells: usize,
}

/// Cells, summed over the goals searched in dense tables, up to which a goal's
/// distances are kept in an array over the whole space rather than a hash map
/// (64 MB): every goal of 1,000 drones on 40×40×10, where looking distances up
/// in hash maps was a sixth of a first plan's time; at 100×100×20 about the
/// first 170.
const DENSE_CELLS: usize = 32 << 20;

/// One goal's breadth-first search, paused: every cell found has its exact
/// distance; `frontier` holds the found cells not yet expanded, nearest first.
struct Search {
    distance: Known,
    frontier: VecDeque<(u32, u16)>,
}

/// The distances one search has found.
enum Known {
    /// Per cell of the space, its distance, [`FAR`] where not found (yet).
    Dense(Vec<u16>),
    /// Only the cells found: a search of a big world that stops near its goal.
    Sparse(HashMap<u32, u16, CellHash>),
}

impl Known {
    fn get(&self, cell: u32) -> Option<u16> {
        match self {
            Self::Dense(d) => Some(d[cell as usize]).filter(|&d| d != FAR),
            Self::Sparse(d) => d.get(&cell).copied(),
        }
    }

    /// Records `cell` at `distance` unless it is known already; whether it was new.
    fn insert_new(&mut self, cell: u32, distance: u16) -> bool {
        match self {
            Self::Dense(d) if d[cell as usize] == FAR => {
                d[cell as usize] = distance;
                true
            }
            Self::Dense(_) => false,
            Self::Sparse(d) => match d.entry(cell) {
                std::collections::hash_map::Entry::Vacant(e) => {
                    e.insert(distance);
                    true
                }
                std::collections::hash_map::Entry::Occupied(_) => false,
            },
        }
    }
}

impl<'a> GoalDistances<'a> {
    pub(crate) fn new(space: &'a Space) -> Self {
        Self {
            space,
            search_of: vec![u32::MAX; space.len()],
            searches: Vec::new(),
            entries: 0,
            dense: 0,
            dense_cells: DENSE_CELLS,
        }
    }

    /// Every search in a hash map, as in a world too big for dense tables.
    #[cfg(test)]
    fn sparse(space: &'a Space) -> Self {
        Self {
            dense_cells: 0,
            ..Self::new(space)
        }
    }

    /// Whether the searches have grown past their budget (see [`MAX_ENTRIES`]).
    pub(crate) fn exhausted(&self) -> bool {
        self.entries > MAX_ENTRIES
    }

    /// Moves from `cell` to `goal` (other drones ignored), [`FAR`] if walled off.
    pub(crate) fn get(&mut self, goal: u32, cell: u32) -> u16 {
        let mut index = self.search_of[goal as usize];
        if index == u32::MAX {
            index = self.searches.len() as u32;
            let cells = self.space.len();
            let mut distance = if (self.dense + 1).saturating_mul(cells) <= self.dense_cells {
                self.dense += 1;
                Known::Dense(vec![FAR; cells])
            } else {
                Known::Sparse(HashMap::default())
            };
            distance.insert_new(goal, 0);
            self.searches.push(Search {
                distance,
                frontier: VecDeque::from([(goal, 0)]),
            });
            self.search_of[goal as usize] = index;
            self.entries += 1;
        }
        let search = &mut self.searches[index as usize];
        if let Some(d) = search.distance.get(cell) {
            return d;
        }
        let mut found = FAR;
        while found == FAR {
            let Some((c, d)) = search.frontier.pop_front() else {
                break;
            };
            let next = d.saturating_add(1).min(FAR - 1);
            for &m in &self.space.moves(c)[1..] {
                if search.distance.insert_new(m, next) {
                    search.frontier.push_back((m, next));
                    self.entries += 1;
                    if m == cell {
                        found = next;
                    }
                }
            }
        }
        found
    }
}

/// A multiply-and-rotate hash (FxHash's) for cell indices: the standard
/// library's SipHash would cost more than the searches themselves.
type CellHash = BuildHasherDefault<CellHasher>;

#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u32(&mut self, n: u32) {
        self.write_u64(u64::from(n));
    }

    fn write_u64(&mut self, n: u64) {
        self.0 = (self.0.rotate_left(5) ^ n).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::{Voxel, VoxelGrid};

    /// Asked in any order, the lazy searches give exactly the whole-world
    /// breadth-first distances, walls and walled-off pockets included.
    #[test]
    fn lazy_distances_equal_whole_searches() {
        let mut world = VoxelGrid::new([7, 5, 3], 1.0, [0.0; 3]);
        for (i, v) in (0..7)
            .flat_map(|x| (0..5).map(move |y| Voxel::new(x, y, 1)))
            .enumerate()
        {
            if i % 3 != 0 {
                world.block(v);
            }
        }
        world.block(Voxel::new(6, 4, 2));
        let space = Space::new(&world, 3);
        for mut lazy in [GoalDistances::new(&space), GoalDistances::sparse(&space)] {
            check_against_whole_searches(&space, &mut lazy);
        }
    }

    fn check_against_whole_searches(space: &Space, lazy: &mut GoalDistances<'_>) {
        for goal in [0u32, 17, space.len() as u32 - 1] {
            let whole = space.distances(&[goal]);
            // Far cells first, then near ones: resumed and already-known answers.
            for cell in (0..space.len() as u32).rev().chain(0..space.len() as u32) {
                let expected = match whole[cell as usize] {
                    crate::plan::space::NONE => FAR,
                    d => d as u16,
                };
                assert_eq!(lazy.get(goal, cell), expected, "goal {goal} cell {cell}");
            }
        }
        assert!(!lazy.exhausted());
    }
}
