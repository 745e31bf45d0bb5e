//! The planner's entry point for a whole flight ([`solve`]), planned anytime, leg
//! by leg: first every leg's first plan (an answer fast, whatever the size), then
//! the flight again with each leg improved in turn while the deadline allows; the
//! better flight is the answer.

use super::anytime::Effort;
use super::discrete_plan::{DiscretePlan, DronePlan, PlanLeg};
use super::error::PlanError;
use super::options::PlanOptions;
use super::solve::{Solution, leg_instance, named, solve_in_space};
use super::space::Space;
use super::stats::{PlanStats, Progress};
use crate::mission::Mission;
use crate::world::{Voxel, VoxelGrid};
use std::time::Instant;

/// Plans `mission` pad to pad (see [`solve_with_progress`]).
///
/// ```
/// use swarmctl::{mission, plan};
/// let m = mission::from_yaml("
/// name: pass
/// world: { dimensions: [5, 1, 1], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 1.5] }
/// limits: { max_speed_mps: 1.0, max_accel_mps2: 1.0, safety_distance_m: 0.2 }
/// groups:
///   - { name: one, drones: [{ id: r1, start: [0, 0, 0] }], goals: [[4, 0, 0]] }
/// ", "pass.yaml".as_ref()).unwrap();
/// let solution = plan::solve(&m, &plan::PlanOptions::default()).unwrap();
/// // Up from the pad, along the world, down to the pad below the goal... and back:
/// // landing is on the group's pads, here the one r1 took off from.
/// let legs: Vec<u32> = solution.plan.legs.iter().map(|l| l.makespan_steps).collect();
/// assert_eq!(legs, vec![1, 4, 5]);
/// ```
pub fn solve(mission: &Mission, options: &PlanOptions) -> Result<Solution, PlanError> {
    solve_with_progress(mission, options, &mut |_| {})
}

/// Plans `mission` leg by leg in its airspace: takeoff from the pads, each formation,
/// landing; every leg makespan-optimal with CBM given where the previous one left
/// the drones, as far as the deadline allows (else the best plan found, each leg's
/// gap to its proven bound stated in [`Solution`]). Deterministic for `options.seed`,
/// except that on a leg whose conflict tree passes `options.exact_after_ct_nodes`
/// the exact method races it and the first to finish gives the paths (the makespan,
/// optimal either way, never changes); `progress` is called a few times a second
/// while a conflict tree grows.
/// The deadline covers all legs together.
pub fn solve_with_progress(
    mission: &Mission,
    options: &PlanOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Solution, PlanError> {
    let pads: Vec<Vec<Voxel>> = mission
        .groups
        .iter()
        .map(|g| g.drones.iter().map(|d| d.pad_voxel()).collect())
        .collect();
    solve_from(mission, 0, pads, options, progress)
}

/// Plans `mission`'s legs from `from_leg` on (an index into `Mission::legs`), every
/// drone starting where `at` puts it (per group, per drone, in mission order), as
/// [`solve_with_progress`] plans them from the pads: the rest of a flight after a
/// replan (see `replan`). Paths start at `at`; the plan's legs are the legs planned.
///
/// Anytime over the whole flight: first every leg's first plan, one after the
/// other, so there is an answer within a fraction of the deadline whatever the
/// size; then the flight again, each leg improved in turn, with the time left
/// (less `options.reserve_per_drone_step` for every drone and step of the first
/// answer, the caller's to schedule and check it). Where the improving pass runs
/// out of time, the legs it has not reached get first plans from where it left
/// the drones; the better of the two flights (fewer steps, or as many but more
/// proven) is the answer. Optimality required, or first plans off, there is one
/// improving pass.
pub(super) fn solve_from(
    mission: &Mission,
    from_leg: usize,
    at: Vec<Vec<Voxel>>,
    options: &PlanOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Solution, PlanError> {
    let started = Instant::now();
    let mut spaces = Spaces::new(mission, options.seed);
    let start = Partial::at(at, from_leg);
    if options.require_optimal || !options.first_plan {
        let mut only = start;
        let pass = (options, Effort::Improve, started);
        plan_legs(mission, &mut spaces, &mut only, pass, progress)?;
        return only.into_solution(mission, started);
    }
    let mut first = start;
    let pass = (options, Effort::FirstPlan, started);
    plan_legs(mission, &mut spaces, &mut first, pass, progress)?;
    if first.proven() {
        return first.into_solution(mission, started);
    }
    // The improving pass keeps back what the first took (to finish the legs it
    // does not reach) and what the caller needs after planning.
    let first_took = started.elapsed();
    let drone_steps = first.drone_steps();
    let answer = options
        .reserve_per_drone_step
        .saturating_mul(u32::try_from(drone_steps).unwrap_or(u32::MAX));
    let improve_options = PlanOptions {
        deadline: options
            .deadline
            .saturating_sub(answer)
            .saturating_sub(first_took),
        ..options.clone()
    };
    // Too little left to redo the first pass's work: nothing better would come.
    if improve_options.deadline < first_took.saturating_mul(2) {
        return first.into_solution(mission, started);
    }
    // The legs proven optimal up front stay: the improving pass starts after them.
    let mut better = first.clone();
    better.keep_proven_legs();
    let pass = (&improve_options, Effort::Improve, started);
    if plan_legs(mission, &mut spaces, &mut better, pass, progress).is_err() {
        let finish_options = PlanOptions {
            deadline: options.deadline.saturating_sub(answer),
            ..options.clone()
        };
        let pass = (&finish_options, Effort::FirstPlan, started);
        if plan_legs(mission, &mut spaces, &mut better, pass, progress).is_err() {
            return first.into_solution(mission, started);
        }
    }
    if better.beats(&first) {
        better.into_solution(mission, started)
    } else {
        first.into_solution(mission, started)
    }
}

/// A flight planned leg by leg up to `next_leg`: every drone's path so far (per
/// group, per drone) and where it is now.
#[derive(Debug, Clone)]
struct Partial {
    at: Vec<Vec<Voxel>>,
    paths: Vec<Vec<Vec<Voxel>>>,
    legs: Vec<PlanLeg>,
    /// Each leg's search figures, in `legs` order.
    leg_stats: Vec<PlanStats>,
    next_leg: usize,
}

impl Partial {
    /// Nothing planned yet: the drones at `at`, the flight at leg `next_leg`.
    fn at(at: Vec<Vec<Voxel>>, next_leg: usize) -> Self {
        let paths = at
            .iter()
            .map(|g| g.iter().map(|&v| vec![v]).collect())
            .collect();
        Self {
            at,
            paths,
            legs: Vec::new(),
            leg_stats: Vec::new(),
            next_leg,
        }
    }

    fn makespan_steps(&self) -> u32 {
        self.legs.last().map_or(0, |l| l.end_step)
    }

    /// Every leg's makespan proven optimal.
    fn proven(&self) -> bool {
        self.legs.iter().all(|l| l.gap_steps() == 0)
    }

    /// Steps summed over the drones: the size of what is scheduled and checked.
    fn drone_steps(&self) -> u64 {
        let drones: usize = self.at.iter().map(Vec::len).sum();
        drones as u64 * u64::from(self.makespan_steps())
    }

    /// Only the legs up to the first one not proven optimal: what any better
    /// flight may start with (the same legs from the same place, none shorter).
    fn keep_proven_legs(&mut self) {
        let proven = self.legs.iter().take_while(|l| l.gap_steps() == 0).count();
        let dropped = self.legs.len() - proven;
        if dropped == 0 {
            return;
        }
        self.legs.truncate(proven);
        self.leg_stats.truncate(proven);
        self.next_leg -= dropped;
        let steps = self.makespan_steps() as usize + 1;
        for (group_paths, group_at) in self.paths.iter_mut().zip(&mut self.at) {
            for (path, at) in group_paths.iter_mut().zip(group_at.iter_mut()) {
                path.truncate(steps);
                *at = path[path.len() - 1];
            }
        }
    }

    /// Shorter than `other`, or as long with more of it proven.
    fn beats(&self, other: &Self) -> bool {
        let proven = |p: &Self| -> u32 { p.legs.iter().filter_map(|l| l.proven_bound_steps).sum() };
        (self.makespan_steps(), std::cmp::Reverse(proven(self)))
            < (other.makespan_steps(), std::cmp::Reverse(proven(other)))
    }

    /// The plan: `mission`'s drones with their paths, the legs planned.
    fn into_solution(self, mission: &Mission, started: Instant) -> Result<Solution, PlanError> {
        let makespan = self.makespan_steps();
        let mut drones = Vec::with_capacity(mission.drone_count());
        let mut sum_of_costs = 0;
        for (g, group_paths) in mission.groups.iter().zip(self.paths) {
            for (d, path) in g.drones.iter().zip(group_paths) {
                let Some(&goal) = path.last() else {
                    return Err(PlanError::Internal("a drone without a path"));
                };
                let plan = DronePlan {
                    id: d.id.clone(),
                    group: g.name.clone(),
                    goal,
                    path,
                };
                sum_of_costs += u64::from(plan.arrival_step());
                drones.push(plan);
            }
        }
        debug_assert!(drones.iter().all(|d| d.path.len() == makespan as usize + 1));
        let mut stats = PlanStats::default();
        for (leg, leg_stats) in self.legs.iter().zip(&self.leg_stats) {
            stats.add_leg(&leg.name, leg_stats, leg.makespan_steps);
        }
        stats.total_time = started.elapsed();
        Ok(Solution {
            plan: DiscretePlan {
                makespan_steps: makespan,
                sum_of_costs_steps: sum_of_costs,
                drones,
                legs: self.legs,
            },
            stats,
        })
    }
}

/// The compact spaces legs are planned in, built once per flight: the airspace,
/// and (built when a leg first needs it) the world's own voxels without the pad
/// layer, for legs that keep out of it (formations of an imported instance).
struct Spaces<'m> {
    airspace: &'m VoxelGrid,
    space: Space,
    world_only: Option<(VoxelGrid, Space)>,
    mission: &'m Mission,
    seed: u64,
}

impl<'m> Spaces<'m> {
    fn new(mission: &'m Mission, seed: u64) -> Self {
        let airspace = &mission.airspace;
        let reach = mission.limits.vertical_reach(airspace);
        Self {
            airspace,
            space: Space::with_reach(airspace, seed, reach),
            world_only: None,
            mission,
            seed,
        }
    }

    /// The grid and space of a leg that may (`pad_layer_open`) or may not use the pad layer.
    fn for_leg(&mut self, pad_layer_open: bool) -> (&VoxelGrid, &Space) {
        if pad_layer_open {
            return (self.airspace, &self.space);
        }
        let (mission, seed) = (self.mission, self.seed);
        let (grid, space) = self.world_only.get_or_insert_with(|| {
            let grid = mission.airspace.without_pad_layer();
            let reach = mission.limits.vertical_reach(&grid);
            let space = Space::with_reach(&grid, seed, reach);
            (grid, space)
        });
        (&*grid, &*space)
    }
}

/// Plans `flight`'s legs from its `next_leg` to the last, each with `effort`,
/// within `options.deadline` counted from `started`. On failure `flight` keeps
/// the legs planned before the one that failed.
fn plan_legs(
    mission: &Mission,
    spaces: &mut Spaces<'_>,
    flight: &mut Partial,
    (options, effort, started): (&PlanOptions, Effort, Instant),
    progress: &mut dyn FnMut(&Progress),
) -> Result<(), PlanError> {
    let flight_legs = mission.legs();
    let leg_count = flight_legs.len();
    for (k, leg) in flight_legs.into_iter().enumerate().skip(flight.next_leg) {
        let (tapf, owners) = leg_instance(&leg.targets, &flight.at)?;
        let remaining = options.deadline.saturating_sub(started.elapsed());
        let leg_options = PlanOptions {
            deadline: remaining,
            ..options.clone()
        };
        let legs_after = leg_count - k - 1;
        let mut in_leg = |p: &Progress| {
            progress(&Progress {
                leg: leg.name.clone(),
                ..p.clone()
            });
        };
        let (grid, space) = spaces.for_leg(leg.pad_layer_open);
        let how = (&leg_options, legs_after, effort);
        let solved =
            solve_in_space(grid, space, &tapf, how, &mut in_leg).map_err(|e| PlanError::Leg {
                leg: leg.name.clone(),
                reason: Box::new(named(e, mission, &owners)),
            })?;
        for ((gi, di), group_paths) in owners.iter().zip(&solved.paths) {
            let drones: Vec<usize> = match di {
                Some(di) => vec![*di],
                None => (0..flight.at[*gi].len()).collect(),
            };
            for (&d, p) in drones.iter().zip(group_paths) {
                flight.paths[*gi][d].extend(p.iter().skip(1).copied());
                flight.at[*gi][d] = *p.last().unwrap_or(&flight.at[*gi][d]);
            }
        }
        let end_step = flight.makespan_steps() + solved.makespan_steps;
        flight.legs.push(PlanLeg {
            name: leg.name.clone(),
            kind: leg.kind,
            end_step,
            hold_s: leg.hold_s,
            makespan_steps: solved.makespan_steps,
            lower_bound_steps: solved.stats.initial_lower_bound_steps,
            proven_bound_steps: Some(solved.stats.best_lower_bound_steps),
        });
        flight.leg_stats.push(solved.stats);
        flight.next_leg = k + 1;
    }
    Ok(())
}
