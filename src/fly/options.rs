//! How to reach the vehicles and how strict the flight is.

use super::observer::FlightObserver;
use crate::link::{CarriedLink, CommandPolicy, SigningKey};
use std::sync::Arc;
use std::time::Duration;

/// Where to reach one drone's autopilot.
#[derive(Debug, Clone)]
pub struct VehicleLink {
    /// rust-mavlink address, e.g. `udpout:127.0.0.1:14540`; for a carried link,
    /// what carries it (`zenoh relay north`), as the flight log shows it.
    pub endpoint: String,
    /// The vehicle's MAVLink system id: messages from any other system are ignored.
    /// Behind a relay it is the id in the relay's own MAVLink network.
    pub system_id: u8,
    /// Frames carried by someone else (a relay) instead of a connection to `endpoint`.
    pub carried: Option<Arc<CarriedLink>>,
}

impl VehicleLink {
    /// A vehicle reached over a MAVLink connection of our own.
    pub fn mavlink(endpoint: impl Into<String>, system_id: u8) -> Self {
        Self {
            endpoint: endpoint.into(),
            system_id,
            carried: None,
        }
    }

    /// A vehicle whose frames `link` carries (see [`crate::link::carried`]).
    pub fn carried(link: Arc<CarriedLink>, system_id: u8) -> Self {
        Self {
            endpoint: link.label().to_string(),
            system_id,
            carried: Some(link),
        }
    }
}

/// Everything `fly` needs besides the mission and plan.
#[derive(Clone)]
pub struct FlyOptions {
    /// One per drone, in plan order.
    pub vehicles: Vec<VehicleLink>,
    /// How long pre-flight waits for each vehicle's first HEARTBEAT.
    pub heartbeat_timeout: Duration,
    /// How long pre-flight waits for each vehicle to be ready to arm: a position in
    /// telemetry and its pre-arm checks passing (real autopilots need some 40 s
    /// after boot for EKF and GPS). Past it, pre-flight says per drone what is missing.
    pub ready_timeout: Duration,
    /// Whether each vehicle keeps its own local frame (real autopilots; learned at
    /// pre-flight) or all report in the mission frame already.
    pub frames: super::placement::FrameSource,
    /// Horizontal distance allowed between where a vehicle is found (its GPS with
    /// `world.geo_origin`, or its report in a shared frame) and its pad.
    pub start_tolerance_m: f64,
    /// Telemetry this close to a commanded rest point counts as arrived (never more
    /// than the mission's tracking error). Real autopilots hover a few centimetres
    /// off their setpoint (ArduCopter SITL: 4–6 cm at rest), so a tolerance at that
    /// level makes every run wait on sensor noise before the next may start.
    pub settle_tolerance_m: f64,
    /// Plan execution gives up (holds, lands) after `factor × makespan + 30 s`.
    pub timeout_factor: f64,
    /// How often and how long each command is tried before the vehicle counts
    /// as refusing (raise it on lossy links).
    pub command_policy: CommandPolicy,
    /// See every telemetry sample, event and status live (a Rerun recorder, a
    /// status line), in this order.
    pub observers: Vec<Arc<dyn FlightObserver>>,
    /// MAVLink 2 signing key shared with the vehicles; `None` flies unsigned.
    pub signing_key: Option<SigningKey>,
    /// Whether and how the rest of the flight is replanned when drones leave it.
    pub replan: super::replan::ReplanOptions,
    /// Start the plan at this instant instead of as soon as the swarm is above its
    /// pads (see [`super::StartAt`]).
    pub start_at: Option<super::StartAt>,
}

impl std::fmt::Debug for FlyOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FlyOptions")
            .field("vehicles", &self.vehicles)
            .field("heartbeat_timeout", &self.heartbeat_timeout)
            .field("ready_timeout", &self.ready_timeout)
            .field("frames", &self.frames)
            .field("start_tolerance_m", &self.start_tolerance_m)
            .field("settle_tolerance_m", &self.settle_tolerance_m)
            .field("timeout_factor", &self.timeout_factor)
            .field("command_policy", &self.command_policy)
            .field("observers", &self.observers.len())
            .field("signing_key", &self.signing_key)
            .field("replan", &self.replan)
            .field("start_at", &self.start_at)
            .finish()
    }
}

impl FlyOptions {
    /// Defaults for a calm link: 5 s for the first heartbeat, per-vehicle frames,
    /// 0.3 m start tolerance, 10 cm settle tolerance, 4 × makespan timeout, no observers,
    /// unsigned, replanning on (see `ReplanOptions::default`), the plan started as
    /// soon as the swarm is above its pads.
    pub fn new(vehicles: Vec<VehicleLink>) -> Self {
        Self {
            vehicles,
            heartbeat_timeout: Duration::from_secs(5),
            ready_timeout: Duration::from_secs(60),
            frames: super::placement::FrameSource::PerVehicle,
            start_tolerance_m: 0.3,
            settle_tolerance_m: 0.10,
            timeout_factor: 4.0,
            command_policy: CommandPolicy::default(),
            observers: Vec::new(),
            signing_key: None,
            replan: super::replan::ReplanOptions::default(),
            start_at: None,
        }
    }
}
