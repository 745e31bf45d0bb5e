//! A live tap on a flight: telemetry samples and events as they happen, for a
//! recorder or a dashboard.
//!
//! The executor calls these from its control loop, between setpoint ticks, so an
//! implementation must return at once: queue the data (a bounded channel with
//! `try_send`) and drop it when the queue is full, never block or wait for I/O.

use super::log::LogEvent;

/// What a status view shows about one drone.
#[derive(Debug, Clone)]
pub struct DroneStatus {
    /// The drone's mission id.
    pub id: String,
    /// Its phase's name (`LINK LOST` while its link is down, `LOST` once given up).
    pub phase: &'static str,
    /// Share of its TPG events observed reached, 0–1.
    pub progress: f64,
    /// Scheduled time of its next event on the plan clock, if any remain.
    pub next_reach_s: Option<f64>,
    /// Index (plan order) of the drone it is waiting for at a closed gate.
    pub waiting_for: Option<u32>,
}

/// The whole swarm at one control tick, for a live status view.
#[derive(Debug, Clone)]
pub struct FlightStatus {
    /// Seconds since the first arm command.
    pub since_arm_s: f64,
    /// Seconds on the plan clock, once every drone is at its start.
    pub t_exec_s: Option<f64>,
    /// Smallest separation measured so far, metres (∞ before two drones fly).
    pub min_separation_m: f64,
    /// Under an ellipsoidal separation, the smallest scaled separation so far
    /// (separated at 1 or more; ∞ before two drones fly); `None` for a sphere.
    pub min_scaled_separation: Option<f64>,
    /// Every drone, in plan order.
    pub drones: Vec<DroneStatus>,
}

/// Receives a flight as it happens. See the module docs: never block.
pub trait FlightObserver: Send + Sync {
    /// A new position from drone `drone` (index in plan order), `t_s` seconds after
    /// the first arm command, ENU metres.
    fn sample(&self, drone: usize, t_s: f64, position_m: [f64; 3]);

    /// A flight event, the same that goes into the flight log.
    fn event(&self, event: &LogEvent);

    /// The swarm's state, once per control tick. Ignored unless overridden.
    fn status(&self, status: &FlightStatus) {
        let _ = status;
    }

    /// Whether [`FlightObserver::status`] wants calls: building the status costs a
    /// string per drone per tick, so observers that ignore it say so.
    fn wants_status(&self) -> bool {
        false
    }
}
