//! `swarmctl fly --via zenoh`: the controller's links through relays — where
//! the controller meets them, and the check that each drone is served by the
//! relay the mission gives it.

use anyhow::Context;
use std::io::Write;
use std::time::Duration;
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;
use swarmctl_relay::{RelayLinks, ZenohEndpoints};

/// The Zenoh flags of `fly`.
pub struct ZenohArgs<'a> {
    /// `--zenoh-listen`.
    pub listen: &'a [String],
    /// `--zenoh-connect`.
    pub connect: &'a [String],
    /// `--relay-wait`, seconds.
    pub wait_s: f64,
}

/// Where the controller meets the relays: the flags, else the mission's
/// `link.zenoh`, else listening on the default endpoint.
pub fn endpoints(mission: &Mission, args: &ZenohArgs<'_>) -> ZenohEndpoints {
    if !args.listen.is_empty() || !args.connect.is_empty() {
        return ZenohEndpoints {
            role: swarmctl_relay::Role::Router,
            listen: args.listen.to_vec(),
            connect: args.connect.to_vec(),
        };
    }
    match &mission.link.zenoh {
        Some(z) if !z.listen.is_empty() || !z.connect.is_empty() => ZenohEndpoints {
            role: swarmctl_relay::Role::Router,
            listen: z.listen.clone(),
            connect: z.connect.clone(),
        },
        _ => ZenohEndpoints::controller_default(),
    }
}

/// Waits for relays to announce every drone of `plan` and opens a link to each,
/// saying how many are found as they come.
pub async fn connect(
    mission: &Mission,
    plan: &DiscretePlan,
    args: &ZenohArgs<'_>,
) -> anyhow::Result<RelayLinks> {
    let wait = Duration::try_from_secs_f64(args.wait_s)
        .ok()
        .filter(|d| !d.is_zero())
        .context("--relay-wait must be a positive number of seconds")?;
    let zenoh = endpoints(mission, args);
    let ids: Vec<String> = plan.drones.iter().map(|d| d.id.clone()).collect();
    eprintln!(
        "waiting up to {:.0} s for relays to serve {} drones (Zenoh: {})",
        wait.as_secs_f64(),
        ids.len(),
        zenoh.describe()
    );
    let links = RelayLinks::connect(&zenoh, &mission.name, &ids, wait, |found, total| {
        eprint!("\r  {found}/{total} drones served");
        let _ = std::io::stderr().flush();
    })
    .await?;
    eprintln!();
    for served in links.served() {
        let declared = mission
            .link
            .relays
            .iter()
            .find(|r| r.drones.contains(&served.drone));
        if let Some(declared) = declared
            && declared.name != served.relay
        {
            anyhow::bail!(
                "drone {} is served by relay {}, but the mission's link.relays gives it to {}",
                served.drone,
                served.relay,
                declared.name
            );
        }
    }
    let mut relays: Vec<&str> = links.served().iter().map(|s| s.relay.as_str()).collect();
    relays.sort_unstable();
    relays.dedup();
    eprintln!(
        "flying through {} relays: {}",
        relays.len(),
        relays.join(", ")
    );
    Ok(links)
}
