//! Lazy cuts: cycles of moves found in a model (rotations, and cycles through the
//! vertical reach) forbidden one clause each before the solver runs again.

use super::encoding::{Encoding, negative};
use crate::plan::conflict::stacked_cycle_at;
use crate::plan::rotation::cycles_at;
use batsat::Lit;

impl Encoding<'_> {
    /// Forbids every rotation that mixes groups in `paths` (cycles inside a group
    /// already replaced by waits); returns how many.
    pub(super) fn cut_cycles(&mut self, paths: &[Vec<Vec<u32>>]) -> u64 {
        self.cut(paths, &|at, drones, t, occupant| {
            cycles_at(at, drones, t, occupant)
        })
    }

    /// Forbids, per step, a cycle of moves through the vertical reach in `paths`
    /// (see [`crate::plan::conflict`]); returns how many.
    pub(super) fn cut_stacked_cycles(&mut self, paths: &[Vec<Vec<u32>>]) -> u64 {
        if !self.space.has_stacking() {
            return 0;
        }
        let space = self.space;
        self.cut(paths, &|at, drones, t, occupant| {
            stacked_cycle_at(space, &at, drones, t, occupant)
                .into_iter()
                .collect()
        })
    }

    /// Forbids, with one clause each, the sets of moves that `find` reports at
    /// each step of `paths` (drone indices in cycle order, given where every drone
    /// is and which drone occupies each cell); returns how many.
    fn cut(&mut self, paths: &[Vec<Vec<u32>>], find: &CycleFinder<'_>) -> u64 {
        let drones: Vec<(usize, &Vec<u32>)> = paths
            .iter()
            .enumerate()
            .flat_map(|(g, ps)| ps.iter().map(move |p| (g, p)))
            .collect();
        let at = |d: usize, t: usize| drones[d].1[t];
        let mut occupant = vec![u32::MAX; self.space.len()];
        let mut cuts = Vec::new();
        for t in 0..self.horizon as usize {
            for (d, (_, p)) in drones.iter().enumerate() {
                occupant[p[t] as usize] = d as u32;
            }
            for cycle in find(&at, drones.len(), t, &occupant) {
                let clause: Vec<Lit> = cycle
                    .iter()
                    .filter_map(|&d| {
                        let (g, from, to) = (drones[d].0, at(d, t), at(d, t + 1));
                        self.moves
                            .iter()
                            .find(|m| {
                                m.group == g && m.step == t as u32 && m.from == from && m.to == to
                            })
                            .map(|m| negative(m.var))
                    })
                    .collect();
                cuts.push(clause);
            }
            for (_, p) in &drones {
                occupant[p[t] as usize] = u32::MAX;
            }
        }
        let count = cuts.len() as u64;
        for clause in cuts {
            self.clause(&clause);
        }
        count
    }
}

/// Finds the cycles of moves between `t` and `t + 1`, given each drone's cell at a
/// step (`at(drone, step)`), the drone count and the occupant of every cell at `t`.
type CycleFinder<'f> =
    dyn Fn(&dyn Fn(usize, usize) -> u32, usize, usize, &[u32]) -> Vec<Vec<usize>> + 'f;
