//! The planner's entry point: options, result, counters and errors.

use super::cbm::{Search, arrival_step};
use super::discrete_plan::{DiscretePlan, DronePlan};
use super::lower_bound::group_lower_bound;
use super::network::GroupCells;
use super::space::Space;
use crate::mission::Mission;
use std::time::{Duration, Instant};

/// How to plan.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// Give up after this long, reporting the best lower bound proven so far.
    pub deadline: Duration,
    /// Breaks ties between equally good paths; the same seed gives the same plan.
    pub seed: u64,
}

impl Default for PlanOptions {
    fn default() -> Self {
        Self {
            deadline: Duration::from_secs(60),
            seed: 0,
        }
    }
}

/// Counters describing the search, for reports and benchmarks.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct PlanStats {
    /// Makespan lower bound before search (bottleneck assignment, collisions ignored).
    pub initial_lower_bound_steps: u32,
    /// Highest makespan of any conflict-tree node expanded: a proven lower bound.
    pub best_lower_bound_steps: u32,
    pub ct_nodes_expanded: u64,
    pub ct_nodes_generated: u64,
    pub low_level_calls: u64,
    pub flow_augmentations: u64,
    #[serde(rename = "low_level_time_s", serialize_with = "as_seconds")]
    pub low_level_time: Duration,
    #[serde(rename = "total_time_s", serialize_with = "as_seconds")]
    pub total_time: Duration,
}

fn as_seconds<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64())
}

impl PlanStats {
    /// Time spent in the conflict tree itself (conflict detection, bookkeeping).
    pub fn high_level_time(&self) -> Duration {
        self.total_time.saturating_sub(self.low_level_time)
    }
}

/// Reported while the search runs, a few times a second.
#[derive(Debug, Clone, PartialEq)]
pub struct Progress {
    pub ct_nodes_expanded: u64,
    pub open_nodes: usize,
    pub best_lower_bound_steps: u32,
    pub elapsed: Duration,
}

/// A plan with the figures that go with it.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    pub plan: DiscretePlan,
    pub stats: PlanStats,
}

/// Why no plan was returned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    #[error(
        "no plan within the deadline of {deadline:?} ({ct_nodes} conflict-tree nodes expanded); \
         the optimal makespan is at least {best_lower_bound_steps} steps"
    )]
    Deadline {
        deadline: Duration,
        best_lower_bound_steps: u32,
        ct_nodes: u64,
    },
    #[error("group {0:?} cannot be matched to distinct reachable goals")]
    Unreachable(String),
    #[error("no plan with a makespan of at most {0} steps")]
    HorizonExceeded(u32),
    #[error("the conflict tree was exhausted without a plan")]
    NoSolution,
    #[error("internal planner error: {0}")]
    Internal(&'static str),
}

/// Plans `mission` makespan-optimally (see [`solve_with_progress`]).
///
/// ```
/// use swarmctl::{mission, plan};
/// let m = mission::from_yaml("
/// name: pass
/// world: { dimensions: [5, 1, 2], voxel_size_m: 1.0,
///          obstacles: [{ min: [0, 0, 1], max: [1, 0, 1] }, { min: [3, 0, 1], max: [4, 0, 1] }] }
/// limits: { max_speed_mps: 1.0, max_accel_mps2: 1.0, safety_distance_m: 0.2 }
/// groups:
///   - { name: one, drones: [{ id: r1, start: [0, 0, 0] }], goals: [[4, 0, 0]] }
///   - { name: two, drones: [{ id: r2, start: [1, 0, 0] }], goals: [[3, 0, 0]] }
/// ", "pass.yaml".as_ref()).unwrap();
/// let solution = plan::solve(&m, &plan::PlanOptions::default()).unwrap();
/// assert_eq!(solution.plan.makespan_steps, 4); // r2 ducks into the side cell
/// ```
pub fn solve(mission: &Mission, options: &PlanOptions) -> Result<Solution, PlanError> {
    solve_with_progress(mission, options, &mut |_| {})
}

/// Plans `mission`: CBM over its groups, deterministic for `options.seed`, calling
/// `progress` a few times a second while the conflict tree grows.
pub fn solve_with_progress(
    mission: &Mission,
    options: &PlanOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Solution, PlanError> {
    let started = Instant::now();
    let world = &mission.world;
    let space = Space::new(world, options.seed);
    let compact = |v| world.cell(v).map(|c| space.compact(c));
    let mut groups = Vec::with_capacity(mission.groups.len());
    let mut lower_bounds = Vec::with_capacity(mission.groups.len());
    for g in &mission.groups {
        let starts: Option<Vec<u32>> = g.drones.iter().map(|d| compact(d.start)).collect();
        let goals: Option<Vec<u32>> = g.goals.iter().map(|&v| compact(v)).collect();
        let (Some(starts), Some(goals)) = (starts, goals) else {
            return Err(PlanError::Unreachable(g.name.clone()));
        };
        let lb =
            group_lower_bound(world, g).ok_or_else(|| PlanError::Unreachable(g.name.clone()))?;
        lower_bounds.push(lb);
        groups.push(GroupCells::new(&space, starts, &goals));
    }
    let initial_lower_bound = lower_bounds.iter().copied().max().unwrap_or(0);
    // Drones can always wait out a finite set of constraints; this bound only guards
    // against runaway memory on instances no search could finish anyway.
    let max_horizon = initial_lower_bound + 2 * space.len() as u32 + 64;
    let deadline_at = started + options.deadline;
    let mut search = Search::new(
        &space,
        &groups,
        &lower_bounds,
        max_horizon,
        deadline_at,
        options,
    );
    search.stats.initial_lower_bound_steps = initial_lower_bound;
    search.stats.best_lower_bound_steps = initial_lower_bound;
    let routings = search.run(progress)?;
    let mut stats = search.stats;

    let makespan = routings.iter().map(|r| r.min_horizon).max().unwrap_or(0);
    let mut drones = Vec::with_capacity(mission.drone_count());
    let mut sum_of_costs = 0;
    for (g, routing) in mission.groups.iter().zip(&routings) {
        for (d, path) in g.drones.iter().zip(&routing.paths) {
            let at = |t: usize| world.voxel(space.world_cell(path[t.min(path.len() - 1)]));
            let path_voxels: Vec<_> = (0..=makespan as usize).map(at).collect();
            sum_of_costs += arrival_step(path);
            drones.push(DronePlan {
                id: d.id.clone(),
                group: g.name.clone(),
                goal: at(path.len() - 1),
                path: path_voxels,
            });
        }
    }
    stats.best_lower_bound_steps = makespan;
    stats.total_time = started.elapsed();
    Ok(Solution {
        plan: DiscretePlan {
            makespan_steps: makespan,
            sum_of_costs_steps: sum_of_costs,
            drones,
        },
        stats,
    })
}
