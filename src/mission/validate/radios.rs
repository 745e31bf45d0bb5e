//! The `link.radios` section: which shared telemetry radio carries which drone,
//! and how much it can carry. Whether the traffic fits is the link budget's
//! question (`link::budget`), asked of a valid mission.

use super::fields::check_drone_id;
use super::report::Report;
use crate::mission::schema::{GroupSpec, LinkSpec};
use std::collections::HashMap;

/// Checks the radios: names unique and printable, a positive finite capacity,
/// every drone named exists and is on at most one radio. A drone on no radio
/// has a link of its own.
pub(super) fn check_radios(link: &LinkSpec, groups: &[GroupSpec], report: &mut Report) {
    let known: Vec<&str> = groups
        .iter()
        .flat_map(|g| g.drones.iter().map(|d| d.id.as_str()))
        .collect();
    let mut names: HashMap<&str, usize> = HashMap::new();
    let mut radio_of: HashMap<&str, &str> = HashMap::new();
    for (ri, radio) in link.radios.iter().enumerate() {
        let path = format!("link.radios[{ri}]");
        if let Err(why) = check_drone_id(&radio.name) {
            report.add(format!("{path}.name"), format!("radio name {why}"));
        }
        if let Some(first) = names.insert(&radio.name, ri) {
            report.add(
                format!("{path}.name"),
                format!("radio {:?} is already link.radios[{first}]", radio.name),
            );
        }
        let capacity = radio.capacity_kbps;
        if !(capacity.is_finite() && capacity > 0.0) {
            report.add(
                format!("{path}.capacity_kbps"),
                format!(
                    "must be a positive number of kbit/s (a SiK radio's air rate, e.g. 64), got {capacity}"
                ),
            );
        }
        if radio.drones.is_empty() {
            report.add(
                format!("{path}.drones"),
                "a radio carries at least one drone",
            );
        }
        for (di, drone) in radio.drones.iter().enumerate() {
            let dpath = format!("{path}.drones[{di}]");
            if !known.contains(&drone.as_str()) {
                report.add(dpath, format!("no drone {drone:?} in the mission's groups"));
            } else if let Some(other) = radio_of.insert(drone, &radio.name) {
                report.add(
                    dpath,
                    format!(
                        "drone {drone} is already on radio {other}; a drone's link goes over one radio"
                    ),
                );
            }
        }
    }
}
