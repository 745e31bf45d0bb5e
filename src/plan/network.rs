//! One group's time-expanded flow network, kept implicit.
//!
//! Layer `t` holds every free cell twice, as `in(c, t)` and `out(c, t)`; the unit
//! edge between them is the vertex capacity (one drone per voxel per step). Moves and
//! waits are edges `out(c, t) → in(c', t + 1)`. A source feeds the start cells at
//! step 0 and every goal at the horizon drains into a sink. Since every vertex
//! carries at most one unit, the whole flow fits in two arrays, `next` and `prev`,
//! and the residual graph is enumerated on the fly instead of being stored: the
//! network never has to be built, and growing the horizon appends one layer.

use super::constraints::{ConstraintIndex, Constraints};
use super::space::{NONE, Space};

/// Marks a unit arriving from the source (`prev` at step 0) or leaving to the sink (`next` at the horizon).
pub(crate) const TERMINAL: u32 = NONE - 1;

/// The cells one group starts from and aims for, with distances used to prune layers.
#[derive(Debug, Clone)]
pub(crate) struct GroupCells {
    pub starts: Vec<u32>,
    /// The group's goals, in the order given.
    pub goals: Vec<u32>,
    pub is_goal: Vec<bool>,
    /// Moves from the nearest start: cell `c` is useless before step `from_start[c]`.
    pub from_start: Vec<u32>,
    /// Moves to the nearest goal: cell `c` is useless after step `horizon - to_goal[c]`.
    pub to_goal: Vec<u32>,
}

impl GroupCells {
    pub(crate) fn new(space: &Space, starts: Vec<u32>, goals: &[u32]) -> Self {
        let mut is_goal = vec![false; space.len()];
        for &g in goals {
            is_goal[g as usize] = true;
        }
        Self {
            from_start: space.distances(&starts),
            to_goal: space.distances(goals),
            starts,
            goals: goals.to_vec(),
            is_goal,
        }
    }

    /// Moves from the group's farthest drone to its nearest goal and, where the
    /// group has as many goals as drones, from its farthest goal to its nearest
    /// drone (breadth-first distances, other drones ignored): no plan takes
    /// fewer steps. `None` when some drone reaches no goal (or, goals and drones
    /// as many, some goal no drone).
    pub(crate) fn nearest_bound(&self) -> Option<u32> {
        let drones = self.starts.iter().map(|&s| self.to_goal[s as usize]).max();
        let drones = drones.unwrap_or(0);
        if drones == NONE {
            return None;
        }
        if self.goals.len() != self.starts.len() {
            return Some(drones);
        }
        let goals = self.goals.iter().map(|&g| self.from_start[g as usize]);
        match goals.max().unwrap_or(0) {
            NONE => None,
            goals => Some(drones.max(goals)),
        }
    }
}

#[cfg(test)]
impl GroupCells {
    /// A group from voxels of `grid` (all free), for tests of the solvers.
    pub(crate) fn from_voxels(
        space: &Space,
        grid: &crate::world::VoxelGrid,
        starts: &[crate::world::Voxel],
        goals: &[crate::world::Voxel],
    ) -> Self {
        let compact =
            |v: &crate::world::Voxel| space.compact(grid.cell(*v).expect("a voxel of the grid"));
        let goals: Vec<u32> = goals.iter().map(compact).collect();
        Self::new(space, starts.iter().map(compact).collect(), &goals)
    }

    /// A 2×2 ring full of drones, two groups on alternate corners, each asked to
    /// take the other's corners: only a rotation (or swaps) could do it, so no plan
    /// exists. Shared by the solvers' tests.
    pub(crate) fn full_ring() -> (Space, Vec<GroupCells>) {
        let grid = crate::world::VoxelGrid::new([2, 2, 1], 1.0, [0.0; 3]);
        let space = Space::new(&grid, 0);
        let v = |x, y| crate::world::Voxel::new(x, y, 0);
        let groups = vec![
            Self::from_voxels(&space, &grid, &[v(0, 0), v(1, 1)], &[v(1, 0), v(0, 1)]),
            Self::from_voxels(&space, &grid, &[v(1, 0), v(0, 1)], &[v(1, 1), v(0, 0)]),
        ];
        (space, groups)
    }
}

/// Where the other groups are, so a group can be steered around them (the costs of
/// the min-cost flow) without being forbidden anything.
#[derive(Debug, Clone)]
pub(crate) struct Reservation {
    cells: usize,
    occupied: Vec<u8>,
    /// For an occupied (cell, step): the cell one of its occupants moves to next.
    next: Vec<u32>,
}

impl Reservation {
    pub(crate) fn new(cells: usize, horizon: u32) -> Self {
        let len = cells * (horizon as usize + 1);
        Self {
            cells,
            occupied: vec![0; len],
            next: vec![NONE; len],
        }
    }

    /// Adds a path, padded with waits at its end up to the reservation's horizon.
    /// Cells stacked with the path's within an ellipsoid's vertical reach count as
    /// occupied too: meeting there is a conflict as well.
    pub(crate) fn add_path(&mut self, path: &[u32], space: &Space) {
        let steps = self.occupied.len() / self.cells;
        let last = path.len().saturating_sub(1);
        for t in 0..steps {
            let c = path[t.min(last)];
            let i = t * self.cells + c as usize;
            self.occupied[i] = self.occupied[i].saturating_add(1);
            self.next[i] = path[(t + 1).min(last)];
            for &stacked in space.stacked(c) {
                let j = t * self.cells + stacked as usize;
                self.occupied[j] = self.occupied[j].saturating_add(1);
            }
        }
    }
}

/// A group's flow network at a given horizon, with its current flow.
pub(crate) struct Network<'a> {
    pub space: &'a Space,
    pub group: &'a GroupCells,
    constraints: &'a Constraints,
    index: ConstraintIndex,
    pub horizon: u32,
    cells: usize,
    /// `next[t * cells + c]`: where the unit at (c, t) goes at t + 1, or [`TERMINAL`].
    pub next: Vec<u32>,
    /// `prev[t * cells + c]`: where the unit at (c, t) came from, or [`TERMINAL`].
    pub prev: Vec<u32>,
    pub flow: usize,
    penalty: Option<(&'a Reservation, i64)>,
}

pub(crate) const IN: usize = 0;
pub(crate) const OUT: usize = 1;

/// Residual edges of one node: at most 7 moves, the vertex edge back, and the sink.
pub(crate) type EdgeBuf = [(usize, i64); 9];

impl<'a> Network<'a> {
    pub(crate) fn new(
        space: &'a Space,
        group: &'a GroupCells,
        constraints: &'a Constraints,
        horizon: u32,
    ) -> Self {
        let cells = space.len();
        let len = cells * (horizon as usize + 1);
        Self {
            space,
            group,
            constraints,
            index: ConstraintIndex::new(constraints, cells, horizon),
            horizon,
            cells,
            next: vec![NONE; len],
            prev: vec![NONE; len],
            flow: 0,
            penalty: None,
        }
    }

    /// Makes moves into cells other groups occupy cost `weight` each (min-cost flow only).
    pub(crate) fn set_penalty(&mut self, reservation: &'a Reservation, weight: i64) {
        self.penalty = Some((reservation, weight));
    }

    /// Node count: two per cell and step, one unused slot for the source (which is
    /// implicit: its edges are the open starts), and the sink.
    pub(crate) fn node_count(&self) -> usize {
        2 * self.cells * (self.horizon as usize + 1) + 2
    }

    pub(crate) fn sink(&self) -> usize {
        self.node_count() - 1
    }

    #[inline]
    pub(crate) fn node(&self, c: u32, t: u32, side: usize) -> usize {
        (t as usize * self.cells + c as usize) * 2 + side
    }

    /// Start nodes whose source edge still has capacity.
    pub(crate) fn open_starts(&self) -> impl Iterator<Item = usize> + '_ {
        self.group
            .starts
            .iter()
            .filter(|&&s| self.prev[s as usize] == NONE && self.allowed(s, 0))
            .map(|&s| self.node(s, 0, IN))
    }

    /// Whether (c, t) may carry a drone: not forbidden, and on some start-to-goal route in time.
    #[inline]
    pub(crate) fn allowed(&self, c: u32, t: u32) -> bool {
        let ci = c as usize;
        self.group.from_start[ci] <= t
            && self.group.to_goal[ci].saturating_add(t) <= self.horizon
            && !self.index.vertex_forbidden(c, t)
    }

    /// Cost of moving c → m between t and t + 1: one step unless waiting at a goal of
    /// the group, plus the penalty for meeting another group there.
    #[inline]
    fn move_cost(&self, c: u32, m: u32, t: u32) -> i64 {
        let base = i64::from(!(c == m && self.group.is_goal[c as usize]));
        let Some((reservation, weight)) = self.penalty else {
            return base;
        };
        let at = (t as usize + 1) * self.cells + m as usize;
        let mut meetings = i64::from(reservation.occupied[at]);
        let here = t as usize * self.cells + m as usize;
        if c != m && reservation.occupied[here] > 0 && reservation.next[here] == c {
            meetings += 1; // a swap with another group
        }
        base + weight * meetings
    }

    /// Writes the residual edges leaving `node` (not the source or sink) into `buf`.
    #[inline]
    pub(crate) fn residual_edges(&self, node: usize, buf: &mut EdgeBuf) -> usize {
        let ct = node >> 1;
        let t = (ct / self.cells) as u32;
        let c = (ct % self.cells) as u32;
        if node & 1 == IN {
            return match self.prev[ct] {
                NONE => {
                    buf[0] = (node | OUT, 0);
                    1
                }
                TERMINAL => 0,
                p => {
                    buf[0] = (self.node(p, t - 1, OUT), -self.move_cost(p, c, t - 1));
                    1
                }
            };
        }
        let mut k = 0;
        let next = self.next[ct];
        if t < self.horizon {
            for &m in self.space.moves(c) {
                if m != next && self.allowed(m, t + 1) && !self.index.edge_forbidden(c, m, t) {
                    buf[k] = (self.node(m, t + 1, IN), self.move_cost(c, m, t));
                    k += 1;
                }
            }
        }
        if self.prev[ct] != NONE {
            buf[k] = (node & !1, 0);
            k += 1;
        }
        if t == self.horizon && self.group.is_goal[c as usize] && next != TERMINAL {
            buf[k] = (self.sink(), 0);
            k += 1;
        }
        k
    }

    /// Pushes one unit along `path`, which runs from a start's `in` node to the sink.
    pub(crate) fn augment(&mut self, path: &[usize]) {
        let cells = self.cells;
        let sink = self.sink();
        if let Some(&first) = path.first() {
            self.prev[first >> 1] = TERMINAL;
        }
        for pair in path.windows(2) {
            let (u, v) = (pair[0], pair[1]);
            if v == sink {
                self.next[u >> 1] = TERMINAL;
            } else if u & 1 == OUT && v & 1 == IN && (v >> 1) / cells > (u >> 1) / cells {
                // Forward move.
                self.next[u >> 1] = ((v >> 1) % cells) as u32;
                self.prev[v >> 1] = ((u >> 1) % cells) as u32;
            } else if u & 1 == IN && v & 1 == OUT && (u >> 1) / cells > (v >> 1) / cells {
                // Backward move: cancel the unit that went v → u.
                let (from, to) = (((v >> 1) % cells) as u32, ((u >> 1) % cells) as u32);
                if self.next[v >> 1] == to {
                    self.next[v >> 1] = NONE;
                }
                if self.prev[u >> 1] == from {
                    self.prev[u >> 1] = NONE;
                }
            }
            // Vertex edges, forward or back, need no bookkeeping: a vertex is in use
            // exactly when its `prev` is set.
        }
        self.flow += 1;
    }

    /// Appends one layer; units that drained at the old horizon now wait one step more.
    pub(crate) fn grow(&mut self) {
        let cells = self.cells;
        let old = self.horizon as usize;
        self.horizon += 1;
        self.next.resize(cells * (old + 2), NONE);
        self.prev.resize(cells * (old + 2), NONE);
        for c in 0..cells {
            if self.next[old * cells + c] == TERMINAL {
                self.next[old * cells + c] = c as u32;
                self.prev[(old + 1) * cells + c] = c as u32;
                self.next[(old + 1) * cells + c] = TERMINAL;
            }
        }
        self.index.grow(self.constraints, self.horizon);
    }

    /// Each drone's cell at every step, in start order (valid once the flow is complete).
    pub(crate) fn paths(&self) -> Vec<Vec<u32>> {
        self.group
            .starts
            .iter()
            .map(|&s| {
                let mut path = Vec::with_capacity(self.horizon as usize + 1);
                let mut c = s;
                path.push(c);
                for t in 0..self.horizon as usize {
                    c = self.next[t * self.cells + c as usize];
                    path.push(c);
                }
                path
            })
            .collect()
    }
}
