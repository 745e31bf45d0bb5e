//! Distances to one goal at a time, for drones that each head for their own.

use crate::plan::space::Space;
use std::collections::VecDeque;

/// No way to the goal.
pub(crate) const FAR: u16 = u16::MAX;

/// One breadth-first table per goal cell, made the first time the goal is asked
/// about and kept: drones trade goals within their group as they go, so any goal
/// of the group may be asked about from anywhere along the way.
///
/// Two bytes a cell and goal: 40×40×10 with 1,000 goals is 32 MB. Callers bound
/// `goals × cells` with [`GoalDistances::bytes_for`] before they start.
pub(crate) struct GoalDistances<'a> {
    space: &'a Space,
    /// Per cell: the index of its table in `tables`, or `u32::MAX` if not made yet.
    table_of: Vec<u32>,
    tables: Vec<Box<[u16]>>,
    queue: VecDeque<u32>,
}

impl<'a> GoalDistances<'a> {
    pub(crate) fn new(space: &'a Space) -> Self {
        Self {
            space,
            table_of: vec![u32::MAX; space.len()],
            tables: Vec::new(),
            queue: VecDeque::new(),
        }
    }

    /// What tables for `goals` distinct goals take in `space`, bytes.
    pub(crate) fn bytes_for(space: &Space, goals: usize) -> usize {
        goals.saturating_mul(space.len()).saturating_mul(2)
    }

    /// Moves from `cell` to `goal` (other drones ignored), [`FAR`] if walled off.
    #[inline]
    pub(crate) fn get(&mut self, goal: u32, cell: u32) -> u16 {
        self.table(goal)[cell as usize]
    }

    /// The whole table of `goal`.
    pub(crate) fn table(&mut self, goal: u32) -> &[u16] {
        let mut index = self.table_of[goal as usize];
        if index == u32::MAX {
            index = self.tables.len() as u32;
            let table = self.search(goal);
            self.tables.push(table);
            self.table_of[goal as usize] = index;
        }
        &self.tables[index as usize]
    }

    fn search(&mut self, goal: u32) -> Box<[u16]> {
        let mut dist = vec![FAR; self.space.len()].into_boxed_slice();
        dist[goal as usize] = 0;
        self.queue.clear();
        self.queue.push_back(goal);
        while let Some(c) = self.queue.pop_front() {
            let next = dist[c as usize].saturating_add(1).min(FAR - 1);
            for &m in &self.space.moves(c)[1..] {
                if dist[m as usize] == FAR {
                    dist[m as usize] = next;
                    self.queue.push_back(m);
                }
            }
        }
        dist
    }
}
