//! What the high level forbids one group: being somewhere, or moving somewhere, at a step.

use std::collections::HashSet;

/// Constraints on one group, added one per conflict-tree branch.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Constraints {
    /// No drone of the group may be in `cell` at `step`.
    pub vertex: Vec<(u32, u32)>,
    /// No drone of the group may move `from` → `to` between `step` and `step + 1`.
    pub edge: Vec<(u32, u32, u32)>,
}

impl Constraints {
    /// Latest step at which some goal is forbidden. Every goal ends up occupied (a
    /// group has exactly as many goals as drones), so the horizon must exceed it.
    pub(crate) fn latest_goal_step(&self, is_goal: &[bool]) -> Option<u32> {
        self.vertex
            .iter()
            .filter(|&&(c, _)| is_goal[c as usize])
            .map(|&(_, t)| t)
            .max()
    }
}

/// Constraints laid out for constant-time lookups at a fixed horizon.
#[derive(Debug, Clone)]
pub(crate) struct ConstraintIndex {
    cells: usize,
    vertex: Vec<bool>,
    edge: HashSet<(u32, u32, u32)>,
}

impl ConstraintIndex {
    pub(crate) fn new(constraints: &Constraints, cells: usize, horizon: u32) -> Self {
        let mut index = Self {
            cells,
            vertex: Vec::new(),
            edge: constraints.edge.iter().copied().collect(),
        };
        index.grow(constraints, horizon);
        index
    }

    /// Re-lays out the vertex table for a longer horizon.
    pub(crate) fn grow(&mut self, constraints: &Constraints, horizon: u32) {
        self.vertex = vec![false; self.cells * (horizon as usize + 1)];
        for &(c, t) in &constraints.vertex {
            if t <= horizon {
                self.vertex[t as usize * self.cells + c as usize] = true;
            }
        }
    }

    #[inline]
    pub(crate) fn vertex_forbidden(&self, c: u32, t: u32) -> bool {
        self.vertex[t as usize * self.cells + c as usize]
    }

    #[inline]
    pub(crate) fn edge_forbidden(&self, from: u32, to: u32, t: u32) -> bool {
        !self.edge.is_empty() && self.edge.contains(&(from, to, t))
    }
}
