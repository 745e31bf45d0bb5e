//! Hands the flight to its observers as it happens: each drone's newest
//! telemetry sample (once), the new log events, and the status once per tick.

use super::drone::DroneRun;
use super::log::LogEvent;
use super::observer::{FlightObserver, FlightStatus};
use std::sync::Arc;
use std::time::Instant;

/// What the observers have been given so far: the newest sample per drone and
/// the number of events.
pub struct Tap {
    last_sample: Vec<Option<Instant>>,
    events_sent: usize,
}

impl Tap {
    /// Nothing handed over yet, for `drones` drones.
    pub fn new(drones: usize) -> Self {
        Self {
            last_sample: vec![None; drones],
            events_sent: 0,
        }
    }

    /// Hands over each drone's newest telemetry (once) and the events since last time.
    pub fn forward(
        &mut self,
        observers: &[Arc<dyn FlightObserver>],
        drones: &[DroneRun],
        armed_at: Instant,
        events: &[LogEvent],
    ) {
        for ((d, last), i) in drones.iter().zip(self.last_sample.iter_mut()).zip(0..) {
            let Some(p) = d.session().state().position else {
                continue;
            };
            if *last == Some(p.received) {
                continue;
            }
            *last = Some(p.received);
            let t_s = p.received.saturating_duration_since(armed_at).as_secs_f64();
            let position_m = d.frame().mission_from_local(p.position_ned_m);
            for o in observers {
                o.sample(i, t_s, position_m);
            }
        }
        for e in &events[self.events_sent.min(events.len())..] {
            for o in observers {
                o.event(e);
            }
        }
        self.events_sent = events.len();
    }

    /// The swarm's status to every observer that wants it (built only if one does).
    pub fn status(
        observers: &[Arc<dyn FlightObserver>],
        drones: &[DroneRun],
        since_arm_s: f64,
        t_exec_s: Option<f64>,
        min_separation_m: f64,
        min_scaled_separation: Option<f64>,
    ) {
        if !observers.iter().any(|o| o.wants_status()) {
            return;
        }
        let status = FlightStatus {
            since_arm_s,
            t_exec_s,
            min_separation_m,
            min_scaled_separation,
            drones: drones.iter().map(DroneRun::status).collect(),
        };
        for o in observers.iter().filter(|o| o.wants_status()) {
            o.status(&status);
        }
    }
}
