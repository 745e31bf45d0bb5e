//! Whether a drone is still in the plan, and why not: retired early (and then
//! released once down), or left out by a replan.

use crate::fly::phase::Retirement;

/// Whether a drone is still in the plan, and why not.
#[derive(Debug, Default)]
pub(super) struct Membership {
    /// Why the drone left its plan early, if it did.
    pub(super) retired: Option<Retirement>,
    /// A retired drone's remaining events have been released (it is down).
    pub(super) released: bool,
    /// A replan flies on without it (lost, or retired and down).
    pub(super) left_plan: bool,
}
