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
    /// Setpoints streamed in the last second: when, where, and how far along the
    /// route (plan setpoints only).
    setpoint_history: VecDeque<Streamed>,
    /// Times its setpoint waited for the vehicle to come back within the tracking error.
    pub(super) holds: usize,
    /// Seconds its setpoint waited so.
    pub(super) hold_s: f64,
}

/// One setpoint streamed.
#[derive(Debug, Clone, Copy)]
struct Streamed {
    at: Instant,
    position_m: [f64; 3],
    /// Arc length along the route flown then (`None` outside the plan).
    arc_m: Option<f64>,
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

    /// Remembers `last_setpoint`, streamed at `now` (`arc_m` along the route when
    /// it is a plan setpoint), and records the tracking error of the newest sample
    /// in `telemetry` while the drone is `following` our setpoints in the air and
    /// we can see it.
    pub(super) fn sample(
        &mut self,
        now: Instant,
        last_setpoint: Option<(Setpoint, Option<f64>)>,
        following: bool,
        telemetry: &Telemetry,
    ) {
        if let Some((s, arc_m)) = last_setpoint {
            self.setpoint_history.push_back(Streamed {
                at: now,
                position_m: s.position_m,
                arc_m,
            });
        }
        while self
            .setpoint_history
            .front()
            .is_some_and(|s| now.duration_since(s.at) > HISTORY)
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
        let p = telemetry.position_m?;
        Some(distance_m(p, self.compared_with(telemetry)?.position_m))
    }

    /// The route's arc length at the setpoint the newest sample is compared with
    /// (see [`Tracking::distance_m`]), if that was a plan setpoint.
    pub(super) fn compared_arc_m(&self, telemetry: &Telemetry) -> Option<f64> {
        self.compared_with(telemetry)?.arc_m
    }

    /// The setpoint streamed last before the newest sample arrived (the oldest
    /// remembered one if it is older still).
    fn compared_with(&self, telemetry: &Telemetry) -> Option<&Streamed> {
        let received = telemetry.position_received?;
        self.setpoint_history
            .iter()
            .rev()
            .find(|s| s.at <= received)
            .or(self.setpoint_history.front())
    }

    /// A new route (a replan's): arc lengths along the old one mean nothing on it.
    pub(super) fn forget_arcs(&mut self) {
        for s in &mut self.setpoint_history {
            s.arc_m = None;
        }
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
