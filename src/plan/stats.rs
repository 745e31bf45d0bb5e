//! What the planner reports about its search: counters at the end, progress on the way.

use std::time::{Duration, Instant};

/// Counters describing the search, for reports and benchmarks.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct PlanStats {
    /// Makespan lower bound before search (bottleneck assignment, collisions ignored).
    pub initial_lower_bound_steps: u32,
    /// Highest makespan of any conflict-tree node expanded: a proven lower bound.
    pub best_lower_bound_steps: u32,
    /// Conflict-tree nodes taken off the open list and branched on; the search's size.
    pub ct_nodes_expanded: u64,
    /// Conflict-tree nodes created (root and children); more than expanded when the
    /// search ends with nodes still open.
    pub ct_nodes_generated: u64,
    /// Calls to the low level (one group's flow, for a horizon or a routing).
    pub low_level_calls: u64,
    /// Augmenting paths found by the low level's flow algorithms, summed over calls.
    pub flow_augmentations: u64,
    /// Horizons the exact SAT encoding decided (0 when the conflict tree finished
    /// within its node budget).
    pub sat_horizons: u64,
    /// Wall time in the SAT encoding and solver (serialised as `sat_time_s`, seconds).
    #[serde(rename = "sat_time_s", serialize_with = "as_seconds")]
    pub sat_time: Duration,
    /// Wall time inside the low level (serialised as `low_level_time_s`, seconds).
    #[serde(rename = "low_level_time_s", serialize_with = "as_seconds")]
    pub low_level_time: Duration,
    /// The first plan's makespan, steps (`None`: no first plan was made or found).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first_plan_steps: Option<u32>,
    /// Wall time making the first plan (serialised as `first_plan_time_s`, seconds).
    #[serde(rename = "first_plan_time_s", serialize_with = "as_seconds")]
    pub first_plan_time: Duration,
    /// Whether the first plan flew straight lines (open sky: nothing between the
    /// formations) rather than PIBT's steps; for a whole flight, how many legs did.
    #[serde(skip_serializing_if = "is_zero")]
    pub straight_line_legs: u32,
    /// Wall time of the whole call, from the lower bounds to the plan (serialised as
    /// `total_time_s`, seconds).
    #[serde(rename = "total_time_s", serialize_with = "as_seconds")]
    pub total_time: Duration,
    /// One entry per leg of a whole flight (empty for a single TAPF instance).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub legs: Vec<LegStats>,
}

/// How one leg's search went.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct LegStats {
    /// The leg's name.
    pub name: String,
    /// Its makespan, steps.
    pub makespan_steps: u32,
    /// Its lower bound before search, steps.
    pub lower_bound_steps: u32,
    /// The largest makespan proven unavoidable, steps: its makespan when the leg
    /// is proven optimal.
    pub proven_bound_steps: u32,
    /// Its first plan's makespan, steps, if one was made.
    pub first_plan_steps: Option<u32>,
    /// Time to its first plan (serialised as `first_plan_time_s`, seconds).
    #[serde(rename = "first_plan_time_s", serialize_with = "as_seconds")]
    pub first_plan_time: Duration,
    /// Whether its first plan flew straight lines (open sky).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub straight_lines: bool,
    /// Conflict-tree nodes expanded for it.
    pub ct_nodes_expanded: u64,
    /// Its planning time (serialised as `time_s`, seconds).
    #[serde(rename = "time_s", serialize_with = "as_seconds")]
    pub time: Duration,
}

fn is_zero(n: &u32) -> bool {
    *n == 0
}

fn as_seconds<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64())
}

impl PlanStats {
    /// Adds one leg's search to a whole flight's figures: counters and times add up,
    /// bounds are the legs' sums (legs are flown one after the other).
    pub fn add_leg(&mut self, name: &str, leg: &PlanStats, makespan_steps: u32) {
        self.initial_lower_bound_steps += leg.initial_lower_bound_steps;
        self.best_lower_bound_steps += leg.best_lower_bound_steps;
        self.ct_nodes_expanded += leg.ct_nodes_expanded;
        self.ct_nodes_generated += leg.ct_nodes_generated;
        self.low_level_calls += leg.low_level_calls;
        self.flow_augmentations += leg.flow_augmentations;
        self.low_level_time += leg.low_level_time;
        self.sat_horizons += leg.sat_horizons;
        self.sat_time += leg.sat_time;
        self.first_plan_time += leg.first_plan_time;
        self.straight_line_legs += leg.straight_line_legs;
        self.first_plan_steps = match (self.first_plan_steps, leg.first_plan_steps) {
            (None, _) if !self.legs.is_empty() => None,
            (Some(total), Some(steps)) => Some(total + steps),
            (None, steps) => steps,
            (Some(_), None) => None,
        };
        self.legs.push(LegStats {
            name: name.to_string(),
            makespan_steps,
            lower_bound_steps: leg.initial_lower_bound_steps,
            proven_bound_steps: leg.best_lower_bound_steps,
            first_plan_steps: leg.first_plan_steps,
            first_plan_time: leg.first_plan_time,
            straight_lines: leg.straight_line_legs > 0,
            ct_nodes_expanded: leg.ct_nodes_expanded,
            time: leg.total_time,
        });
    }

    /// Time spent in the conflict tree itself (conflict detection, bookkeeping).
    pub fn high_level_time(&self) -> Duration {
        self.total_time.saturating_sub(self.low_level_time)
    }
}

/// Reported while the search runs, a few times a second, so a long search can show
/// that it is alive, what it is doing and how close it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Progress {
    /// The leg of the flight being planned (empty for a single TAPF instance).
    pub leg: String,
    /// What the planner is doing.
    pub phase: PlanPhase,
    /// Conflict-tree nodes expanded so far.
    pub ct_nodes_expanded: u64,
    /// Nodes waiting on the open list: how wide the search currently is.
    pub open_nodes: usize,
    /// The makespan proven unavoidable so far, steps.
    pub best_lower_bound_steps: u32,
    /// The best plan found so far, its makespan, steps (`None`: none yet).
    pub incumbent_steps: Option<u32>,
    /// Time since the search started.
    pub elapsed: Duration,
}

/// The planner's phases, in order, with how far each has got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanPhase {
    /// Bounding each group's makespan, collisions ignored.
    LowerBounds {
        /// Groups bounded so far.
        groups_done: usize,
        /// Groups in the leg.
        groups: usize,
    },
    /// A first plan, fast: every drone stepping towards its goal.
    FirstPlan {
        /// Steps planned so far.
        step: u32,
        /// Drones at their goals after them.
        drones_at_goal: usize,
        /// Drones in the leg.
        drones: usize,
    },
    /// The conflict tree's root, first part: each group's least horizon on its own,
    /// grown one step at a time from its lower bound.
    Horizons {
        /// Groups whose horizon is known.
        groups_done: usize,
        /// Groups in the leg.
        groups: usize,
        /// The horizon the current group is being tried at, steps.
        horizon_steps: u32,
    },
    /// The root, second part: each group routed at the largest of those horizons,
    /// around the groups routed before it.
    Routings {
        /// Groups routed so far.
        groups_done: usize,
        /// Groups in the leg.
        groups: usize,
        /// The horizon every group is routed at, steps.
        horizon_steps: u32,
        /// Drones of the group being routed that have their path so far.
        drones_routed: usize,
        /// Drones in that group.
        drones: usize,
    },
    /// Resolving conflicts between groups.
    ConflictTree,
}

impl std::fmt::Display for PlanPhase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            PlanPhase::LowerBounds {
                groups_done,
                groups,
            } => write!(f, "lower bounds, {groups_done}/{groups} groups"),
            PlanPhase::Horizons {
                groups_done,
                groups,
                horizon_steps,
            } => write!(
                f,
                "each group's least horizon, {groups_done}/{groups} done, trying {horizon_steps} steps"
            ),
            PlanPhase::Routings {
                groups_done,
                groups,
                horizon_steps,
                drones_routed,
                drones,
            } => write!(
                f,
                "routing each group at {horizon_steps} steps, {groups_done}/{groups} done \
                 ({drones_routed}/{drones} drones of the next)"
            ),
            PlanPhase::FirstPlan {
                step,
                drones_at_goal,
                drones,
            } => write!(
                f,
                "first plan, step {step}, {drones_at_goal}/{drones} drones at their goals"
            ),
            PlanPhase::ConflictTree => write!(f, "conflict tree"),
        }
    }
}

/// Lets progress reports through a few times a second.
#[derive(Debug)]
pub(crate) struct Throttle {
    last: Instant,
}

impl Throttle {
    /// How often a report is let through.
    const EVERY: Duration = Duration::from_millis(200);

    pub(crate) fn new() -> Self {
        Self {
            last: Instant::now(),
        }
    }

    /// True when the last report let through is `EVERY` old.
    pub(crate) fn due(&mut self) -> bool {
        let due = self.last.elapsed() >= Self::EVERY;
        if due {
            self.last = Instant::now();
        }
        due
    }
}
