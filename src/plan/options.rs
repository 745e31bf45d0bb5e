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
}

impl Default for PlanOptions {
    /// A minute of search, seed 0, the SAT encoding after 256 conflict-tree nodes:
    /// enough for the bundled missions, deterministic.
    fn default() -> Self {
        Self {
            deadline: Duration::from_secs(60),
            seed: 0,
            exact_after_ct_nodes: Some(256),
        }
    }
}
