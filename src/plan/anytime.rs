//! A leg planned anytime: a first plan fast ([`first_plan_within`]), finished by
//! the exact search where PIBT stalls, then the exact search to beat it until
//! [`improve_until`], which keeps time for the legs still to plan.

use super::cbm::{Search, arrival_step};
use super::error::PlanError;
use super::first_plan::{FirstPlan, Stepping, first_plan};
use super::low_level::GroupRouting;
use super::network::GroupCells;
use super::options::PlanOptions;
use super::space::Space;
use super::stats::{PlanPhase, PlanStats, Progress, Throttle};
use std::rc::Rc;
use std::time::{Duration, Instant};

/// A leg's routing in compact cells: per group, per drone (in start order), its
/// cell at every step up to `makespan` (or until it stays), with the figures.
pub(super) struct Routed {
    pub paths: Vec<Vec<Vec<u32>>>,
    pub makespan: u32,
    pub stats: PlanStats,
}

/// How much work a leg gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Effort {
    /// The exact search's head start (none on a big leg), then its first plan
    /// and no more (the exact search only where no first plan is found): a
    /// whole flight's first answer, fast.
    FirstPlan,
    /// The same, then the exact search to beat the first plan until
    /// [`improve_until`].
    Improve,
}

/// Plans one leg's groups (`cells`, with their bottleneck `lower_bounds` and
/// assignments `assigned`, per group, per drone, a goal) anytime:
/// a first plan, returned at once if it meets the bound (or if `effort` asks for
/// no more); else the exact search for a better one, capped below the first
/// plan's makespan, until [`improve_until`]. Past that, the first plan with the
/// bound proven so far, or (with `require_optimal`) the deadline error. The
/// search started at `started`.
pub(super) fn plan_anytime(
    space: &Space,
    (cells, lower_bounds, assigned): (&[GroupCells], &[u32], &[Vec<u32>]),
    (options, legs_after, effort): (&PlanOptions, usize, Effort),
    started: Instant,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Routed, PlanError> {
    let initial_lower_bound = lower_bounds.iter().copied().max().unwrap_or(0);
    // Drones can always wait out a finite set of constraints; this bound only guards
    // against runaway memory on instances no search could finish anyway.
    let max_horizon = initial_lower_bound + 2 * space.len() as u32 + 64;
    let deadline_at = started + options.deadline;
    let mut stats = PlanStats {
        initial_lower_bound_steps: initial_lower_bound,
        best_lower_bound_steps: initial_lower_bound,
        ..PlanStats::default()
    };
    let mut head_start_used = Duration::ZERO;
    let first = if options.first_plan {
        // Where the exact search is quick, as on most instances of a few hundred
        // drones, a first plan would only cost time: it gets a short head start.
        // A big leg gets none: its search would only start building networks
        // (seconds at 5,000 drones) before it noticed its time was up.
        let head = head_start(space, cells, initial_lower_bound, options);
        if !head.is_zero() {
            let head_start_at = started + head;
            let head_options = PlanOptions {
                deadline: head,
                ..options.clone()
            };
            let mut search = Search::new(
                space,
                cells,
                lower_bounds,
                max_horizon,
                head_start_at,
                &head_options,
            );
            search.stats = stats;
            let head_started = Instant::now();
            let outcome = search.run(progress);
            head_start_used = head_started.elapsed();
            stats = search.stats;
            match outcome {
                Ok(routings) => return Ok(routed(&routings, stats)),
                Err(PlanError::Deadline { .. }) => {}
                Err(proof) => return Err(proof),
            }
        }
        let groups = (cells, lower_bounds, assigned);
        first_plan_within(space, groups, (started, options), progress)
    } else {
        None
    };
    let first_steps = first.as_ref().map(|(f, _)| f.makespan);
    stats.first_plan_steps = first_steps;
    stats.first_plan_time = first.as_ref().map_or_else(Duration::default, |(_, t)| *t);
    let answer = |first: FirstPlan, stats| Routed {
        paths: first.paths,
        makespan: first.makespan,
        stats,
    };
    let first = match first {
        Some((first, _)) if first.makespan <= initial_lower_bound => {
            // At the bound: nothing can beat it.
            stats.best_lower_bound_steps = first.makespan;
            return Ok(answer(first, stats));
        }
        Some((first, _)) if effort == Effort::FirstPlan => return Ok(answer(first, stats)),
        other => other,
    };
    // With a first plan in hand, the exact search only has to find a better one:
    // no horizon at or past the first plan's is worth trying.
    let cap = first_steps.map_or(max_horizon, |f| f.saturating_sub(1).min(max_horizon));
    let until = match &first {
        // What this leg took to its first plan (bounds, networks' distances, the
        // plan itself, less any head start), as the measure of what a later leg needs.
        Some(_) => {
            let setup = started.elapsed().saturating_sub(head_start_used);
            improve_until(deadline_at, setup, legs_after, options)
        }
        None => deadline_at,
    };
    let improve_options = PlanOptions {
        deadline: until.saturating_duration_since(started),
        ..options.clone()
    };
    let mut search = Search::new(space, cells, lower_bounds, cap, until, &improve_options);
    search.stats = stats;
    let outcome = search.run(&mut |p: &Progress| {
        progress(&Progress {
            incumbent_steps: first_steps,
            ..p.clone()
        });
    });
    let mut stats = search.stats;
    match (outcome, first) {
        (Ok(routings), _) => Ok(routed(&routings, stats)),
        // Nothing below the first plan's makespan: it is optimal.
        (Err(PlanError::HorizonExceeded(_) | PlanError::NoSolution), Some((first, _))) => {
            stats.best_lower_bound_steps = first.makespan;
            Ok(answer(first, stats))
        }
        (Err(PlanError::Deadline { .. }), Some((first, _))) if !options.require_optimal => {
            Ok(answer(first, stats))
        }
        (Err(e), _) => Err(e),
    }
}

/// The exact search's routing as a leg's answer: optimal, so proven.
fn routed(routings: &[Rc<GroupRouting>], mut stats: PlanStats) -> Routed {
    let makespan = routings.iter().map(|r| r.min_horizon).max().unwrap_or(0);
    let paths: Vec<Vec<Vec<u32>>> = routings.iter().map(|r| r.paths.clone()).collect();
    debug_assert!(
        paths
            .iter()
            .flatten()
            .all(|p| arrival_step(p) <= u64::from(makespan))
    );
    stats.best_lower_bound_steps = makespan;
    Routed {
        paths,
        makespan,
        stats,
    }
}

/// Time-expanded network size times drones past which a leg is big: its exact
/// search takes seconds (1,000 drones in 50 groups on 40×40×10: 230–600 M, 6–11 s
/// a leg), where the suites' legs are at most 72 M (400 drones in 10 groups on
/// 32×32×8) and take under a second.
const BIG_LEG_WORK: u64 = 150_000_000;

/// How long the exact search runs alone before a first plan is made. A first
/// plan costs the exact search a restart (it is capped below the plan it has to
/// beat), so a leg the exact search would finish soon is left to it for a
/// quarter of the deadline, at most 5 s: legs up to a few hundred drones keep
/// their time. A big leg (see [`BIG_LEG_WORK`]) gets its first plan at once.
/// Racing the two on both cores would spare the choice.
fn head_start(space: &Space, cells: &[GroupCells], bound: u32, options: &PlanOptions) -> Duration {
    let drones: usize = cells.iter().map(|g| g.starts.len()).sum();
    if is_big_leg(drones, space, bound) {
        return Duration::ZERO;
    }
    (options.deadline / 4).min(Duration::from_secs(5))
}

/// Whether a leg of `drones` in `space` with a makespan of at least `bound` is
/// big (see [`BIG_LEG_WORK`]): its exact search takes seconds.
pub(super) fn is_big_leg(drones: usize, space: &Space, bound: u32) -> bool {
    drones as u64 * space.len() as u64 * u64::from(bound.max(1)) >= BIG_LEG_WORK
}

/// Until when the exact search may try to beat a first plan reached after `first`
/// of the leg's own work: the deadline when optimality is required (a leg not
/// proven optimal fails the flight anyway). Else the legs still to plan keep
/// three times `first` each for their own first plans (a leg's is about as
/// costly as the next's: the same drones in the same world), and what is left
/// is shared evenly between this leg and them: a leg whose exact search cannot
/// finish (10,000 drones taking off, each its own group) does not starve the rest.
fn improve_until(
    deadline_at: Instant,
    first: Duration,
    legs_after: usize,
    options: &PlanOptions,
) -> Instant {
    if options.require_optimal {
        return deadline_at;
    }
    let reserve = first.saturating_mul(3 * legs_after as u32);
    let now = Instant::now();
    let spare = deadline_at
        .saturating_duration_since(now)
        .saturating_sub(reserve);
    now + spare / (legs_after as u32 + 1)
}

/// The first plan ([`first_plan`]) within the deadline (half of it when optimality
/// is required, so the exact search keeps the other half), and within steps
/// enough for any instance a first plan is good for; with the time it took.
fn first_plan_within(
    space: &Space,
    (cells, lower_bounds, assigned): (&[GroupCells], &[u32], &[Vec<u32>]),
    (started, options): (Instant, &PlanOptions),
    progress: &mut dyn FnMut(&Progress),
) -> Option<(FirstPlan, Duration)> {
    let bound = lower_bounds.iter().copied().max().unwrap_or(0);
    let max_steps = bound.saturating_mul(3).saturating_add(100);
    // Without optimality required, a first plan is worth the whole deadline: no
    // plan at all is the one answer worse than a plan with a gap.
    let until = if options.require_optimal {
        started + options.deadline / 2
    } else {
        started + options.deadline
    };
    let began = Instant::now();
    let mut throttle = Throttle::new();
    let mut on_step = |s: Stepping| {
        if throttle.due() {
            progress(&Progress {
                leg: String::new(),
                phase: PlanPhase::FirstPlan {
                    step: s.step,
                    drones_at_goal: s.at_goal,
                    drones: s.drones,
                },
                ct_nodes_expanded: 0,
                open_nodes: 0,
                best_lower_bound_steps: bound,
                incumbent_steps: None,
                elapsed: started.elapsed(),
            });
        }
    };
    // PIBT is cheap next to the exact search: a stall it cannot finish gets
    // another try with other ties (seeds after the caller's, so deterministic).
    for attempt in 0..FIRST_PLAN_ATTEMPTS {
        let seed = options.seed.wrapping_add(attempt);
        let stepping = (max_steps, until);
        let found = first_plan(space, cells, assigned, stepping, seed, &mut on_step)?;
        if found.complete {
            return Some((found, began.elapsed()));
        }
        // The rest is small, or the exact search would not finish it soon either:
        // ten times what PIBT took (at least 50 ms), at most a quarter of what is
        // left when optimality is required (the search from the start keeps the
        // rest), else half: without it there may be no plan at all.
        let left = until.saturating_duration_since(Instant::now());
        let share = if options.require_optimal {
            left / 4
        } else {
            left / 2
        };
        let budget = (began.elapsed() * 10)
            .max(Duration::from_millis(50))
            .min(share);
        if let Some(done) = finish(space, cells, found, Instant::now() + budget, options) {
            return Some((done, began.elapsed()));
        }
    }
    None
}

/// PIBT runs (each with its exact finish) before a leg goes without a first plan.
const FIRST_PLAN_ATTEMPTS: u64 = 3;

/// A stalled first plan finished by the exact search from where it stalled (see
/// `FirstPlan::complete`): by then most drones are on their goals, so the rest is
/// a small instance over few steps.
fn finish(
    space: &Space,
    cells: &[GroupCells],
    prefix: FirstPlan,
    until: Instant,
    options: &PlanOptions,
) -> Option<FirstPlan> {
    let rest: Vec<GroupCells> = cells
        .iter()
        .zip(&prefix.paths)
        .map(|(group, paths)| {
            let at: Vec<u32> = paths.iter().filter_map(|p| p.last().copied()).collect();
            GroupCells::new(space, at, &group.goals)
        })
        .collect();
    // Each group's farthest drone from its nearest goal: enough to start from.
    let bounds: Vec<u32> = rest
        .iter()
        .map(|g| {
            let far = g.starts.iter().map(|&s| g.to_goal[s as usize]).max();
            far.unwrap_or(0)
        })
        .collect();
    let bound = bounds.iter().copied().max().unwrap_or(0);
    let max_horizon = bound + 2 * space.len() as u32 + 64;
    let remaining = until.checked_duration_since(Instant::now())?;
    let rest_options = PlanOptions {
        deadline: remaining,
        ..options.clone()
    };
    let mut search = Search::new(space, &rest, &bounds, max_horizon, until, &rest_options);
    let routings = search.run(&mut |_| {}).ok()?;
    let tail = routings.iter().map(|r| r.min_horizon).max().unwrap_or(0);
    let paths = prefix
        .paths
        .into_iter()
        .zip(&routings)
        .map(|(group, routing)| {
            group
                .into_iter()
                .zip(&routing.paths)
                .map(|(mut path, rest)| {
                    let last = rest.len() - 1;
                    path.extend((1..=tail as usize).map(|t| rest[t.min(last)]));
                    path
                })
                .collect()
        })
        .collect();
    Some(FirstPlan {
        paths,
        makespan: prefix.makespan + tail,
        complete: true,
    })
}
