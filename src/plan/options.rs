//! How to plan: the planner's knobs.

use std::time::Duration;

/// How to plan.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// Give up after this long, reporting the best lower bound proven so far.
    pub deadline: Duration,
    /// Breaks ties between equally good paths; the same seed gives the same plan.
    pub seed: u64,
}

impl Default for PlanOptions {
    /// A minute of search and seed 0: enough for the bundled missions, deterministic.
    fn default() -> Self {
        Self {
            deadline: Duration::from_secs(60),
            seed: 0,
        }
    }
}
