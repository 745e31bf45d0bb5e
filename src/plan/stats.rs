//! What the planner reports about its search: counters at the end, progress on the way.

use std::time::Duration;

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
    /// Wall time inside the low level (serialised as `low_level_time_s`, seconds).
    #[serde(rename = "low_level_time_s", serialize_with = "as_seconds")]
    pub low_level_time: Duration,
    /// Wall time of the whole call, from the lower bounds to the plan (serialised as
    /// `total_time_s`, seconds).
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

/// Reported while the search runs, a few times a second, so a long search can show
/// that it is alive and how close it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Progress {
    /// Conflict-tree nodes expanded so far.
    pub ct_nodes_expanded: u64,
    /// Nodes waiting on the open list: how wide the search currently is.
    pub open_nodes: usize,
    /// The makespan proven unavoidable so far, steps.
    pub best_lower_bound_steps: u32,
    /// Time since the search started.
    pub elapsed: Duration,
}
