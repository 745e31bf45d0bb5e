//! Tracking error: how far the vehicle's telemetry is from the setpoint that was
//! being streamed to it when the sample arrived, while it flies on our setpoints.
//! Real autopilots lag and overshoot; the schedule keeps setpoints apart by the
//! safety distance plus twice the mission's tracking error, so separation holds
//! only while every vehicle stays within that of its setpoint. The plan holds a
//! drone's setpoint while it strays further (`plan`), and the summary reports the
//! error per drone and whether the bound held. One drone's record of all this is a
//! [`Tracking`], owned by its `DroneRun`.
//!
//! A sample is compared with the setpoint streamed before it arrived, not the one
//! streamed this tick: telemetry is up to a period old when it is read, and
//! comparing it with a newer setpoint would charge the vehicle with our own delay.

use super::telemetry::Telemetry;
use crate::fly::follower::Setpoint;
use crate::fly::log::TrackingError;
use crate::fly::path::distance_m;
use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// How long streamed setpoints are remembered.
const HISTORY: Duration = Duration::from_secs(1);

/// One drone's tracking error: the setpoints recently streamed to it, the errors
/// recorded, and how often its setpoint held for it.
pub(super) struct Tracking {
    /// Distances from telemetry to the streamed setpoint, metres.
    errors_m: Vec<f64>,
    /// Setpoints streamed in the last second, with when.
    setpoint_history: VecDeque<(Instant, [f64; 3])>,
    /// Times its setpoint waited for the vehicle to come back within the tracking error.
    pub(super) holds: usize,
    /// Seconds its setpoint waited so.
    pub(super) hold_s: f64,
}

impl Tracking {
    /// Nothing streamed or recorded yet.
    pub(super) fn new() -> Self {
        Self {
            errors_m: Vec::new(),
            setpoint_history: VecDeque::new(),
            holds: 0,
            hold_s: 0.0,
        }
    }

    /// Remembers `last_setpoint`, streamed at `now`, and records the tracking error
    /// of the newest sample in `telemetry` while the drone is `following` our
    /// setpoints in the air and we can see it.
    pub(super) fn sample(
        &mut self,
        now: Instant,
        last_setpoint: Option<Setpoint>,
        following: bool,
        telemetry: &Telemetry,
    ) {
        if let Some(s) = last_setpoint {
            self.setpoint_history.push_back((now, s.position_m));
        }
        while self
            .setpoint_history
            .front()
            .is_some_and(|(t, _)| now.duration_since(*t) > HISTORY)
        {
            self.setpoint_history.pop_front();
        }
        if !following || telemetry.stale || telemetry.link_lost {
            return;
        }
        if let Some(e) = self.distance_m(telemetry) {
            self.errors_m.push(e);
        }
    }

    /// Distance from the newest position sample to the setpoint streamed last before
    /// it arrived (the oldest remembered one if it is older still), metres.
    pub(super) fn distance_m(&self, telemetry: &Telemetry) -> Option<f64> {
        let (p, received) = (telemetry.position_m?, telemetry.position_received?);
        let setpoint = self
            .setpoint_history
            .iter()
            .rev()
            .find(|(t, _)| *t <= received)
            .or(self.setpoint_history.front())?
            .1;
        Some(distance_m(p, setpoint))
    }

    /// Median, 95th percentile and maximum of the recorded tracking error (`None`
    /// before any sample).
    pub(super) fn error(&self) -> Option<TrackingError> {
        let mut sorted = self.errors_m.clone();
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
