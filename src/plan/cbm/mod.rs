//! Conflict-Based Min-Cost-Flow (Ma & Koenig, AAMAS 2016): a best-first conflict tree
//! over groups on top of one flow per group.
//!
//! This file holds the tree search itself; how a conflict splits a node is in
//! `branch`, and the exact method the search starts beside itself is in `exact`.

mod branch;
mod exact;

use super::conflict::{Conflict, first_conflict};
use super::constraints::Constraints;
use super::error::PlanError;
use super::low_level::{GroupRouting, LowLevelWork, min_horizon, route};
use super::network::{GroupCells, Reservation};
use super::options::PlanOptions;
use super::sat::SatOutcome;
use super::space::Space;
use super::stats::{PlanPhase, PlanStats, Progress, Throttle};
use branch::{Branch, branches};
use exact::{Exact, StopOnDrop, exact};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::rc::Rc;
use std::sync::atomic::AtomicBool;
use std::thread::ScopedJoinHandle;
use std::time::Instant;

/// A conflict-tree node: every group's constraints and routing.
struct Node {
    constraints: Vec<Rc<Constraints>>,
    routings: Vec<Rc<GroupRouting>>,
    makespan: u32,
    sum_of_costs: u64,
    conflicts: usize,
    first: Option<Conflict>,
}

/// Best-first order: makespan, then sum of costs, then fewer conflicts, then age.
type Key = Reverse<(u32, u64, u64, u64)>;

pub(crate) struct Search<'a> {
    pub space: &'a Space,
    pub groups: &'a [GroupCells],
    pub lower_bounds: &'a [u32],
    pub max_horizon: u32,
    pub options: &'a PlanOptions,
    pub stats: PlanStats,
    deadline_at: Instant,
    started: Instant,
}

impl<'a> Search<'a> {
    pub(crate) fn new(
        space: &'a Space,
        groups: &'a [GroupCells],
        lower_bounds: &'a [u32],
        max_horizon: u32,
        deadline_at: Instant,
        options: &'a PlanOptions,
    ) -> Self {
        Self {
            space,
            groups,
            lower_bounds,
            max_horizon,
            options,
            stats: PlanStats::default(),
            deadline_at,
            // When the caller started (its deadline's origin), so progress reports
            // count from the same moment as the lower bounds' before them.
            started: deadline_at
                .checked_sub(options.deadline)
                .unwrap_or_else(Instant::now),
        }
    }

    /// The conflict-free routing of least makespan, one path list per group.
    ///
    /// Past `options.exact_after_ct_nodes` expanded nodes the exact method (an
    /// impossibility proof, then the SAT encoding from the tree's proven lower bound)
    /// starts on a second thread while the tree goes on: whichever finishes first
    /// answers, and the other is stopped. Both are makespan-optimal, so the makespan
    /// never depends on which; the paths may.
    pub(crate) fn run(
        &mut self,
        progress: &mut dyn FnMut(&Progress),
    ) -> Result<Vec<Rc<GroupRouting>>, PlanError> {
        let root = self.root(progress)?;
        if root.first.is_none() {
            self.stats.ct_nodes_expanded = 1;
            return Ok(root.routings);
        }
        let stop = AtomicBool::new(false);
        let (space, groups) = (self.space, self.groups);
        let (max_horizon, deadline_at) = (self.max_horizon, self.deadline_at);
        std::thread::scope(|scope| {
            // However the tree ends, the exact method is told to stop before the
            // scope waits for it.
            let _stop_on_exit = StopOnDrop(&stop);
            let stop = &stop;
            self.tree(root, progress, &|from| {
                scope.spawn(move || exact(space, groups, from, max_horizon, (deadline_at, stop)))
            })
        })
    }

    /// Best-first search of the conflict tree from `root`; `start_exact(bound)` starts
    /// the exact method when the node budget is reached.
    fn tree<'s>(
        &mut self,
        root: Node,
        progress: &mut dyn FnMut(&Progress),
        start_exact: &dyn Fn(u32) -> ScopedJoinHandle<'s, Exact>,
    ) -> Result<Vec<Rc<GroupRouting>>, PlanError> {
        let mut open: BinaryHeap<(Key, usize)> = BinaryHeap::new();
        let mut nodes: Vec<Option<Node>> = Vec::new();
        let push =
            |open: &mut BinaryHeap<(Key, usize)>, nodes: &mut Vec<Option<Node>>, node: Node| {
                let id = nodes.len();
                open.push((
                    Reverse((
                        node.makespan,
                        node.conflicts as u64,
                        node.sum_of_costs,
                        id as u64,
                    )),
                    id,
                ));
                nodes.push(Some(node));
            };
        push(&mut open, &mut nodes, root);
        let mut throttle = Throttle::new();
        let mut running: Option<ScopedJoinHandle<'s, Exact>> = None;
        while let Some((Reverse((makespan, ..)), id)) = open.pop() {
            let Some(node) = nodes[id].take() else {
                continue;
            };
            self.stats.best_lower_bound_steps = self.stats.best_lower_bound_steps.max(makespan);
            let Some(conflict) = node.first.clone() else {
                return Ok(node.routings);
            };
            self.stats.ct_nodes_expanded += 1;
            if Instant::now() >= self.deadline_at {
                return Err(self.deadline_error());
            }
            if let Some(done) = running.take_if(|h| h.is_finished())
                && let Some(found) = self.settle(done.join())?
            {
                return Ok(found);
            }
            // Nearly every instance is solved well inside the default budget (the
            // formation change in 4 nodes, paper-scale instances in tens), while the
            // tight ones that explode the tree are small, which the encoding likes.
            if Some(self.stats.ct_nodes_expanded) == self.options.exact_after_ct_nodes {
                running = Some(start_exact(makespan));
            }
            if throttle.due() {
                progress(&self.progress(PlanPhase::ConflictTree, open.len()));
            }
            for (group, constraint) in branches(conflict) {
                let mut constraints = node.constraints.clone();
                let mut added = (*constraints[group]).clone();
                match constraint {
                    Branch::Vertex(cell, step) => added.vertex.push((cell, step)),
                    Branch::Edge(from, to, step) => added.edge.push((from, to, step)),
                }
                constraints[group] = Rc::new(added);
                if let Some(child) = self.child(&node, group, constraints)? {
                    self.stats.ct_nodes_generated += 1;
                    push(&mut open, &mut nodes, child);
                }
            }
        }
        Err(PlanError::NoSolution)
    }

    /// Every group routed on its own (its least horizon, then a routing at the
    /// largest, steering around the groups routed before it), reporting each horizon
    /// tried: at drone-show scale this is most of the work.
    fn root(&mut self, progress: &mut dyn FnMut(&Progress)) -> Result<Node, PlanError> {
        let empty = Rc::new(Constraints::default());
        let groups = self.groups.len();
        let mut throttle = Throttle::new();
        let mut horizons = Vec::with_capacity(groups);
        let (started, bound) = (self.started, self.stats.best_lower_bound_steps);
        for (g, cells) in self.groups.iter().enumerate() {
            let mut on_layer = |horizon_steps| {
                if throttle.due() {
                    let phase = PlanPhase::Horizons {
                        groups_done: g,
                        groups,
                        horizon_steps,
                    };
                    progress(&snapshot(started, phase, (0, 0), bound));
                }
            };
            let t = self.min_horizon(cells, &empty, self.lower_bounds[g], &mut on_layer)?;
            horizons.push(t);
        }
        let makespan = horizons.iter().copied().max().unwrap_or(0);
        // Route groups in turn, each steering around those already routed.
        let mut reservation = Reservation::new(self.space.len(), makespan);
        let mut routings = Vec::with_capacity(groups);
        for (g, cells) in self.groups.iter().enumerate() {
            let mut on_routed = |drones_routed| {
                if throttle.due() {
                    let phase = PlanPhase::Routings {
                        groups_done: g,
                        groups,
                        horizon_steps: makespan,
                        drones_routed,
                        drones: cells.starts.len(),
                    };
                    progress(&snapshot(started, phase, (0, 0), bound));
                }
            };
            let paths = self.route(cells, &empty, makespan, &reservation, &mut on_routed)?;
            for p in &paths {
                reservation.add_path(p, self.space);
            }
            routings.push(Rc::new(GroupRouting {
                min_horizon: horizons[g],
                paths,
            }));
        }
        self.stats.ct_nodes_generated = 1;
        Ok(self.evaluate(vec![empty; self.groups.len()], routings))
    }

    /// Re-routes `group` under its new constraints; `None` if it cannot be routed at all.
    fn child(
        &mut self,
        parent: &Node,
        group: usize,
        constraints: Vec<Rc<Constraints>>,
    ) -> Result<Option<Node>, PlanError> {
        let cells = &self.groups[group];
        let previous = parent.routings[group].min_horizon;
        let horizon = match self.min_horizon(cells, &constraints[group], previous, &mut |_| {}) {
            Ok(horizon) => horizon,
            Err(PlanError::HorizonExceeded(_)) => return Ok(None),
            Err(other) => return Err(other),
        };
        let others_makespan = parent
            .routings
            .iter()
            .enumerate()
            .filter(|&(g, _)| g != group)
            .map(|(_, r)| r.min_horizon)
            .max()
            .unwrap_or(0);
        let makespan = horizon.max(others_makespan);
        let mut reservation = Reservation::new(self.space.len(), makespan);
        for (_, r) in parent
            .routings
            .iter()
            .enumerate()
            .filter(|&(g, _)| g != group)
        {
            for p in &r.paths {
                reservation.add_path(p, self.space);
            }
        }
        let paths = self.route(
            cells,
            &constraints[group],
            makespan,
            &reservation,
            &mut |_| {},
        )?;
        let mut routings = parent.routings.clone();
        routings[group] = Rc::new(GroupRouting {
            min_horizon: horizon,
            paths,
        });
        Ok(Some(self.evaluate(constraints, routings)))
    }

    fn evaluate(&self, constraints: Vec<Rc<Constraints>>, routings: Vec<Rc<GroupRouting>>) -> Node {
        let makespan = routings.iter().map(|r| r.min_horizon).max().unwrap_or(0);
        let sum_of_costs = routings
            .iter()
            .flat_map(|r| r.paths.iter())
            .map(|p| arrival_step(p))
            .sum();
        let views: Vec<&[Vec<u32>]> = routings.iter().map(|r| r.paths.as_slice()).collect();
        let (first, conflicts) = first_conflict(&views, self.space, makespan);
        Node {
            constraints,
            routings,
            makespan,
            sum_of_costs,
            conflicts,
            first,
        }
    }

    /// Takes in what the exact method found: its routing, or `None` to let the tree
    /// go on (the encoding was too large, or it was stopped), with its proven bound.
    fn settle(
        &mut self,
        joined: std::thread::Result<Exact>,
    ) -> Result<Option<Vec<Rc<GroupRouting>>>, PlanError> {
        let Ok(done) = joined else {
            return Err(PlanError::Internal("the exact method's thread panicked"));
        };
        self.stats.sat_horizons += done.work.horizons;
        self.stats.sat_time += done.time;
        if let Some((groups, arrangements)) = done.impossible {
            return Err(PlanError::Impossible {
                who: groups.iter().map(|g| format!("#{g}")).collect(),
                arrangements,
            });
        }
        match done.outcome {
            Some(SatOutcome::Solved { makespan, routings }) => {
                self.stats.best_lower_bound_steps = makespan;
                Ok(Some(routings.into_iter().map(Rc::new).collect()))
            }
            Some(SatOutcome::NoPlanUpToCap) => Err(PlanError::HorizonExceeded(self.max_horizon)),
            Some(SatOutcome::TooLarge { lower_bound } | SatOutcome::Stopped { lower_bound }) => {
                self.stats.best_lower_bound_steps =
                    self.stats.best_lower_bound_steps.max(lower_bound);
                Ok(None)
            }
            None => Ok(None),
        }
    }

    fn deadline_error(&self) -> PlanError {
        PlanError::Deadline {
            deadline: self.options.deadline,
            best_lower_bound_steps: self.stats.best_lower_bound_steps,
            ct_nodes: self.stats.ct_nodes_expanded,
        }
    }

    /// What the search has got to, for a progress report.
    fn progress(&self, phase: PlanPhase, open_nodes: usize) -> Progress {
        let nodes = (self.stats.ct_nodes_expanded, open_nodes);
        snapshot(
            self.started,
            phase,
            nodes,
            self.stats.best_lower_bound_steps,
        )
    }

    fn min_horizon(
        &mut self,
        cells: &GroupCells,
        constraints: &Constraints,
        at_least: u32,
        on_layer: &mut dyn FnMut(u32),
    ) -> Result<u32, PlanError> {
        let started = Instant::now();
        let mut work = LowLevelWork::default();
        let result = min_horizon(
            self.space,
            cells,
            constraints,
            (at_least, self.max_horizon),
            (self.deadline_at, on_layer),
            &mut work,
        );
        self.account(started, work);
        match result {
            Some(horizon) => Ok(horizon),
            None if Instant::now() >= self.deadline_at => Err(self.deadline_error()),
            None => Err(PlanError::HorizonExceeded(self.max_horizon)),
        }
    }

    fn route(
        &mut self,
        cells: &GroupCells,
        constraints: &Constraints,
        horizon: u32,
        others: &Reservation,
        on_routed: &mut dyn FnMut(usize),
    ) -> Result<Vec<Vec<u32>>, PlanError> {
        let started = Instant::now();
        let mut work = LowLevelWork::default();
        let result = route(
            self.space,
            cells,
            constraints,
            horizon,
            others,
            (self.deadline_at, on_routed),
            &mut work,
        );
        self.account(started, work);
        match result {
            Some(paths) => Ok(paths),
            None if Instant::now() >= self.deadline_at => Err(self.deadline_error()),
            // The horizon was proven feasible just before, so this cannot happen.
            None => Err(PlanError::Internal("no routing at a feasible horizon")),
        }
    }

    fn account(&mut self, started: Instant, work: LowLevelWork) {
        self.stats.low_level_calls += 1;
        self.stats.flow_augmentations += work.augmentations;
        self.stats.low_level_time += started.elapsed();
    }
}

/// A progress report: the search started at `started`, is in `phase` with
/// `(expanded, open)` conflict-tree nodes, and has proven the makespan at least
/// `bound_steps`.
fn snapshot(
    started: Instant,
    phase: PlanPhase,
    (expanded, open): (u64, usize),
    bound_steps: u32,
) -> Progress {
    Progress {
        leg: String::new(),
        phase,
        ct_nodes_expanded: expanded,
        open_nodes: open,
        best_lower_bound_steps: bound_steps,
        incumbent_steps: None,
        elapsed: started.elapsed(),
    }
}

/// The first step from which a path stays at its last cell.
pub(crate) fn arrival_step(path: &[u32]) -> u64 {
    let Some(&goal) = path.last() else { return 0 };
    path.iter()
        .rposition(|&c| c != goal)
        .map_or(0, |i| i as u64 + 1)
}
