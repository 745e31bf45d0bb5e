//! What a caller chooses per vehicle: identity, flavour, limits and faults.

use crate::error::SitlError;
use crate::geo::GeoPoint;
use std::time::Duration;

/// Which autopilot the mock imitates on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Flavour {
    /// PX4: OFFBOARD mode, `main << 16 | sub << 24` custom modes, MIS_TAKEOFF_ALT.
    Px4,
    /// ArduPilot Copter: GUIDED / LOITER / RTL / LAND custom modes.
    ArduPilot,
}

impl std::fmt::Display for Flavour {
    /// The firmware's own name: `PX4`, `ArduPilot`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.imitation().name())
    }
}

impl std::str::FromStr for Flavour {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let name = s.to_ascii_lowercase();
        Flavour::ALL
            .into_iter()
            .find(|f| f.imitation().aliases().contains(&name.as_str()))
            .ok_or_else(|| {
                let known: Vec<&str> = Flavour::ALL
                    .iter()
                    .map(|f| f.imitation().aliases()[0])
                    .collect();
                format!("unknown flavour {name:?} ({})", known.join(" or "))
            })
    }
}

/// A link outage: starts `after_takeoff` after the vehicle is first airborne
/// and lasts `duration`. Both directions are cut, as with a real radio dropout.
/// `duration: Duration::MAX` is a permanent loss: the link never comes back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LinkDrop {
    /// Delay from the first moment the vehicle is airborne to the cut.
    pub after_takeoff: Duration,
    /// How long the link stays cut; [`Duration::MAX`] (or anything longer
    /// than the flight) means for good.
    pub duration: Duration,
}

impl LinkDrop {
    /// A link that is cut `after_takeoff` after the vehicle is first airborne
    /// and never comes back.
    pub fn permanent(after_takeoff: Duration) -> Self {
        Self {
            after_takeoff,
            duration: Duration::MAX,
        }
    }
}

/// Largest latency fault accepted (larger values are almost certainly a unit mistake).
pub const MAX_LATENCY: Duration = Duration::from_secs(3600);

/// Faults injected into one vehicle. `Faults::default()` is a healthy vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct Faults {
    /// Share of packets dropped, in percent (0–100), independently in each direction.
    pub loss_percent: f64,
    /// Share of datagrams delivered twice, in percent (0–100), independently
    /// in each direction (counted in `LinkStats::{rx,tx}_duplicated`).
    pub duplicate_percent: f64,
    /// Share of datagrams held back by a random 10–60 ms so later ones
    /// overtake them, in percent (0–100), independently in each direction
    /// (counted in `LinkStats::{rx,tx}_reordered`).
    pub reorder_percent: f64,
    /// Latency added to each direction (so round trips grow by twice this);
    /// at most [`MAX_LATENCY`].
    pub latency: Duration,
    /// Multiplies the vehicle's speed limit: 0.5 flies at most half as fast (a slow drone).
    pub speed_factor: f64,
    /// A link outage some time after takeoff.
    pub link_drop: Option<LinkDrop>,
    /// Arming is denied (COMMAND_ACK DENIED plus a STATUSTEXT reason).
    pub refuse_arm: bool,
    /// After this much armed time the battery turns LOW: a warning only
    /// (battery_remaining at most 25 %, BATTERY_STATUS charge state LOW,
    /// STATUSTEXT WARNING "Low battery…"); the vehicle keeps flying.
    pub low_battery_after: Option<Duration>,
    /// After this much armed time the battery turns CRITICAL
    /// (battery_remaining at most 8 %, charge state CRITICAL, STATUSTEXT
    /// CRITICAL) and the failsafe fires: PX4 lands, ArduPilot returns and
    /// lands; arming is refused afterwards. Critical implies low.
    pub critical_battery_after: Option<Duration>,
    /// This long after takeoff the vehicle crashes: its motors stop, it falls
    /// under gravity (straight down from a hover) and lies where it hits the
    /// ground, and its link goes silent for good (nothing reports a crash).
    pub crash_after_takeoff: Option<Duration>,
    /// This long after takeoff a rogue ground station takes the vehicle over in
    /// GUIDED or OFFBOARD, sending it far west (`faults::ROGUE_TARGET_WEST_M`):
    /// only its own geofence stops it.
    pub rogue_after_takeoff: Option<Duration>,
}

impl Default for Faults {
    fn default() -> Self {
        Self {
            loss_percent: 0.0,
            duplicate_percent: 0.0,
            reorder_percent: 0.0,
            latency: Duration::ZERO,
            speed_factor: 1.0,
            link_drop: None,
            refuse_arm: false,
            low_battery_after: None,
            critical_battery_after: None,
            crash_after_takeoff: None,
            rogue_after_takeoff: None,
        }
    }
}

impl Faults {
    /// Checks the knobs are in range; `system_id` only labels the error.
    pub fn validate(&self, system_id: u8) -> Result<(), SitlError> {
        let bad = |reason: String| SitlError::InvalidFault { system_id, reason };
        for (what, percent) in [
            ("loss", self.loss_percent),
            ("duplicate", self.duplicate_percent),
            ("reorder", self.reorder_percent),
        ] {
            if !(0.0..=100.0).contains(&percent) {
                return Err(bad(format!("{what} {percent}% is not in 0..=100")));
            }
        }
        if self.latency > MAX_LATENCY {
            return Err(bad(format!(
                "latency {:?} is longer than {MAX_LATENCY:?}",
                self.latency
            )));
        }
        if !(self.speed_factor.is_finite() && self.speed_factor > 0.0 && self.speed_factor <= 10.0)
        {
            return Err(bad(format!(
                "speed factor {} is not in (0, 10]",
                self.speed_factor
            )));
        }
        Ok(())
    }
}

/// Everything that defines one mock vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleConfig {
    /// MAVLink system id (1–255); the autopilot is always component 1.
    pub system_id: u8,
    /// UDP port the vehicle listens on; 0 picks a free ephemeral port.
    pub port: u16,
    /// Autopilot imitated on the wire.
    pub flavour: Flavour,
    /// Where the vehicle sits on the ground at start, in the swarm's shared
    /// NED frame (metres), the simulator's own.
    pub initial_position_ned_m: [f32; 3],
    /// Where the vehicle's own local frame has its zero, in the shared frame
    /// (metres): LOCAL_POSITION_NED and LOCAL_NED setpoints are relative to it, and
    /// GPS_GLOBAL_ORIGIN reports it. `[0, 0, 0]` (the default) puts every vehicle in
    /// the shared frame; [`VehicleConfig::own_frame`] puts it where the vehicle
    /// stands, as a real EKF does at its first GPS fix.
    pub local_origin_ned_m: [f32; 3],
    /// Geodetic position of the start point: origin of GLOBAL_POSITION_INT and HOME_POSITION.
    pub home: GeoPoint,
    /// Speed limit of the position controller (before the fault speed factor).
    pub max_speed_mps: f32,
    /// Acceleration limit of the position controller.
    pub max_accel_mps2: f32,
    /// Faults to inject.
    pub faults: Faults,
    /// MAVLink 2 signing key: when set, unsigned or wrongly signed input is
    /// dropped and everything sent is signed.
    pub signing_key: Option<[u8; 32]>,
    /// Seed of the deterministic sensor noise and packet-loss draws.
    pub seed: u64,
    /// Also stream everything to this UDP port on the bind address (a ground station).
    pub gcs_stream_port: Option<u16>,
    /// PX4 only: after offboard loss the vehicle holds, then lands after this
    /// long. [`Duration::MAX`] holds forever (PX4 with the offboard-loss
    /// action set to Hold). ArduPilot has no such timer: in GUIDED it keeps
    /// flying to its last position target (or stops after a velocity target
    /// times out) and holds there.
    pub offboard_loss_land_after: Duration,
}

impl VehicleConfig {
    /// A healthy vehicle at the local origin with PX4-like default limits
    /// (5 m/s, 3 m/s²), on an ephemeral port.
    pub fn new(system_id: u8, flavour: Flavour) -> Self {
        Self {
            system_id,
            port: 0,
            flavour,
            initial_position_ned_m: [0.0; 3],
            local_origin_ned_m: [0.0; 3],
            home: GeoPoint::default(),
            max_speed_mps: 5.0,
            max_accel_mps2: 3.0,
            faults: Faults::default(),
            signing_key: None,
            seed: u64::from(system_id),
            gcs_stream_port: None,
            offboard_loss_land_after: Duration::from_secs(5),
        }
    }

    /// Places the vehicle at `initial_position_ned_m` in a shared frame whose
    /// origin is the geodetic point `origin`, and derives `home` from it.
    pub fn at(mut self, origin: GeoPoint, initial_position_ned_m: [f32; 3]) -> Self {
        self.initial_position_ned_m = initial_position_ned_m;
        self.home = origin.offset_ned(initial_position_ned_m.map(f64::from));
        self
    }

    /// Starts the vehicle's local frame where it stands (see `local_origin_ned_m`).
    pub fn own_frame(mut self) -> Self {
        self.local_origin_ned_m = self.initial_position_ned_m;
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_faults_are_healthy_and_valid() {
        let faults = Faults::default();
        assert!(faults.validate(1).is_ok());
        assert_eq!(faults.duplicate_percent, 0.0);
        assert_eq!(faults.reorder_percent, 0.0);
        assert_eq!(faults.low_battery_after, None);
        assert_eq!(faults.critical_battery_after, None);
    }

    #[test]
    fn validate_rejects_out_of_range_knobs_and_accepts_forever() {
        for bad in [
            Faults {
                duplicate_percent: 100.5,
                ..Faults::default()
            },
            Faults {
                reorder_percent: -1.0,
                ..Faults::default()
            },
            Faults {
                reorder_percent: f64::NAN,
                ..Faults::default()
            },
            Faults {
                latency: Duration::MAX,
                ..Faults::default()
            },
        ] {
            assert!(bad.validate(3).is_err(), "{bad:?}");
        }
        let forever = Faults {
            duplicate_percent: 100.0,
            reorder_percent: 100.0,
            latency: MAX_LATENCY,
            link_drop: Some(LinkDrop::permanent(Duration::MAX)),
            low_battery_after: Some(Duration::MAX),
            critical_battery_after: Some(Duration::MAX),
            ..Faults::default()
        };
        assert!(forever.validate(3).is_ok());
    }
}
