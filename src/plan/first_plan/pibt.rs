//! One step of Priority Inheritance with Backtracking (Okumura et al., AIJ 2022),
//! under the moves a swarm can fly.
//!
//! In priority order each undecided drone takes the free cell nearest its goal;
//! when that cell holds a drone that has not moved yet, the cell's drone decides
//! first (it inherits the priority) and, if it finds nowhere to go, the first
//! drone tries its next cell. Beyond plain PIBT, a move is refused when it would
//!
//! - close a cycle of movers, each entering the cell the next one leaves (swaps
//!   and rotations: no schedule can fly them, every drone of the cycle would wait
//!   for the next), or
//! - enter a cell stacked under another drone's (an ellipsoid's vertical reach):
//!   the cells stacked with a target must hold no other drone now and none next.
//!
//! The second rule is stricter than the model (a drone may follow another
//! vertically once it has left), which only costs a first plan a little time.
//! Together the rules keep every step one the validator accepts: no two drones in
//! a cell or in stacked cells, no swaps, no rotations, no stacked cycles.

use crate::plan::space::{NONE, Space};

/// Up to the wait and six neighbours, nearest to the goal first.
type Candidates = ([u32; 8], usize);

/// How far a drone's goal is from a cell: `distance(drone, cell)`.
pub(super) type Distance<'d> = &'d mut dyn FnMut(u32, u32) -> u16;

/// A drone's tie-break between equally good cells: `tie(drone, cell)`.
pub(super) type Tie<'t> = &'t dyn Fn(u32, u32) -> u32;

/// Scratch for stepping one configuration to the next.
pub(super) struct Pibt<'a> {
    space: &'a Space,
    /// Per cell: the drone in it now.
    occupied_now: Vec<u32>,
    /// Per cell: the drone that takes it next.
    occupied_next: Vec<u32>,
    /// Per drone: its cell next, [`NONE`] while undecided.
    next: Vec<u32>,
    /// Explicit recursion: (drone, its candidates, the next one to try).
    stack: Vec<(u32, Candidates, usize)>,
}

impl<'a> Pibt<'a> {
    pub(super) fn new(space: &'a Space, drones: usize) -> Self {
        Self {
            space,
            occupied_now: vec![NONE; space.len()],
            occupied_next: vec![NONE; space.len()],
            next: vec![NONE; drones],
            stack: Vec::new(),
        }
    }

    /// Moves every drone one step from `at`, the highest priority first (`order`);
    /// `distance(drone, cell)` ranks its cells (nearest first, then `tie(drone,
    /// cell)`). Returns the next configuration.
    pub(super) fn step(
        &mut self,
        at: &[u32],
        order: &[u32],
        distance: Distance,
        tie: Tie,
    ) -> Vec<u32> {
        for (d, &c) in at.iter().enumerate() {
            self.occupied_now[c as usize] = d as u32;
        }
        self.next.fill(NONE);
        for &d in order {
            if self.next[d as usize] == NONE {
                self.decide(d, at, distance, tie);
            }
        }
        let next = self.next.clone();
        for (&c, &n) in at.iter().zip(&next) {
            self.occupied_now[c as usize] = NONE;
            self.occupied_next[n as usize] = NONE;
        }
        next
    }

    /// PIBT from `root`, iteratively: the chain of inheriting drones can be as long
    /// as the swarm.
    fn decide(&mut self, root: u32, at: &[u32], distance: Distance, tie: Tie) {
        let first = ranked(self.space, &self.occupied_now, at, root, (distance, tie));
        self.stack.push((root, first, 0));
        // What the drone just popped found: Some(true) moved, Some(false) stays.
        let mut child_found: Option<bool> = None;
        while let Some(&(d, (cells, n), tried)) = self.stack.last() {
            if child_found.take() == Some(true) {
                self.stack.pop();
                child_found = Some(true);
                continue;
            }
            let Some(&v) = cells[..n].get(tried) else {
                // Nowhere to go: stay (the caller's claim on this cell passes to it).
                let here = at[d as usize];
                self.next[d as usize] = here;
                self.occupied_next[here as usize] = d;
                self.stack.pop();
                child_found = Some(false);
                continue;
            };
            if let Some(top) = self.stack.last_mut() {
                top.2 += 1;
            }
            if !self.may_take(d, v, at) {
                continue;
            }
            self.next[d as usize] = v;
            self.occupied_next[v as usize] = d;
            let occupant = self.occupied_now[v as usize];
            if occupant != NONE && occupant != d && self.next[occupant as usize] == NONE {
                let its = ranked(
                    self.space,
                    &self.occupied_now,
                    at,
                    occupant,
                    (distance, tie),
                );
                self.stack.push((occupant, its, 0));
                continue;
            }
            self.stack.pop();
            child_found = Some(true);
        }
    }

    /// Whether drone `d`, now at `at[d]`, may take `v` next (see the module's rules).
    fn may_take(&self, d: u32, v: u32, at: &[u32]) -> bool {
        if self.occupied_next[v as usize] != NONE {
            return false;
        }
        let stacked_clear = self.space.stacked(v).iter().all(|&s| {
            let now = self.occupied_now[s as usize];
            self.occupied_next[s as usize] == NONE && (now == NONE || now == d)
        });
        if !stacked_clear {
            return false;
        }
        let occupant = self.occupied_now[v as usize];
        if occupant == NONE || occupant == d || self.next[occupant as usize] == NONE {
            return true;
        }
        // The occupant moves on: follow who waits for whom from it; reaching `d`
        // would close a cycle. The chain is a path (one target per drone, one drone
        // per cell), so it ends within the swarm's size.
        let mut x = occupant;
        for _ in 0..at.len() {
            let ahead = self.occupied_now[self.next[x as usize] as usize];
            if ahead == d {
                return false;
            }
            if ahead == NONE {
                return true;
            }
            let its_next = self.next[ahead as usize];
            if its_next == NONE || its_next == at[ahead as usize] {
                return true;
            }
            x = ahead;
        }
        false
    }
}

/// Drone `d`'s cells for the next step, best first: nearest its goal; among
/// equals, one nobody is in now, so that a drone stepping aside does not push
/// another off its goal; then `tie`.
fn ranked(
    space: &Space,
    occupied_now: &[u32],
    at: &[u32],
    d: u32,
    (distance, tie): (Distance, Tie),
) -> Candidates {
    let moves = space.moves(at[d as usize]);
    let n = moves.len().min(8);
    let mut keyed: [(u16, bool, u32, u32); 8] = [(u16::MAX, true, u32::MAX, NONE); 8];
    for (k, &c) in moves[..n].iter().enumerate() {
        let taken = occupied_now[c as usize];
        keyed[k] = (distance(d, c), taken != NONE && taken != d, tie(d, c), c);
    }
    keyed[..n].sort_unstable();
    let mut cells = [NONE; 8];
    for (k, key) in keyed[..n].iter().enumerate() {
        cells[k] = key.3;
    }
    (cells, n)
}
