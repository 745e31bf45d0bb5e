//! The `fence` section: how far beyond the airspace each autopilot's own fence
//! stands. What it becomes on each vehicle is `fly::fence`'s question.

use super::report::Report;
use crate::mission::schema::FenceSpec;

/// The narrowest fence margin accepted, metres: below it, GPS drift and an
/// autopilot's overshoot (a few tenths of a metre) would breach a fence a
/// vehicle flying its plan never meant to cross.
pub const MIN_FENCE_MARGIN_M: f64 = 0.5;
/// The widest fence margin accepted, metres: beyond it the fence keeps nothing
/// of the mission's airspace.
pub const MAX_FENCE_MARGIN_M: f64 = 100.0;

/// Checks the margin (only when the fence is on: a fence that is off is set on
/// no vehicle).
pub(super) fn check_fence(fence: &FenceSpec, report: &mut Report) {
    let margin_m = fence.margin_m;
    if fence.enabled && !(MIN_FENCE_MARGIN_M..=MAX_FENCE_MARGIN_M).contains(&margin_m) {
        report.add(
            "fence.margin_m",
            format!(
                "must be {MIN_FENCE_MARGIN_M} to {MAX_FENCE_MARGIN_M} m (room beyond the airspace for tracking error and GPS drift), got {margin_m}"
            ),
        );
    }
}
