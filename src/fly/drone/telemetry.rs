//! What telemetry says about one vehicle and whether we can still trust it: the
//! latest position and velocity, how fresh the position is, and the link's health
//! (silence, losses, a carrier that says the vehicle is out of reach).

use crate::fly::path::distance_m;
use crate::fly::settings::LoopSettings;
use crate::link::{Session, VehicleFrame, frames};
use std::time::Instant;

/// Position telemetry older than this (ten periods at 20 Hz) means we cannot see
/// the drone: its commanded motion pauses long before the heartbeat timeout.
const TELEMETRY_STALE_S: f64 = 0.5;

/// The newest telemetry of one vehicle and the health of its link.
pub(super) struct Telemetry {
    /// Latest telemetry position, ENU metres.
    pub(super) position_m: Option<[f64; 3]>,
    /// Latest telemetry velocity, ENU metres per second.
    pub(super) velocity_mps: [f64; 3],
    /// When the newest position sample arrived.
    pub(super) position_received: Option<Instant>,
    /// Nothing heard for the mission's link timeout (or the carrier says so).
    pub(super) link_lost: bool,
    /// Times the link was lost during the flight.
    pub(super) link_losses: usize,
    /// Seconds since any message from the vehicle.
    pub(super) silent_s: f64,
    /// No position telemetry for `TELEMETRY_STALE_S`: the follower pauses.
    pub(super) stale: bool,
}

impl Telemetry {
    /// Nothing heard yet.
    pub(super) fn new() -> Self {
        Self {
            position_m: None,
            velocity_mps: [0.0; 3],
            position_received: None,
            link_lost: false,
            link_losses: 0,
            silent_s: 0.0,
            stale: false,
        }
    }

    /// Copies the newest telemetry of `session` in (positions through `frame`) and
    /// detects link loss and stale positions, telling `log` what changed. A stale
    /// or returning position is told only while `flying`.
    pub(super) fn read(
        &mut self,
        session: &Session,
        frame: VehicleFrame,
        settings: &LoopSettings,
        now: Instant,
        flying: bool,
        mut log: impl FnMut(&str),
    ) {
        let (position, silent_s) = {
            let s = session.state();
            (s.position, s.message_age_s(now))
        };
        self.silent_s = silent_s.unwrap_or(f64::INFINITY);
        let stale = position.is_none_or(|p| {
            now.saturating_duration_since(p.received).as_secs_f64() > TELEMETRY_STALE_S
        });
        if stale != self.stale && flying {
            let what = if stale {
                "position telemetry stopped: pausing at the next possible stop"
            } else {
                "position telemetry back: resuming"
            };
            log(what);
        }
        self.stale = stale;
        if let Some(p) = position {
            self.position_m = Some(frame.mission_from_local(p.position_ned_m));
            self.position_received = Some(p.received);
            self.velocity_mps = frames::enu_from_ned_f32(p.velocity_ned_mps);
        }
        // Any message proves the link: under heavy loss heartbeats alone (1 Hz) go
        // missing for seconds while telemetry (20 Hz) still gets through.
        // A carrier that says the vehicle is out of reach (its relay left) is
        // believed at once: waiting out the timeout would only fly blind longer.
        let carrier_down = session.carrier_down();
        let lost =
            carrier_down.is_some() || silent_s.is_none_or(|age| age > settings.link_timeout_s);
        if lost && !self.link_lost {
            self.link_losses += 1;
            let why = carrier_down
                .unwrap_or_else(|| format!("nothing heard for {:.1} s", settings.link_timeout_s));
            log(&format!("link lost: {why}"));
        } else if !lost && self.link_lost {
            log("link back");
        }
        self.link_lost = lost;
    }

    /// Latest telemetry speed, metres per second.
    pub(super) fn speed_mps(&self) -> f64 {
        distance_m(self.velocity_mps, [0.0; 3])
    }

    /// Where telemetry says the vehicle would come to rest braking within `limits`
    /// from its current velocity (its position when at rest), ENU metres.
    pub(super) fn stopping_point_m(&self, limits: crate::profile::Kinematics) -> Option<[f64; 3]> {
        let p = self.position_m?;
        let speed_mps = self.speed_mps();
        if speed_mps <= 0.0 {
            return Some(p);
        }
        let moving = crate::profile::State {
            x_m: 0.0,
            v_mps: speed_mps,
            a_mps2: 0.0,
        };
        let reach_s = crate::profile::Brake::new(moving, limits).stop_m() / speed_mps;
        let v = self.velocity_mps;
        Some(std::array::from_fn(|i| p[i] + v[i] * reach_s))
    }
}
