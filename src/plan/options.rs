//! How to plan: the planner's knobs.

use std::time::Duration;

/// How to plan.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// Give up after this long, reporting the best lower bound proven so far.
    pub deadline: Duration,
    /// Breaks ties between equally good paths; the same seed gives the same plan.
    pub seed: u64,
    /// Once a conflict tree has expanded this many nodes, start the exact method
    /// (impossibility proof, then the SAT encoding) beside it on a second thread;
    /// the first to finish answers (`None`: never, CBM alone; for comparison).
    pub exact_after_ct_nodes: Option<u64>,
    /// Start each leg with a fast first plan (PIBT towards assigned goals) that
    /// the exact search then has to beat (`false`: the exact search alone, as
    /// before anytime planning; for comparison).
    pub first_plan: bool,
    /// Fail rather than return a plan not proven makespan-optimal. Without it,
    /// a leg whose exact search is still running at the deadline keeps its first
    /// plan, and the plan states its gap to the best lower bound proven.
    pub require_optimal: bool,
    /// Time the caller needs after planning for every drone and step of the plan
    /// (to schedule and check it), kept out of `deadline`: the planner stops
    /// improving early enough that planning and that work together end by the
    /// deadline. Zero: the deadline is the planner's alone.
    pub reserve_per_drone_step: Duration,
}

impl Default for PlanOptions {
    /// A minute of search, seed 0, the SAT encoding after 256 conflict-tree nodes,
    /// a first plan, the best plan by the deadline, nothing reserved after it:
    /// enough for the bundled missions, deterministic.
    fn default() -> Self {
        Self {
            deadline: Duration::from_secs(60),
            seed: 0,
            exact_after_ct_nodes: Some(256),
            first_plan: true,
            require_optimal: false,
            reserve_per_drone_step: Duration::ZERO,
        }
    }
}
