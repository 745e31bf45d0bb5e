//! The periodic-message schedule of one vehicle: which telemetry streams at
//! which rate (changed by MAV_CMD_SET_MESSAGE_INTERVAL) and when each is due.
//!
//! It only knows message ids and periods; building the messages from the
//! vehicle's state is the job of the `telemetry` module.

use rand::Rng;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Message ids the vehicle can produce.
pub mod id {
    /// HEARTBEAT.
    pub const HEARTBEAT: u32 = 0;
    /// SYS_STATUS.
    pub const SYS_STATUS: u32 = 1;
    /// SYSTEM_TIME.
    pub const SYSTEM_TIME: u32 = 2;
    /// ATTITUDE.
    pub const ATTITUDE: u32 = 30;
    /// LOCAL_POSITION_NED.
    pub const LOCAL_POSITION_NED: u32 = 32;
    /// GLOBAL_POSITION_INT.
    pub const GLOBAL_POSITION_INT: u32 = 33;
    /// GPS_GLOBAL_ORIGIN: where the local frame is zero.
    pub const GPS_GLOBAL_ORIGIN: u32 = 49;
    /// BATTERY_STATUS.
    pub const BATTERY_STATUS: u32 = 147;
    /// AUTOPILOT_VERSION (on request only).
    pub const AUTOPILOT_VERSION: u32 = 148;
    /// HOME_POSITION.
    pub const HOME_POSITION: u32 = 242;
    /// EXTENDED_SYS_STATE.
    pub const EXTENDED_SYS_STATE: u32 = 245;
}

/// One periodic message.
#[derive(Debug, Clone, PartialEq)]
struct Stream {
    message_id: u32,
    default_period_s: f64,
    /// Current period; `None` when disabled by an interval of -1.
    period_s: Option<f64>,
    next_due_s: f64,
}

/// The periodic-message schedule of one vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct Streams {
    entries: Vec<Stream>,
}

impl Streams {
    /// Default schedule: heartbeat, status and home at 1 Hz or slower,
    /// landed state at 5 Hz, position and attitude at `telemetry_rate_hz`.
    /// Each stream starts at a seed-dependent phase so a swarm does not send
    /// in bursts on the same tick.
    pub fn new(seed: u64, telemetry_rate_hz: f64) -> Self {
        let fast_s = 1.0 / telemetry_rate_hz;
        let defaults = [
            (id::HEARTBEAT, 1.0),
            (id::SYS_STATUS, 1.0),
            (id::SYSTEM_TIME, 1.0),
            (id::ATTITUDE, fast_s),
            (id::LOCAL_POSITION_NED, fast_s),
            (id::GLOBAL_POSITION_INT, fast_s),
            (id::BATTERY_STATUS, 1.0),
            (id::HOME_POSITION, 2.0),
            (id::GPS_GLOBAL_ORIGIN, 5.0),
            (id::EXTENDED_SYS_STATE, 0.2),
        ];
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed_57a7);
        let entries = defaults
            .into_iter()
            .map(|(message_id, period_s)| Stream {
                message_id,
                default_period_s: period_s,
                period_s: Some(period_s),
                // The first heartbeat goes out at once so peers discover us quickly.
                next_due_s: if message_id == id::HEARTBEAT {
                    0.0
                } else {
                    rng.random::<f64>() * period_s
                },
            })
            .collect();
        Self { entries }
    }

    /// Applies MAV_CMD_SET_MESSAGE_INTERVAL: `interval_us` -1 disables, 0
    /// restores the default, > 0 sets the period. False if `message_id` is not streamable.
    pub fn set_interval(&mut self, message_id: u32, interval_us: f32) -> bool {
        let Some(stream) = self.entries.iter_mut().find(|s| s.message_id == message_id) else {
            return false;
        };
        stream.period_s = if interval_us == -1.0 {
            None
        } else if interval_us == 0.0 || !interval_us.is_finite() {
            Some(stream.default_period_s)
        } else if interval_us > 0.0 {
            // Faster than 1 kHz makes no sense for a 100 Hz simulation.
            Some((f64::from(interval_us) / 1e6).max(1e-3))
        } else {
            return false;
        };
        true
    }

    /// Current period of a stream in seconds (`None` if disabled or unknown).
    pub fn period_s(&self, message_id: u32) -> Option<f64> {
        self.entries
            .iter()
            .find(|s| s.message_id == message_id)
            .and_then(|s| s.period_s)
    }

    /// Ids of the streams due at `now_s`, advancing their schedule.
    pub(crate) fn take_due(&mut self, now_s: f64, due: &mut Vec<u32>) {
        for s in &mut self.entries {
            let Some(period_s) = s.period_s else { continue };
            if now_s + 1e-9 >= s.next_due_s {
                due.push(s.message_id);
                s.next_due_s += period_s;
                if s.next_due_s < now_s {
                    s.next_due_s = now_s + period_s; // fell behind: do not burst
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_disable_restore_and_reject_unknown() {
        let mut s = Streams::new(1, 20.0);
        assert_eq!(s.period_s(id::LOCAL_POSITION_NED), Some(0.05));
        assert!(s.set_interval(id::LOCAL_POSITION_NED, 100_000.0));
        assert_eq!(s.period_s(id::LOCAL_POSITION_NED), Some(0.1));
        assert!(s.set_interval(id::LOCAL_POSITION_NED, -1.0));
        assert_eq!(s.period_s(id::LOCAL_POSITION_NED), None);
        assert!(s.set_interval(id::LOCAL_POSITION_NED, 0.0));
        assert_eq!(s.period_s(id::LOCAL_POSITION_NED), Some(0.05));
        assert!(!s.set_interval(12345, 1000.0));
    }

    #[test]
    fn due_streams_follow_their_rates() {
        let mut s = Streams::new(7, 20.0);
        let mut counts = std::collections::HashMap::new();
        let mut due = Vec::new();
        for step in 0..1000 {
            due.clear();
            s.take_due(f64::from(step) * 0.01, &mut due);
            for id in &due {
                *counts.entry(*id).or_insert(0) += 1;
            }
        }
        // 10 s of simulated time.
        assert!(
            (199..=201).contains(&counts[&id::LOCAL_POSITION_NED]),
            "{counts:?}"
        );
        assert!((10..=11).contains(&counts[&id::HEARTBEAT]), "{counts:?}");
        assert!((5..=6).contains(&counts[&id::HOME_POSITION]), "{counts:?}");
    }
}
