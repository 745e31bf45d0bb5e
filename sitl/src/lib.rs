//! Mock PX4 and ArduPilot quadcopters that speak real MAVLink 2 over UDP.
//!
//! Many vehicles run in one process (tokio). Each listens on its own UDP port,
//! answers whoever spoke to it last, flies simple quadrotor dynamics and can
//! be given faults (loss, duplication, reordering, latency, a slow drone,
//! temporary or permanent link drops, arming refusal, a low battery and a
//! critical-battery failsafe) so flight code can be tested without hardware.
//! [`forge`] builds CRC-valid frames from arbitrary parts, for fuzzers.
//!
//! ```no_run
//! # async fn demo() -> Result<(), swarmctl_sitl::SitlError> {
//! use swarmctl_sitl::{Flavour, VehicleConfig, spawn};
//! let vehicles = (1..=3).map(|id| VehicleConfig::new(id, Flavour::Px4)).collect();
//! let swarm = spawn("127.0.0.1".parse().unwrap(), vehicles, 100.0, 20.0).await?;
//! println!("connect with udpout:{}", swarm.addresses()[0]);
//! let state = swarm.snapshot(0);
//! assert!(!state.armed);
//! swarm.shutdown().await;
//! # Ok(()) }
//! ```

#![warn(missing_docs)]

pub mod ardupilot;
#[cfg(feature = "cli")]
mod bench;
#[cfg(feature = "cli")]
pub mod cli;
pub mod codec;
mod commands;
pub mod config;
pub mod dynamics;
pub mod error;
pub mod faults;
pub mod fence;
pub mod forge;
pub mod geo;
mod imitation;
mod link;
pub mod mode;
mod params;
pub mod px4;
pub mod setpoint_intervals;
mod setpoints;
pub mod streams;
pub mod swarm;
pub mod telemetry;
pub mod truth;
pub mod vehicle;
#[cfg(test)]
mod vehicle_tests;

pub use config::{Faults, Flavour, LinkDrop, VehicleConfig};
pub use error::SitlError;
pub use faults::{FaultError, FaultSpec, faults_for, parse_fault};
pub use geo::GeoPoint;
pub use link::LinkStats;
pub use mode::FlightMode;
pub use swarm::{Swarm, TickStats, VehicleSnapshot, spawn};
pub use vehicle::Vehicle;
