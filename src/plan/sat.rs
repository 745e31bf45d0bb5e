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

use super::conflict::{first_conflict, stacked_cycle_at};
use super::low_level::GroupRouting;
use super::network::GroupCells;
use super::rotation::{cycles_at, remove_cycles};
use super::space::{NONE, Space};
use batsat::{Callbacks, Lit, SolverInterface, SolverOpts, Var, lbool};
use std::sync::atomic::{AtomicBool, Ordering};
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

/// Stops the solver at the deadline or when asked to.
struct Until<'s> {
    deadline_at: Instant,
    stop: &'s AtomicBool,
}

impl Callbacks for Until<'_> {
    fn stop(&self) -> bool {
        self.stop.load(Ordering::Relaxed) || Instant::now() >= self.deadline_at
    }
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

/// One move variable: group, step, from, to.
struct Move {
    group: usize,
    step: u32,
    from: u32,
    to: u32,
    var: Var,
}

/// The encoding at one horizon, and the solver holding it.
struct Encoding<'a> {
    space: &'a Space,
    groups: &'a [GroupCells],
    horizon: u32,
    solver: batsat::Solver<Until<'a>>,
    /// `present[g][t][c]`: the `x` variable, or `None` where pruned.
    present: Vec<Vec<Vec<Option<Var>>>>,
    moves: Vec<Move>,
}

fn positive(v: Var) -> Lit {
    Lit::new(v, true)
}

fn negative(v: Var) -> Lit {
    Lit::new(v, false)
}

impl<'a> Encoding<'a> {
    /// The encoding at `horizon`; `None` when a start cannot reach a goal by then.
    fn new(
        space: &'a Space,
        groups: &'a [GroupCells],
        horizon: u32,
        until: &Until<'a>,
    ) -> Option<Self> {
        let until = Until {
            deadline_at: until.deadline_at,
            stop: until.stop,
        };
        let solver = batsat::Solver::new(SolverOpts::default(), until);
        let mut encoding = Self {
            space,
            groups,
            horizon,
            solver,
            present: Vec::with_capacity(groups.len()),
            moves: Vec::new(),
        };
        if !encoding.make_presence() {
            return None;
        }
        encoding.make_moves();
        encoding.forbid_meetings();
        Some(encoding)
    }

    fn clause(&mut self, lits: &[Lit]) {
        let mut clause = lits.to_vec();
        self.solver.add_clause_reuse(&mut clause);
    }

    /// Pairwise at most one: the lists here are short (a cell's moves, or the groups
    /// that may reach one cell), except for many groups in one open space.
    fn at_most_one(&mut self, vars: &[Var]) {
        if vars.len() <= 8 {
            for (i, &a) in vars.iter().enumerate() {
                for &b in &vars[i + 1..] {
                    self.clause(&[negative(a), negative(b)]);
                }
            }
            return;
        }
        // Sequential counter: s_i = "one of the first i is true".
        let mut previous: Option<Var> = None;
        for &v in vars {
            let s = self.solver.new_var_default();
            self.clause(&[negative(v), positive(s)]);
            if let Some(p) = previous {
                self.clause(&[negative(p), positive(s)]);
                self.clause(&[negative(p), negative(v)]);
            }
            previous = Some(s);
        }
    }

    /// The `x` variables, starts fixed; false if some start cannot be placed.
    fn make_presence(&mut self) -> bool {
        let cells = self.space.len();
        for (g, group) in self.groups.iter().enumerate() {
            let mut by_step = Vec::with_capacity(self.horizon as usize + 1);
            for t in 0..=self.horizon {
                let mut row = vec![None; cells];
                for (c, slot) in row.iter_mut().enumerate() {
                    let (s, e) = (group.from_start[c], group.to_goal[c]);
                    if s != NONE && e != NONE && s <= t && e <= self.horizon - t {
                        *slot = Some(self.solver.new_var_default());
                    }
                }
                by_step.push(row);
            }
            self.present.push(by_step);
            for &s in &self.groups[g].starts {
                let Some(v) = self.present[g][0][s as usize] else {
                    return false;
                };
                self.clause(&[positive(v)]);
            }
        }
        // At most one group per cell and step.
        for t in 0..=self.horizon as usize {
            for c in 0..cells {
                let here: Vec<Var> = self.present.iter().filter_map(|g| g[t][c]).collect();
                if here.len() > 1 {
                    self.at_most_one(&here);
                }
            }
        }
        self.forbid_stacking();
        true
    }

    /// At most one drone in any two cells within the vertical reach at a step,
    /// whatever its group (two of one group included).
    fn forbid_stacking(&mut self) {
        let space = self.space;
        for t in 0..=self.horizon as usize {
            for c in 0..space.len() as u32 {
                for &r in space.stacked(c).iter().filter(|&&r| r > c) {
                    let both: Vec<Var> = self
                        .present
                        .iter()
                        .flat_map(|g| [g[t][c as usize], g[t][r as usize]])
                        .flatten()
                        .collect();
                    if both.len() > 1 {
                        self.at_most_one(&both);
                    }
                }
            }
        }
    }

    fn make_moves(&mut self) {
        let cells = self.space.len();
        for g in 0..self.groups.len() {
            let mut incoming: Vec<Vec<Var>> = vec![Vec::new(); cells];
            for t in 0..self.horizon {
                let (now, next) = (t as usize, t as usize + 1);
                for list in &mut incoming {
                    list.clear();
                }
                for c in 0..cells as u32 {
                    let Some(here) = self.present[g][now][c as usize] else {
                        continue;
                    };
                    let mut outgoing = Vec::with_capacity(7);
                    for &n in self.space.moves(c) {
                        let Some(there) = self.present[g][next][n as usize] else {
                            continue;
                        };
                        let y = self.solver.new_var_default();
                        self.clause(&[negative(y), positive(here)]);
                        self.clause(&[negative(y), positive(there)]);
                        outgoing.push(y);
                        incoming[n as usize].push(y);
                        self.moves.push(Move {
                            group: g,
                            step: t,
                            from: c,
                            to: n,
                            var: y,
                        });
                    }
                    let mut some_move = vec![negative(here)];
                    some_move.extend(outgoing.iter().map(|&y| positive(y)));
                    self.clause(&some_move);
                    self.at_most_one(&outgoing);
                }
                for (n, into) in incoming.iter().enumerate() {
                    let Some(there) = self.present[g][next][n] else {
                        continue;
                    };
                    let mut some_move = vec![negative(there)];
                    some_move.extend(into.iter().map(|&y| positive(y)));
                    self.clause(&some_move);
                    self.at_most_one(into);
                }
            }
        }
    }

    /// No two drones trade cells along an edge in one step, whatever their groups.
    fn forbid_meetings(&mut self) {
        let mut along: std::collections::HashMap<(u32, u32, u32), Vec<Var>> =
            std::collections::HashMap::new();
        for m in &self.moves {
            if m.from != m.to {
                along.entry((m.step, m.from, m.to)).or_default().push(m.var);
            }
        }
        let mut pairs = Vec::new();
        for (&(t, from, to), forward) in &along {
            if from < to
                && let Some(backward) = along.get(&(t, to, from))
            {
                for &a in forward {
                    for &b in backward {
                        pairs.push([negative(a), negative(b)]);
                    }
                }
            }
        }
        for pair in pairs {
            self.clause(&pair);
        }
    }

    /// The model as paths: drones of each group in `starts` order, followed along
    /// their moves.
    fn paths(&self) -> Vec<Vec<Vec<u32>>> {
        let mut next: std::collections::HashMap<(usize, u32, u32), u32> =
            std::collections::HashMap::new();
        for m in &self.moves {
            if self.solver.value_var(m.var) == lbool::TRUE {
                next.insert((m.group, m.step, m.from), m.to);
            }
        }
        self.groups
            .iter()
            .enumerate()
            .map(|(g, group)| {
                group
                    .starts
                    .iter()
                    .map(|&s| {
                        let mut path = Vec::with_capacity(self.horizon as usize + 1);
                        path.push(s);
                        for t in 0..self.horizon {
                            let at = path[t as usize];
                            path.push(next.get(&(g, t, at)).copied().unwrap_or(at));
                        }
                        path
                    })
                    .collect()
            })
            .collect()
    }

    /// Forbids every rotation that mixes groups in `paths` (cycles inside a group
    /// already replaced by waits); returns how many.
    fn cut_cycles(&mut self, paths: &[Vec<Vec<u32>>]) -> u64 {
        self.cut(paths, &|at, drones, t, occupant| {
            cycles_at(at, drones, t, occupant)
        })
    }

    /// Forbids, per step, a cycle of moves through the vertical reach in `paths`
    /// (see [`super::conflict`]); returns how many.
    fn cut_stacked_cycles(&mut self, paths: &[Vec<Vec<u32>>]) -> u64 {
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
