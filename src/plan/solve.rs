//! One TAPF instance on any grid ([`solve_tapf`]), with the search's figures, and
//! what a whole flight's legs (`flight`) need of it: a leg as a TAPF instance,
//! solved in a compact space built once.

use super::anytime::{Effort, is_big_leg, plan_anytime};
use super::discrete_plan::DiscretePlan;
use super::error::PlanError;
use super::lower_bound::{Bottleneck, bottleneck_assignment_in};
use super::network::GroupCells;
use super::open_sky::{pairwise_stable, straight_lines};
use super::options::PlanOptions;
use super::space::{NONE, Space};
use super::stats::{PlanPhase, PlanStats, Progress, Throttle};
use crate::mission::{Mission, Targets, contested};
use crate::world::{Voxel, VoxelGrid};
use std::time::Instant;

/// A plan with the figures that go with it.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// One path per drone, pad to pad, each leg makespan-optimal.
    pub plan: DiscretePlan,
    /// How the search went: bounds, node counts, time, per leg and in total.
    pub stats: PlanStats,
}

/// Interchangeable drones of one TAPF instance: any of them may take any goal.
#[derive(Debug, Clone, PartialEq)]
pub struct TapfGroup {
    /// Where each drone is at step 0.
    pub starts: Vec<Voxel>,
    /// At least one goal per drone.
    pub goals: Vec<Voxel>,
}

/// A makespan-optimal solution of one TAPF instance.
#[derive(Debug, Clone, PartialEq)]
pub struct TapfSolution {
    /// Per group, per drone (in `starts` order): its voxel at every step from 0 to
    /// `makespan_steps`.
    pub paths: Vec<Vec<Vec<Voxel>>>,
    /// The step at which the last drone arrives for good.
    pub makespan_steps: u32,
    /// The search's figures.
    pub stats: PlanStats,
}

/// Which TAPF group each of a leg's groups or drones becomes: `(group, None)` for a
/// group's shared targets, `(group, Some(drone))` for a drone's own.
pub(super) type Owners = Vec<(usize, Option<usize>)>;

/// A leg as one TAPF instance from where the drones are (`at`, per group): shared
/// targets make one CBM group; per-drone targets one group per drone.
pub(super) fn leg_instance(
    targets: &[Targets],
    at: &[Vec<Voxel>],
) -> Result<(Vec<TapfGroup>, Owners), PlanError> {
    let mut tapf = Vec::new();
    let mut owners = Vec::new();
    for (gi, targets) in targets.iter().enumerate() {
        match (targets, targets.per_drone(&at[gi])) {
            (Targets::Any(goals), _) => {
                tapf.push(TapfGroup {
                    starts: at[gi].clone(),
                    goals: goals.clone(),
                });
                owners.push((gi, None));
            }
            (_, Some(own)) => {
                for (di, goal) in own.into_iter().enumerate() {
                    tapf.push(TapfGroup {
                        starts: vec![at[gi][di]],
                        goals: vec![goal],
                    });
                    owners.push((gi, Some(di)));
                }
            }
            (_, None) => return Err(PlanError::Internal("leg targets without a voxel set")),
        }
    }
    Ok((tapf, owners))
}

/// `e` with the TAPF group indices (`#i`) it names replaced by what the user wrote:
/// `group blue` for a group's shared targets, `drone b1` for a drone's own.
pub(super) fn named(
    e: PlanError,
    mission: &Mission,
    owners: &[(usize, Option<usize>)],
) -> PlanError {
    let name = |tapf: &str| {
        let owner = tapf
            .strip_prefix('#')
            .and_then(|i| i.parse::<usize>().ok())
            .and_then(|i| owners.get(i));
        match owner {
            Some(&(gi, None)) => format!("group {}", mission.groups[gi].name),
            Some(&(gi, Some(di))) => format!("drone {}", mission.groups[gi].drones[di].id),
            None => tapf.to_string(),
        }
    };
    match e {
        PlanError::Impossible { who, arrangements } => PlanError::Impossible {
            who: who.iter().map(|w| name(w)).collect(),
            arrangements,
        },
        PlanError::Unreachable(who) => PlanError::Unreachable(name(&who)),
        PlanError::Contested {
            who,
            voxels,
            stacked,
        } => PlanError::Contested {
            who: who.iter().map(|w| name(w)).collect(),
            voxels,
            stacked,
        },
        other => other,
    }
}

/// Solves one TAPF instance on `grid`: CBM over `groups`, makespan-optimal.
///
/// ```
/// use swarmctl::plan::{self, TapfGroup};
/// use swarmctl::world::{Voxel, VoxelGrid};
/// // A corridor with one side cell: r2 ducks into it to let r1 pass.
/// let mut grid = VoxelGrid::new([5, 1, 2], 1.0, [0.0; 3]);
/// for x in [0, 1, 3, 4] {
///     grid.block(Voxel::new(x, 0, 1));
/// }
/// let groups = [
///     TapfGroup { starts: vec![Voxel::new(0, 0, 0)], goals: vec![Voxel::new(4, 0, 0)] },
///     TapfGroup { starts: vec![Voxel::new(1, 0, 0)], goals: vec![Voxel::new(3, 0, 0)] },
/// ];
/// let solution = plan::solve_tapf(&grid, &groups, &plan::PlanOptions::default()).unwrap();
/// assert_eq!(solution.makespan_steps, 4);
/// ```
pub fn solve_tapf(
    grid: &VoxelGrid,
    groups: &[TapfGroup],
    options: &PlanOptions,
) -> Result<TapfSolution, PlanError> {
    let space = Space::new(grid, options.seed);
    let how = (options, 0, Effort::Improve);
    solve_in_space(grid, &space, groups, how, &mut |_| {})
}

/// [`solve_tapf`] on a compact space built once for several instances, with
/// `legs_after` legs of the same flight still to plan within `options.deadline`
/// (see `improve_until`), with `effort`.
pub(super) fn solve_in_space(
    grid: &VoxelGrid,
    space: &Space,
    groups: &[TapfGroup],
    (options, legs_after, effort): (&PlanOptions, usize, Effort),
    progress: &mut dyn FnMut(&Progress),
) -> Result<TapfSolution, PlanError> {
    let started = Instant::now();
    let compact = |v| grid.cell(v).map(|c| space.compact(c));
    // A target that is blocked is no target: a replan blocks a lost drone's
    // column, which may hold another drone's pad (any of the group's others
    // may still do; too few left is reported below).
    let free_goals: Vec<Vec<Voxel>> = groups
        .iter()
        .map(|g| {
            g.goals
                .iter()
                .copied()
                .filter(|&v| grid.is_free(v))
                .collect()
        })
        .collect();
    // Groups whose targets overlap may need more of them than there are, or must
    // take two stacked under an ellipsoid: no search places them, however long it
    // runs, so say so now.
    let demands: Vec<(usize, &[Voxel])> = groups
        .iter()
        .zip(&free_goals)
        .map(|(g, goals)| (g.starts.len(), &goals[..]))
        .collect();
    let stacked = |a: Voxel, b: Voxel| match (compact(a), compact(b)) {
        (Some(a), Some(b)) => space.stacked(a).contains(&b),
        _ => false,
    };
    if let Some(contest) = contested(&demands, &stacked) {
        return Err(PlanError::Contested {
            who: contest.demands.iter().map(|i| format!("#{i}")).collect(),
            voxels: contest.voxels,
            stacked: contest.stacked,
        });
    }
    if let Some(answer) = open_sky(
        grid,
        space,
        (groups, &free_goals),
        (options, effort),
        started,
    ) {
        return Ok(answer);
    }
    let mut cells = Vec::with_capacity(groups.len());
    for (gi, g) in groups.iter().enumerate() {
        let starts: Option<Vec<u32>> = g.starts.iter().map(|&v| compact(v)).collect();
        let goals: Option<Vec<u32>> = free_goals[gi].iter().map(|&v| compact(v)).collect();
        let (Some(starts), Some(goals)) = (starts, goals) else {
            return Err(PlanError::Unreachable(format!("#{gi}")));
        };
        if starts.contains(&NONE) || goals.contains(&NONE) {
            return Err(PlanError::Unreachable(format!("#{gi}")));
        }
        cells.push(GroupCells::new(space, starts, &goals));
    }
    let (lower_bounds, assigned) =
        bounds_and_assignments(space, &cells, (options, effort, started), progress)?;
    let legs = (options, legs_after, effort);
    let groups = (&cells[..], &lower_bounds[..], &assigned[..]);
    let routed = plan_anytime(space, groups, legs, started, progress)?;
    let (paths, makespan) = (&routed.paths, routed.makespan);
    Ok(tapf_solution(
        grid,
        space,
        paths,
        makespan,
        routed.stats,
        started,
    ))
}

/// Each group's lower bound and a distinct goal per drone for PIBT to start
/// from: the bottleneck assignment, or where a big leg's first pass runs out of
/// the time it gives that, the nearest-goal bound and an assignment by squared
/// distances. Fails naming the group (`#i`) that cannot reach its goals.
fn bounds_and_assignments(
    space: &Space,
    cells: &[GroupCells],
    (options, effort, started): (&PlanOptions, Effort, Instant),
    progress: &mut dyn FnMut(&Progress),
) -> Result<(Vec<u32>, Vec<Vec<u32>>), PlanError> {
    // The bottleneck assignment is the tighter bound and PIBT's best start, but
    // on a big leg (see `is_big_leg`) it can take seconds (10 s for 5,000 drones
    // landing 41 moves from their pads). A big leg's first pass gives it a third
    // of the leg's time; groups it does not reach by then start from the
    // nearest-goal bound and an assignment by squared distances (milliseconds
    // each): a first answer with a wider gap rather than none.
    let nearest: Vec<Option<u32>> = cells.iter().map(GroupCells::nearest_bound).collect();
    let drones = cells.iter().map(|g| g.starts.len()).sum();
    let leg_nearest = nearest.iter().flatten().copied().max().unwrap_or(0);
    let hurried =
        options.first_plan && effort == Effort::FirstPlan && is_big_leg(drones, space, leg_nearest);
    let bounds_until = hurried.then(|| started + options.deadline / 3);
    let mut lower_bounds = Vec::with_capacity(cells.len());
    let mut assigned = Vec::with_capacity(cells.len());
    let mut throttle = Throttle::new();
    for (gi, group) in cells.iter().enumerate() {
        if throttle.due() {
            progress(&Progress {
                leg: String::new(),
                phase: PlanPhase::LowerBounds {
                    groups_done: gi,
                    groups: cells.len(),
                },
                ct_nodes_expanded: 0,
                open_nodes: 0,
                best_lower_bound_steps: lower_bounds.iter().copied().max().unwrap_or(0),
                incumbent_steps: None,
                elapsed: started.elapsed(),
            });
        }
        let unreachable = || PlanError::Unreachable(format!("#{gi}"));
        let Some(nearest) = nearest[gi] else {
            return Err(unreachable());
        };
        let (lb, first_goals) = match bottleneck_assignment_in(
            space,
            &group.starts,
            (&group.goals, &group.to_goal),
            bounds_until,
        ) {
            Bottleneck::Found(lb, assigned) => (lb, assigned),
            Bottleneck::Unmatchable => return Err(unreachable()),
            Bottleneck::OutOfTime => {
                let until = started + options.deadline;
                match assignment_by_squares(space, group, until) {
                    Some(by_squares) => (nearest, by_squares),
                    None if Instant::now() >= until => {
                        let so_far = lower_bounds.iter().copied().max().unwrap_or(0);
                        return Err(PlanError::Deadline {
                            deadline: options.deadline,
                            best_lower_bound_steps: so_far.max(nearest),
                            ct_nodes: 0,
                        });
                    }
                    None => return Err(unreachable()),
                }
            }
        };
        lower_bounds.push(lb);
        assigned.push(first_goals);
    }
    Ok((lower_bounds, assigned))
}

/// Each drone of `group` a distinct goal such that no exchange of two drones'
/// goals lowers their summed squared distances (`open_sky`'s assignment): a
/// start for PIBT found in milliseconds; `None` past `until`.
fn assignment_by_squares(space: &Space, group: &GroupCells, until: Instant) -> Option<Vec<u32>> {
    let point = |&c: &u32| space.point(c);
    let starts: Vec<[i32; 3]> = group.starts.iter().map(point).collect();
    let goals: Vec<[i32; 3]> = group.goals.iter().map(point).collect();
    let goal_of = pairwise_stable(&starts, &goals, until)?;
    Some(goal_of.into_iter().map(|g| group.goals[g]).collect())
}

/// The leg on straight lines where it is open sky (see `open_sky`), tried within
/// a quarter of the deadline (where lines meet, the rest is the search's): the
/// answer when they meet their bound, or as a big leg's first answer (its
/// bounds and exact search take seconds). Anywhere else they are not used: as
/// the search's incumbent in place of PIBT's first plan they cost optimality on
/// the `scale` suite (a landing leg left 5–8 steps above its bound, which the
/// search beat from PIBT's plan). Whether they would be used is known from the
/// assignment's longest line before any staircase is flown, so a leg where
/// they cannot be pays for the assignment only (a big leg's improving pass
/// no longer flies and checks its staircases a second time).
fn open_sky(
    grid: &VoxelGrid,
    space: &Space,
    (groups, free_goals): (&[TapfGroup], &[Vec<Voxel>]),
    (options, effort): (&PlanOptions, Effort),
    started: Instant,
) -> Option<TapfSolution> {
    if !options.first_plan {
        return None;
    }
    let ends: Vec<(&[Voxel], &[Voxel])> = groups
        .iter()
        .zip(free_goals)
        .map(|(g, goals)| (&g.starts[..], &goals[..]))
        .collect();
    let until = started + options.deadline / 4;
    let drones = groups.iter().map(|g| g.starts.len()).sum();
    let used = |makespan: u32, lower_bound: u32| {
        makespan <= lower_bound
            || (effort == Effort::FirstPlan && is_big_leg(drones, space, lower_bound))
    };
    let lines = straight_lines(grid, space, &ends, until, used)?;
    let stats = PlanStats {
        initial_lower_bound_steps: lines.lower_bound,
        best_lower_bound_steps: lines.lower_bound,
        first_plan_steps: Some(lines.makespan),
        first_plan_time: started.elapsed(),
        straight_line_legs: 1,
        ..PlanStats::default()
    };
    Some(tapf_solution(
        grid,
        space,
        &lines.paths,
        lines.makespan,
        stats,
        started,
    ))
}

/// A TAPF solution from compact paths (per group, per drone), each padded with
/// waits to `makespan`.
fn tapf_solution<P: AsRef<[Vec<u32>]>>(
    grid: &VoxelGrid,
    space: &Space,
    groups: &[P],
    makespan: u32,
    mut stats: PlanStats,
    started: Instant,
) -> TapfSolution {
    let paths = groups
        .iter()
        .map(|group| {
            group
                .as_ref()
                .iter()
                .map(|path| {
                    let at = |t: usize| grid.voxel(space.world_cell(path[t.min(path.len() - 1)]));
                    (0..=makespan as usize).map(at).collect()
                })
                .collect()
        })
        .collect();
    stats.total_time = started.elapsed();
    TapfSolution {
        paths,
        makespan_steps: makespan,
        stats,
    }
}
