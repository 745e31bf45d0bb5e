//! The exact method on its second thread: a bounded proof of impossibility, then
//! the SAT encoding horizon by horizon, stopped when the tree finishes first.

use crate::plan::feasibility::impossible_groups;
use crate::plan::network::GroupCells;
use crate::plan::sat::{self, SatOutcome, SatWork};
use crate::plan::space::Space;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Arrangements the impossibility proof may visit at the hand-over (a few tens of
/// milliseconds): enough for corridors and rings, far too few to waste time on a
/// large instance.
const PROOF_BUDGET: u64 = 20_000;

/// What the exact method found on its thread.
pub(crate) struct Exact {
    /// The groups proven unable to reach their goals together, and the arrangements
    /// searched to prove it.
    pub(super) impossible: Option<(Vec<usize>, u64)>,
    /// The SAT encoding's answer, when it ran.
    pub(super) outcome: Option<SatOutcome>,
    /// What the SAT encoding did, for the planner's counters.
    pub(super) work: SatWork,
    /// How long the exact method ran.
    pub(super) time: Duration,
}

/// The exact method: first the impossibility proof (a bounded search of every
/// arrangement), then the SAT encoding horizon by horizon from `from`.
pub(super) fn exact(
    space: &Space,
    groups: &[GroupCells],
    from: u32,
    max_horizon: u32,
    until: (Instant, &AtomicBool),
) -> Exact {
    let started = Instant::now();
    let mut work = SatWork::default();
    if let Some(found) = impossible_groups(space, groups, PROOF_BUDGET) {
        return Exact {
            impossible: Some(found),
            outcome: None,
            work,
            time: started.elapsed(),
        };
    }
    let outcome = sat::solve(space, groups, from, max_horizon, until, &mut work);
    Exact {
        impossible: None,
        outcome: Some(outcome),
        work,
        time: started.elapsed(),
    }
}

/// Sets its flag when dropped: the exact method's thread stops on every way out of
/// the tree search.
pub(super) struct StopOnDrop<'s>(pub(super) &'s AtomicBool);

impl Drop for StopOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}
