//! The exact second method: one TAPF instance as a SAT problem on the time-expanded
//! network, horizon by horizon from a proven lower bound, the first satisfiable
//! horizon being the optimal makespan.
//!
//! CBM ([`super::cbm`]) is fast where groups rarely meet, but on small, tight
//! instances its conflict tree can explode (hundreds of thousands of nodes) while the
//! whole instance, every group at once, is a few thousand variables. When the tree
//! grows past a node budget the search starts this encoding on a second thread and
//! keeps searching: the first to prove an optimum wins, and the other is stopped
//! (see [`super::cbm::Search::run`]).
//!
//! # The encoding, for a horizon `T`
//!
//! - `x[g][c][t]`: a drone of group `g` is in cell `c` at step `t`, made only where a
//!   start of `g` reaches `c` by `t` and `c` reaches a goal of `g` by `T` (so at `t =
//!   0` only at starts, at `T` only at goals).
//! - `y[g][c→n][t]`: a drone of `g` moves (or waits, `n = c`) from `c` at `t` to `n`
//!   at `t + 1`.
//! - Flow, one drone per unit: every present `x` has exactly one outgoing `y` (before
//!   `T`) and exactly one incoming `y` (after 0); every `y` implies both ends. The
//!   moves between two steps are then a matching, so drones are neither lost nor
//!   duplicated, and at `T` every drone of `g` stands on a goal of `g`.
//! - Vertex conflicts: at most one group per cell and step (and one drone per group,
//!   by the matching).
//! - Swaps: no two drones trade cells along an edge, of any groups.
//! - Rotations (a cycle of drones each entering the cell the next one leaves, which
//!   no vehicle can fly, see [`super::rotation`]): forbidden lazily. A model is
//!   read as paths, cycles inside one group are replaced by waits (the group's
//!   cells are the same either way), and each cycle left gets a clause forbidding
//!   that set of moves; then the solver runs again. Forbidding swaps and cycles
//!   inside a group loses no plan for the same reason.
//!
//! - Under an ellipsoidal separation (cells of one column within its vertical
//!   reach, see [`Space::stacked`]): at most one drone in any two related cells
//!   at a step, of any groups (one group included); cycles through the reach
//!   (each drone entering the reach of the cell the next one leaves) are cut
//!   lazily like rotations.
//!
//! So a horizon is satisfiable exactly when CBM's model has a plan of that makespan:
//! refuting `T₀ … T − 1` and satisfying `T` proves `T` optimal given a lower bound
//! `T₀`. The solver is batsat, a pure-Rust MiniSat.
//!
//! This file holds the horizon loop and the lazy cuts' driver; the clauses are
//! built in `encoding`, and the cycles found in a model are forbidden in `cuts`.

mod cuts;
mod encoding;

use super::conflict::first_conflict;
use super::low_level::GroupRouting;
use super::network::GroupCells;
use super::rotation::remove_cycles;
use super::space::{NONE, Space};
use batsat::{Callbacks, SolverInterface, lbool};
use encoding::{Encoding, Until};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Largest encoding tried, in move variables: above it CBM keeps the instance alone
/// (building it is not interruptible, and takes about a second per million).
pub(crate) const MAX_MOVE_VARS: usize = 1_000_000;

/// How the exact method ended.
#[derive(Debug)]
pub(crate) enum SatOutcome {
    /// An optimal routing: `T`, with one path list per group (each path `T + 1` long).
    Solved {
        makespan: u32,
        routings: Vec<GroupRouting>,
    },
    /// Every horizon up to the cap refuted: the instance has no plan that short.
    NoPlanUpToCap,
    /// The encoding at the next horizon would exceed [`MAX_MOVE_VARS`]; every horizon
    /// below it was refuted (a proven lower bound).
    TooLarge { lower_bound: u32 },
    /// Stopped (the deadline passed, or the conflict tree finished first); every
    /// horizon below `lower_bound` was refuted.
    Stopped { lower_bound: u32 },
}

/// What one run did, for the planner's counters.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SatWork {
    /// Horizons decided (refuted or solved).
    pub horizons: u64,
    /// Rotation cycles forbidden after the fact.
    pub cycle_cuts: u64,
}

/// Decides horizons `from, from + 1, …, max_horizon` in turn until one has a plan,
/// the deadline passes or `stop` is set.
pub(crate) fn solve(
    space: &Space,
    groups: &[GroupCells],
    from: u32,
    max_horizon: u32,
    until: (Instant, &AtomicBool),
    work: &mut SatWork,
) -> SatOutcome {
    let until = Until {
        deadline_at: until.0,
        stop: until.1,
    };
    let mut horizon = from;
    while horizon <= max_horizon {
        if until.stop() {
            return SatOutcome::Stopped {
                lower_bound: horizon,
            };
        }
        if move_vars_at_most(space, groups, horizon) > MAX_MOVE_VARS {
            return SatOutcome::TooLarge {
                lower_bound: horizon,
            };
        }
        match decide(space, groups, horizon, &until, work) {
            Decision::Plan(routings) => {
                return SatOutcome::Solved {
                    makespan: horizon,
                    routings,
                };
            }
            Decision::NoPlan => horizon += 1,
            Decision::Stopped => {
                return SatOutcome::Stopped {
                    lower_bound: horizon,
                };
            }
        }
    }
    SatOutcome::NoPlanUpToCap
}

/// An upper bound on the move variables at `horizon`, from the pruned cells.
fn move_vars_at_most(space: &Space, groups: &[GroupCells], horizon: u32) -> usize {
    let per_step: usize = groups
        .iter()
        .map(|g| {
            (0..space.len() as u32)
                .filter(|&c| {
                    let (s, e) = (g.from_start[c as usize], g.to_goal[c as usize]);
                    s != NONE && e != NONE && s + e <= horizon
                })
                .map(|c| space.moves(c).len())
                .sum::<usize>()
        })
        .sum();
    per_step.saturating_mul(horizon as usize)
}

enum Decision {
    Plan(Vec<GroupRouting>),
    NoPlan,
    Stopped,
}

/// Decides one horizon: a routing, none, or stopped.
fn decide<'a>(
    space: &'a Space,
    groups: &'a [GroupCells],
    horizon: u32,
    until: &Until<'a>,
    work: &mut SatWork,
) -> Decision {
    let Some(mut encoding) = Encoding::new(space, groups, horizon, until) else {
        work.horizons += 1;
        return Decision::NoPlan;
    };
    loop {
        let answer = encoding.solver.solve_limited(&[]);
        if answer == lbool::FALSE {
            work.horizons += 1;
            return Decision::NoPlan;
        }
        if answer != lbool::TRUE {
            return Decision::Stopped;
        }
        let mut paths = encoding.paths();
        for group_paths in &mut paths {
            remove_cycles(group_paths, space.len());
        }
        let cuts = encoding.cut_cycles(&paths) + encoding.cut_stacked_cycles(&paths);
        if cuts > 0 {
            work.cycle_cuts += cuts;
            continue;
        }
        let views: Vec<&[Vec<u32>]> = paths.iter().map(Vec::as_slice).collect();
        if first_conflict(&views, space, horizon).0.is_some() {
            // The encoding forbids every conflict CBM knows; one left is a bug here,
            // and the caller falls back to the conflict tree.
            return Decision::Stopped;
        }
        work.horizons += 1;
        return Decision::Plan(
            paths
                .into_iter()
                .map(|paths| GroupRouting {
                    min_horizon: horizon,
                    paths,
                })
                .collect(),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::{Voxel, VoxelGrid};
    use std::time::Duration;

    /// Two drones trading ends of a corridor with one side pocket: one must duck in.
    /// The optimum is 6 steps; 4 and 5 are refuted.
    #[test]
    fn a_corridor_with_a_pocket_needs_six_steps() {
        let mut grid = VoxelGrid::new([5, 1, 2], 1.0, [0.0; 3]);
        for x in [0, 1, 3, 4] {
            grid.block(Voxel::new(x, 0, 1));
        }
        let space = Space::new(&grid, 0);
        let groups = [
            GroupCells::from_voxels(
                &space,
                &grid,
                &[Voxel::new(0, 0, 0)],
                &[Voxel::new(4, 0, 0)],
            ),
            GroupCells::from_voxels(
                &space,
                &grid,
                &[Voxel::new(4, 0, 0)],
                &[Voxel::new(0, 0, 0)],
            ),
        ];
        let mut work = SatWork::default();
        let deadline = Instant::now() + Duration::from_secs(10);
        let stop = AtomicBool::new(false);
        match solve(&space, &groups, 4, 40, (deadline, &stop), &mut work) {
            SatOutcome::Solved { makespan, routings } => {
                assert_eq!(makespan, 6, "each drone 4 moves plus a duck in and out");
                let views: Vec<&[Vec<u32>]> = routings.iter().map(|r| r.paths.as_slice()).collect();
                assert!(first_conflict(&views, &space, makespan).0.is_none());
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(work.horizons, 3, "4 and 5 refuted, 6 solved");
    }

    /// A stop asked for before the first horizon is obeyed at once.
    #[test]
    fn a_stopped_search_says_how_far_it_got() {
        let grid = VoxelGrid::new([3, 1, 1], 1.0, [0.0; 3]);
        let space = Space::new(&grid, 0);
        let groups = [GroupCells::from_voxels(
            &space,
            &grid,
            &[Voxel::new(0, 0, 0)],
            &[Voxel::new(2, 0, 0)],
        )];
        let stop = AtomicBool::new(true);
        let deadline = Instant::now() + Duration::from_secs(10);
        let outcome = solve(
            &space,
            &groups,
            2,
            10,
            (deadline, &stop),
            &mut SatWork::default(),
        );
        assert!(
            matches!(outcome, SatOutcome::Stopped { lower_bound: 2 }),
            "{outcome:?}"
        );
    }

    /// Four drones of two groups round a 2×2 ring must not rotate.
    #[test]
    fn a_full_ring_cannot_rotate() {
        let (space, groups) = GroupCells::full_ring();
        let mut work = SatWork::default();
        let deadline = Instant::now() + Duration::from_secs(10);
        let stop = AtomicBool::new(false);
        let outcome = solve(&space, &groups, 1, 6, (deadline, &stop), &mut work);
        assert!(matches!(outcome, SatOutcome::NoPlanUpToCap), "{outcome:?}");
        assert!(work.cycle_cuts > 0);
    }
}
