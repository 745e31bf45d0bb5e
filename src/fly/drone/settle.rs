//! Arriving by measurement: a drone is at a point only when telemetry shows it
//! within tolerance *and* slow, and it has stayed so for a moment. An overshooting
//! drone passing through its goal is not "arrived", and no drone is told to land
//! while it still moves.

use super::telemetry::Telemetry;
use crate::fly::path::distance_m;
use std::time::{Duration, Instant};

/// Telemetry speed at or below this counts as at rest, m/s: well above a hovering
/// vehicle's velocity noise, well below any planned motion.
pub const REST_SPEED_MPS: f64 = 0.15;

/// How long a drone must stay within tolerance and at rest to count as there.
pub const SETTLE_HOLD: Duration = Duration::from_millis(300);

/// Since when telemetry has shown a drone where it is going and at rest.
#[derive(Debug, Default)]
pub(super) struct Settling {
    since: Option<Instant>,
}

impl Settling {
    /// True once `telemetry` has shown the drone within `tolerance_m` of `point_m`
    /// and at rest for [`SETTLE_HOLD`] without a break.
    pub(super) fn at(
        &mut self,
        telemetry: &Telemetry,
        point_m: [f64; 3],
        tolerance_m: f64,
    ) -> bool {
        let here = telemetry
            .position_m
            .is_some_and(|p| distance_m(p, point_m) <= tolerance_m);
        if !(here && telemetry.speed_mps() <= REST_SPEED_MPS) {
            self.since = None;
            return false;
        }
        let now = Instant::now();
        let since = *self.since.get_or_insert(now);
        now.duration_since(since) >= SETTLE_HOLD
    }

    /// Going somewhere new: arriving starts over.
    pub(super) fn restart(&mut self) {
        self.since = None;
    }
}
