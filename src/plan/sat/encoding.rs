//! The SAT encoding at one horizon: presence and move variables, the flow clauses
//! that make them paths, the clauses forbidding meetings, swaps and stacking, and
//! the model read back as paths.

use crate::plan::network::GroupCells;
use crate::plan::space::{NONE, Space};
use batsat::{Callbacks, Lit, SolverInterface, SolverOpts, Var, lbool};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Stops the solver at the deadline or when asked to.
pub(super) struct Until<'s> {
    pub(super) deadline_at: Instant,
    pub(super) stop: &'s AtomicBool,
}

impl Callbacks for Until<'_> {
    fn stop(&self) -> bool {
        self.stop.load(Ordering::Relaxed) || Instant::now() >= self.deadline_at
    }
}

/// One move variable: group, step, from, to.
pub(super) struct Move {
    pub(super) group: usize,
    pub(super) step: u32,
    pub(super) from: u32,
    pub(super) to: u32,
    pub(super) var: Var,
}

/// The encoding at one horizon, and the solver holding it.
pub(super) struct Encoding<'a> {
    pub(super) space: &'a Space,
    groups: &'a [GroupCells],
    pub(super) horizon: u32,
    pub(super) solver: batsat::Solver<Until<'a>>,
    /// `present[g][t][c]`: the `x` variable, or `None` where pruned.
    present: Vec<Vec<Vec<Option<Var>>>>,
    pub(super) moves: Vec<Move>,
}

fn positive(v: Var) -> Lit {
    Lit::new(v, true)
}

pub(super) fn negative(v: Var) -> Lit {
    Lit::new(v, false)
}

impl<'a> Encoding<'a> {
    /// The encoding at `horizon`; `None` when a start cannot reach a goal by then.
    pub(super) fn new(
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

    pub(super) fn clause(&mut self, lits: &[Lit]) {
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
    pub(super) fn paths(&self) -> Vec<Vec<Vec<u32>>> {
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
}
