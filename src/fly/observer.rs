//! A live tap on a flight: telemetry samples and events as they happen, for a
//! recorder or a dashboard.
//!
//! The executor calls these from its control loop, between setpoint ticks, so an
//! implementation must return at once: queue the data (a bounded channel with
//! `try_send`) and drop it when the queue is full, never block or wait for I/O.

use super::log::LogEvent;

/// Receives a flight as it happens. See the module docs: never block.
pub trait FlightObserver: Send + Sync {
    /// A new position from drone `drone` (index in plan order), `t_s` seconds after
    /// the first arm command, ENU metres.
    fn sample(&self, drone: usize, t_s: f64, position_m: [f64; 3]);

    /// A flight event, the same that goes into the flight log.
    fn event(&self, event: &LogEvent);
}
