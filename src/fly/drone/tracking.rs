//! Tracking error: how far the vehicle's telemetry is from the setpoint that was
//! being streamed to it when the sample arrived, while it flies on our setpoints.
//! Real autopilots lag and overshoot; the schedule keeps setpoints apart by the
//! safety distance plus twice the mission's tracking error, so separation holds
//! only while every vehicle stays within that of its setpoint. The plan holds a
//! drone's setpoint while it strays further (`plan`), and the summary reports the
//! error per drone and whether the bound held.
//!
//! A sample is compared with the setpoint streamed before it arrived, not the one
//! streamed this tick: telemetry is up to a period old when it is read, and
//! comparing it with a newer setpoint would charge the vehicle with our own delay.

use super::DroneRun;
use crate::fly::log::TrackingError;
use crate::fly::path::distance_m;
use crate::fly::phase::Phase;
use std::time::{Duration, Instant};

/// How long streamed setpoints are remembered.
const HISTORY: Duration = Duration::from_secs(1);

impl DroneRun {
    /// Remembers the setpoint streamed at `now` and records the tracking error of
    /// the newest sample, in the phases where the drone follows our setpoints in the
    /// air.
    pub fn sample_tracking(&mut self, now: Instant) {
        if let Some(s) = self.last_setpoint {
            self.setpoint_history.push_back((now, s.position_m));
        }
        while self
            .setpoint_history
            .front()
            .is_some_and(|(t, _)| now.duration_since(*t) > HISTORY)
        {
            self.setpoint_history.pop_front();
        }
        let following = matches!(self.phase, Phase::Flying | Phase::AtStart | Phase::AtGoal);
        if !following || self.telemetry_stale || self.link_lost {
            return;
        }
        if let Some(e) = self.tracking_distance_m() {
            self.tracking_m.push(e);
        }
    }

    /// Distance from the newest position sample to the setpoint streamed last before
    /// it arrived (the oldest remembered one if it is older still), metres.
    pub fn tracking_distance_m(&self) -> Option<f64> {
        let (p, received) = (self.position_m?, self.position_received?);
        let setpoint = self
            .setpoint_history
            .iter()
            .rev()
            .find(|(t, _)| *t <= received)
            .or(self.setpoint_history.front())?
            .1;
        Some(distance_m(p, setpoint))
    }

    /// Times its setpoint waited for the vehicle to come back within the bound.
    pub fn tracking_holds(&self) -> usize {
        self.tracking_holds
    }

    /// Seconds its setpoint waited so.
    pub fn tracking_hold_s(&self) -> f64 {
        self.tracking_hold_s
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
