//! Starting the bundled simulator (`swarmctl-sitl`) for a mission that names no
//! endpoints: one vehicle per drone on an ephemeral loopback port, on the
//! ground below its start, with the mission's limits and the `--fault` flags.
//!
//! This is the glue between the controller and the simulator that tests it:
//! it needs both (missions and plans from `swarmctl`, vehicles from
//! `swarmctl-sitl`), and the simulator may not depend on the controller, so it
//! is a crate of its own. `swarmctl fly` and `swarmctl relay --sitl` start
//! their vehicles here; so do the harness, the tests and the benchmarks.

mod configs;
mod error;

pub use configs::{relay_vehicle_configs, vehicle_configs, vehicle_configs_in};
pub use error::BundledSitlError;

use std::net::{IpAddr, Ipv4Addr};
use std::time::Duration;
use swarmctl::fly::{FlyOptions, VehicleLink};
use swarmctl::mission::Autopilot;
use swarmctl_sitl::{Flavour, Swarm, VehicleConfig};

/// The bundled vehicles report a position and their pre-arm state at once: a
/// vehicle not ready this soon will not become ready (a `refuse-arm` fault).
pub const READY_TIMEOUT: Duration = Duration::from_secs(5);

/// Flight options for the bundled vehicles at `links`: the defaults, with the
/// bundled simulator's [`READY_TIMEOUT`].
pub fn fly_options(links: Vec<VehicleLink>) -> FlyOptions {
    let mut options = FlyOptions::new(links);
    options.ready_timeout = READY_TIMEOUT;
    options
}

/// The simulator's imitation of `autopilot`. The simulator keeps its own
/// autopilot type (it does not depend on the controller it tests); this is the
/// one place the two meet, so a new autopilot fails to compile here until the
/// simulator imitates it.
pub fn flavour(autopilot: Autopilot) -> Flavour {
    match autopilot {
        Autopilot::Px4 => Flavour::Px4,
        Autopilot::Ardupilot => Flavour::ArduPilot,
    }
}

/// Spawns the vehicles on 127.0.0.1 and returns the swarm and how to reach each.
pub async fn start(
    configs: Vec<VehicleConfig>,
    telemetry_rate_hz: f64,
) -> Result<(Swarm, Vec<VehicleLink>), BundledSitlError> {
    let ids: Vec<u8> = configs.iter().map(|c| c.system_id).collect();
    let swarm = swarmctl_sitl::spawn(
        IpAddr::V4(Ipv4Addr::LOCALHOST),
        configs,
        100.0,
        telemetry_rate_hz,
    )
    .await?;
    let links = swarm
        .addresses()
        .into_iter()
        .zip(ids)
        .map(|(address, system_id)| VehicleLink::mavlink(format!("udpout:{address}"), system_id))
        .collect();
    Ok((swarm, links))
}
