//! A plan started at a known instant (`fly --start-at`), so a flight can run to
//! music, a camera or another system's clock.
//!
//! ```text
//! pre-flight (must pass by `at − takeoff_lead`) ─► wait on the ground ─► arm and
//!   take off at `at − takeoff_lead` ─► hover above the pads ─► plan time 0 at `at`
//! ```
//!
//! A swarm that cannot be above its pads by `at` is refused before anybody arms:
//! pre-flight is given only until `at − takeoff_lead`, and its error names every
//! drone not ready by then. A drone that arms but is still not above its pad at
//! `at` aborts the flight (everyone holds, then lands), naming the late drones: a
//! show that starts late is a failed show, and starting without a drone would fly
//! a plan whose gates wait for it.

use super::error::FlyError;
use std::time::{Duration, Instant, SystemTime};

/// When plan execution starts, and how long before it the swarm takes off.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StartAt {
    /// Plan time 0, wall clock.
    pub at: SystemTime,
    /// How long before `at` the swarm arms and takes off: enough for every
    /// vehicle to arm, climb to its pad-layer cell and settle there.
    pub takeoff_lead: Duration,
}

impl StartAt {
    /// Takeoff lead by default: the bundled simulator is above its pads 4 s after
    /// arming, ArduCopter and PX4 SITL within 15 s.
    pub const DEFAULT_TAKEOFF_LEAD: Duration = Duration::from_secs(20);

    /// Starts at `at` with the default takeoff lead.
    pub fn new(at: SystemTime) -> Self {
        Self {
            at,
            takeoff_lead: Self::DEFAULT_TAKEOFF_LEAD,
        }
    }

    /// Time left, from `now`, until the swarm must arm; an error when that moment
    /// has passed (`preflight_done`: pre-flight has run, it took too long).
    pub(super) fn until_arming(
        &self,
        now: SystemTime,
        preflight_done: bool,
    ) -> Result<Duration, FlyError> {
        let arm_at = self.at.checked_sub(self.takeoff_lead).unwrap_or(self.at);
        arm_at
            .duration_since(now)
            .map_err(|_| FlyError::StartTooSoon {
                start_in_s: signed_s(self.at, now),
                takeoff_lead_s: self.takeoff_lead.as_secs_f64(),
                after_preflight: preflight_done,
            })
    }

    /// `at` on the monotonic clock the flight loop runs on.
    pub(super) fn instant(&self) -> Instant {
        let now = Instant::now();
        match self.at.duration_since(SystemTime::now()) {
            Ok(ahead) => now + ahead,
            Err(past) => now.checked_sub(past.duration()).unwrap_or(now),
        }
    }
}

/// Waits on the ground until it is time to arm for `start`, or returns at once
/// without one. An abort while waiting ends the flight before anybody armed.
pub(super) async fn wait_to_arm(
    start: Option<&StartAt>,
    abort: &mut tokio::sync::watch::Receiver<bool>,
) -> Result<(), FlyError> {
    let Some(start) = start else {
        return Ok(());
    };
    let wait = start.until_arming(SystemTime::now(), true)?;
    if *abort.borrow_and_update() {
        return Err(FlyError::AbortedBeforeTakeoff);
    }
    tokio::select! {
        () = tokio::time::sleep(wait) => Ok(()),
        _ = abort.changed() => Err(FlyError::AbortedBeforeTakeoff),
    }
}

/// How far after the start instant asked for the plan clock started, seconds,
/// measured from the log (its arming instant and its [`super::PLAN_STARTED`]
/// event); `None` unless the flight had a start instant and the plan started.
pub fn plan_start_delay_s(log: &super::FlightLog) -> Option<f64> {
    let started_s = log
        .events
        .iter()
        .find(|e| e.message == super::PLAN_STARTED)?
        .t_s;
    Some(log.armed_at_unix_s? + started_s - log.start_at_unix_s?)
}

/// Seconds from `now` to `at` (negative when `at` has passed).
fn signed_s(at: SystemTime, now: SystemTime) -> f64 {
    match at.duration_since(now) {
        Ok(d) => d.as_secs_f64(),
        Err(e) => -e.duration().as_secs_f64(),
    }
}

/// Seconds since the Unix epoch of `t` (negative before it), for the flight log.
pub fn unix_s(t: SystemTime) -> f64 {
    signed_s(t, SystemTime::UNIX_EPOCH)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arming_waits_for_the_lead_before_the_start_and_a_start_too_soon_is_refused() {
        let now = SystemTime::now();
        let start = StartAt {
            at: now + Duration::from_secs(30),
            takeoff_lead: Duration::from_secs(20),
        };
        let left = start.until_arming(now, false).expect("10 s to spare");
        assert!((left.as_secs_f64() - 10.0).abs() < 1e-6);
        let soon = StartAt {
            at: now + Duration::from_secs(5),
            ..start
        };
        match soon.until_arming(now, true) {
            Err(FlyError::StartTooSoon {
                start_in_s,
                takeoff_lead_s,
                after_preflight: true,
            }) => {
                assert!((start_in_s - 5.0).abs() < 1e-6);
                assert!((takeoff_lead_s - 20.0).abs() < 1e-9);
            }
            other => panic!("expected StartTooSoon, got {other:?}"),
        }
    }
}
