//! The planner's entry point: from a mission to its plan and the search's figures.

use super::cbm::{Search, arrival_step};
use super::discrete_plan::{DiscretePlan, DronePlan};
use super::error::PlanError;
use super::lower_bound::group_lower_bound;
use super::network::GroupCells;
use super::options::PlanOptions;
use super::space::Space;
use super::stats::{PlanStats, Progress};
use crate::mission::Mission;
use std::time::Instant;

/// A plan with the figures that go with it.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// One path per drone, makespan-optimal.
    pub plan: DiscretePlan,
    /// How the search went: bounds, node counts, time.
    pub stats: PlanStats,
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
