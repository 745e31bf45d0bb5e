//! Tracking error: how far the vehicle's telemetry is from the setpoint being
//! streamed to it, while it flies on our setpoints. Real autopilots lag and
//! overshoot; the schedule's separation argument holds only while this stays small,
//! so the summary reports it per drone.

use super::DroneRun;
use crate::fly::log::TrackingError;
use crate::fly::path::distance_m;
use crate::fly::phase::Phase;

impl DroneRun {
    /// Records the distance from telemetry to the current setpoint, in the phases
    /// where the drone follows our setpoints in the air.
    pub fn sample_tracking(&mut self) {
        let following = matches!(self.phase, Phase::Flying | Phase::AtStart | Phase::AtGoal);
        if !following || self.telemetry_stale || self.link_lost {
            return;
        }
        if let (Some(p), Some(s)) = (self.position_m, self.last_setpoint) {
            self.tracking_m.push(distance_m(p, s.position_m));
        }
    }

    /// Median, 95th percentile and maximum of the recorded tracking error (`None`
    /// before any sample).
    pub fn tracking_error(&self) -> Option<TrackingError> {
        let mut sorted = self.tracking_m.clone();
        sorted.sort_by(f64::total_cmp);
        let at = |q: f64| {
            let i = ((sorted.len() - 1) as f64 * q).round() as usize;
            sorted[i.min(sorted.len() - 1)]
        };
        (!sorted.is_empty()).then(|| TrackingError {
            median_m: at(0.5),
            p95_m: at(0.95),
            max_m: at(1.0),
        })
    }
}
