//! How the controller reaches the vehicles: the mission's endpoints, relays over
//! Zenoh, or the bundled SITL — and what stands behind them, to stop after the
//! flight.

use super::Args;
use super::bundled_sitl;
use anyhow::Context;
use swarmctl::fly::VehicleLink;
use swarmctl::link::SigningKey;
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;

/// What stands behind the vehicle links for the flight, stopped after it.
pub(super) enum Backing {
    /// The mission's own endpoints: nothing to stop.
    Endpoints,
    /// The bundled SITL, started here.
    Sitl(swarmctl_sitl::Swarm),
    /// Links through relays over Zenoh.
    Relays(swarmctl_relay::RelayLinks),
}

impl Backing {
    pub(super) async fn shutdown(self) {
        match self {
            Backing::Endpoints => {}
            Backing::Sitl(swarm) => swarm.shutdown().await,
            Backing::Relays(links) => links.close().await,
        }
    }
}

/// How to reach each drone of `plan` (plan order): the mission's endpoints, or,
/// when it names none, the bundled SITL started here (returned too, to shut it
/// down after the flight).
pub(super) async fn vehicles(
    args: &Args,
    mission: &Mission,
    plan: &DiscretePlan,
    signing_key: Option<&SigningKey>,
) -> anyhow::Result<(Vec<VehicleLink>, Backing)> {
    let via_zenoh = match args.via.as_deref() {
        Some(via) => via == "zenoh",
        None => !mission.link.relays.is_empty(),
    };
    if via_zenoh {
        if !args.faults.is_empty() || args.autopilot.is_some() {
            anyhow::bail!(
                "--fault and --autopilot apply to the bundled SITL this process starts; through relays, give them to `swarmctl relay --sitl`"
            );
        }
        let links = crate::commands::fly_relays::connect(
            mission,
            plan,
            &crate::commands::fly_relays::ZenohArgs {
                listen: &args.zenoh_listen,
                connect: &args.zenoh_connect,
                wait_s: args.relay_wait,
            },
        )
        .await?;
        return Ok((links.vehicle_links(), Backing::Relays(links)));
    }
    let endpoints = mission_endpoints(mission, plan);
    if endpoints.iter().all(Option::is_none) {
        let (links, swarm) =
            bundled_sitl::start_bundled_sitl(args, mission, plan, signing_key).await?;
        return Ok((links, Backing::Sitl(swarm)));
    }
    if !args.faults.is_empty() || args.autopilot.is_some() {
        anyhow::bail!(
            "--fault and --autopilot apply to the bundled SITL only, but the mission names endpoints"
        );
    }
    let links = endpoints
        .into_iter()
        .zip(&plan.drones)
        .map(|(e, d)| {
            e.with_context(|| {
                format!(
                    "drone {} has no endpoint (give all drones one, or none)",
                    d.id
                )
            })
        })
        .collect::<anyhow::Result<_>>()?;
    Ok((links, Backing::Endpoints))
}

/// The endpoint the mission gives each drone of `plan` (plan order), if any; a
/// drone without a system id gets its 1-based position in the plan.
fn mission_endpoints(mission: &Mission, plan: &DiscretePlan) -> Vec<Option<VehicleLink>> {
    plan.drones
        .iter()
        .enumerate()
        .map(|(i, d)| {
            mission
                .drones()
                .find(|(_, m)| m.id == d.id)
                .and_then(|(_, m)| {
                    m.endpoint.clone().map(|endpoint| {
                        VehicleLink::mavlink(endpoint, m.system_id.unwrap_or(i as u8 + 1))
                    })
                })
        })
        .collect()
}
