//! The faults the simulator can inject, as an operator names them: one
//! `KIND=VALUE` grammar (`loss=10%`, `latency=50ms`, `dup=5%`, `reorder=10%`,
//! `slow=DRONE:0.5`, `drop=DRONE@5s+3s`, `lose=DRONE@5s`, `crash=DRONE@5s`,
//! `refuse-arm=DRONE`, `low-battery=DRONE@10s`, `critical-battery=DRONE@10s`)
//! shared by every command that starts simulated vehicles (`swarmctl fly
//! --fault`, `swarmctl relay --fault`, `swarmctl sitl`), and the conversion of
//! those flags into one vehicle's [`Faults`](crate::Faults).
//!
//! A drone is named as the command names its vehicles: the mission's drone id
//! for `fly` and `relay`, the system id for `swarmctl sitl`. The simulator only
//! ever compares names, so it needs to know neither.
//!
//! Adding a fault kind: a variant of [`FaultSpec`], its arm in the parser
//! (`faults/parse.rs`) and in [`faults_for`] (`faults/vehicle.rs`), a knob in
//! [`Faults`](crate::Faults) and its effect in the vehicle model, and a
//! scenario in the controller's fault matrix (`harness/src/fault_matrix/`).

mod parse;
mod vehicle;

pub use parse::{FaultError, parse_fault};
pub use vehicle::{CRITICAL_AFTER_LOW, faults_for, unknown_drone};

use std::time::Duration;

/// Every fault kind with its form, as a command's `--fault` help gives it (the
/// drone is the mission's drone id there), so a new kind is documented where it
/// is parsed.
pub const FAULT_HELP: &str = "Bundled SITL fault, repeatable: link-wide loss=10%, latency=50ms, dup=5%, reorder=10% (loss=DRONE_ID:10% for one drone); per drone slow=DRONE_ID:0.5, drop=DRONE_ID@5s+3s (link cut 5 s after takeoff for 3 s; +inf: for good), lose=DRONE_ID@5s (cut for good), crash=DRONE_ID@5s (motors stop, it falls, silent), rogue=DRONE_ID@5s (a rogue ground station streams it a target 100 m west: its own geofence must stop it), refuse-arm=DRONE_ID, low-battery=DRONE_ID@10s (critical 45 s later; @10s+inf: a warning only), critical-battery=DRONE_ID@10s (after arming).";

/// How far west of its home a rogue ground station sends a drone, metres.
pub const ROGUE_TARGET_WEST_M: f32 = 100.0;

/// One parsed fault flag.
#[derive(Debug, Clone, PartialEq)]
pub enum FaultSpec {
    /// Drop this share of packets (percent) in each direction, on every vehicle
    /// or, when a drone is named, on that one.
    Loss {
        /// The vehicle it applies to; every vehicle when `None`.
        drone: Option<String>,
        /// Share of packets dropped, 0–100 %.
        percent: f64,
    },
    /// Add this latency in each direction, on every vehicle or the one named.
    Latency {
        /// The vehicle it applies to; every vehicle when `None`.
        drone: Option<String>,
        /// Extra one-way delay.
        latency: Duration,
    },
    /// Deliver this share of packets (percent) twice, each direction, on every
    /// vehicle or the one named.
    Duplicate {
        /// The vehicle it applies to; every vehicle when `None`.
        drone: Option<String>,
        /// Share of packets sent twice, 0–100 %.
        percent: f64,
    },
    /// Hold back this share of packets (percent) so later ones overtake them, on
    /// every vehicle or the one named.
    Reorder {
        /// The vehicle it applies to; every vehicle when `None`.
        drone: Option<String>,
        /// Share of packets held back, 0–100 %.
        percent: f64,
    },
    /// Cut this drone's link `after` takeoff, for good.
    Lose {
        /// The drone's name.
        drone: String,
        /// Time after takeoff when the link is cut.
        after: Duration,
    },
    /// This drone's battery turns low `after` arming (a warning), and critical
    /// `critical_after` later, when its autopilot lands it.
    LowBattery {
        /// The drone's name.
        drone: String,
        /// Time after arming when the battery turns low.
        after: Duration,
        /// How long it stays low before turning critical ([`CRITICAL_AFTER_LOW`]
        /// unless given; [`Duration::MAX`]: a warning only, it never turns
        /// critical by itself).
        critical_after: Duration,
    },
    /// This drone's battery turns critical `after` arming with no warning first:
    /// its autopilot's failsafe lands it (PX4) or returns it (ArduPilot).
    CriticalBattery {
        /// The drone's name.
        drone: String,
        /// Time after arming when the battery turns critical.
        after: Duration,
    },
    /// This drone crashes `after` takeoff: its motors stop, it falls to the ground
    /// below it and never speaks again (a lost drone that is not hovering).
    Crash {
        /// The drone's name.
        drone: String,
        /// Time after takeoff when it crashes.
        after: Duration,
    },
    /// From `after` takeoff a rogue ground station streams this drone a target
    /// [`ROGUE_TARGET_WEST_M`] west of its home at its height, faster than the
    /// controller streams its own: in GUIDED or OFFBOARD it flies there, until
    /// its own geofence takes it out of that mode.
    Rogue {
        /// The drone's name.
        drone: String,
        /// Time after takeoff when the rogue stream starts.
        after: Duration,
    },
    /// This drone flies at `factor` times the speed it is commanded.
    Slow {
        /// The drone's name.
        drone: String,
        /// Flown speed over commanded speed, in (0, 1].
        factor: f64,
    },
    /// Cut this drone's link `after` takeoff, for `duration` ([`Duration::MAX`]:
    /// for good).
    Drop {
        /// The drone's name.
        drone: String,
        /// Time after takeoff when the link is cut.
        after: Duration,
        /// How long it stays cut.
        duration: Duration,
    },
    /// This drone refuses to arm (fails its pre-arm checks).
    RefuseArm {
        /// The drone's name.
        drone: String,
    },
}

impl FaultSpec {
    /// The drone the fault names, if it names one (a link-wide fault without a
    /// drone applies to every vehicle).
    pub fn drone(&self) -> Option<&str> {
        match self {
            FaultSpec::Slow { drone, .. }
            | FaultSpec::Drop { drone, .. }
            | FaultSpec::Lose { drone, .. }
            | FaultSpec::Crash { drone, .. }
            | FaultSpec::Rogue { drone, .. }
            | FaultSpec::LowBattery { drone, .. }
            | FaultSpec::CriticalBattery { drone, .. }
            | FaultSpec::RefuseArm { drone } => Some(drone),
            FaultSpec::Loss { drone, .. }
            | FaultSpec::Latency { drone, .. }
            | FaultSpec::Duplicate { drone, .. }
            | FaultSpec::Reorder { drone, .. } => drone.as_deref(),
        }
    }
}
