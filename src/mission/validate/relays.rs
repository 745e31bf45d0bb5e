//! The `link.relays` and `link.zenoh` sections: which relay serves which drone,
//! and where the controller meets the relays.

use super::fields::check_drone_id;
use super::report::Report;
use crate::mission::schema::{GroupSpec, LinkSpec};
use std::collections::HashMap;

/// Checks the relays: names unique and usable on a command line, every drone
/// named exists and is served by exactly one relay, and — once any relay is
/// declared — every drone has one. Returns each drone's relay (drone id → name).
pub(super) fn check_relays(
    link: &LinkSpec,
    groups: &[GroupSpec],
    report: &mut Report,
) -> HashMap<String, String> {
    if let Some(zenoh) = &link.zenoh {
        for (field, endpoints) in [("listen", &zenoh.listen), ("connect", &zenoh.connect)] {
            for (i, e) in endpoints.iter().enumerate() {
                if let Err(why) = check_zenoh_endpoint(e) {
                    report.add(format!("link.zenoh.{field}[{i}]"), why);
                }
            }
        }
    }
    let mut relay_of: HashMap<String, String> = HashMap::new();
    if link.relays.is_empty() {
        return relay_of;
    }
    let known: Vec<&str> = groups
        .iter()
        .flat_map(|g| g.drones.iter().map(|d| d.id.as_str()))
        .collect();
    let mut names: HashMap<&str, usize> = HashMap::new();
    for (ri, relay) in link.relays.iter().enumerate() {
        let path = format!("link.relays[{ri}]");
        if let Err(why) = check_drone_id(&relay.name) {
            report.add(format!("{path}.name"), format!("relay name {why}"));
        }
        if let Some(first) = names.insert(&relay.name, ri) {
            report.add(
                format!("{path}.name"),
                format!("relay {:?} is already link.relays[{first}]", relay.name),
            );
        }
        if relay.drones.is_empty() {
            report.add(
                format!("{path}.drones"),
                "a relay serves at least one drone",
            );
        }
        for (di, drone) in relay.drones.iter().enumerate() {
            let dpath = format!("{path}.drones[{di}]");
            if !known.contains(&drone.as_str()) {
                report.add(dpath, format!("no drone {drone:?} in the mission's groups"));
            } else if let Some(other) = relay_of.insert(drone.clone(), relay.name.clone()) {
                report.add(
                    dpath,
                    format!("drone {drone} is already served by relay {other}; give each drone to one relay"),
                );
            }
        }
    }
    let unserved: Vec<&str> = known
        .iter()
        .copied()
        .filter(|d| !relay_of.contains_key(*d))
        .collect();
    if !unserved.is_empty() {
        report.add(
            "link.relays",
            format!(
                "no relay serves {}; with relays, every drone needs one",
                unserved.join(", ")
            ),
        );
    }
    relay_of
}

/// A Zenoh TCP endpoint, `tcp/HOST:PORT` (the only transport swarmctl builds).
fn check_zenoh_endpoint(endpoint: &str) -> Result<(), String> {
    let Some(address) = endpoint.strip_prefix("tcp/") else {
        return Err(format!(
            "{endpoint:?}: write Zenoh endpoints as tcp/HOST:PORT, e.g. \"tcp/127.0.0.1:7447\" (TCP is the transport swarmctl builds)"
        ));
    };
    let port = address
        .rsplit_once(':')
        .map(|(host, port)| (host, port.parse::<u16>()));
    match port {
        Some((host, Ok(_))) if !host.is_empty() => Ok(()),
        _ => Err(format!(
            "{endpoint:?}: expected tcp/HOST:PORT with a port from 0 to 65535"
        )),
    }
}
