//! One vehicle configuration per drone: where it stands, in which frame, with
//! the mission's limits and the faults that name it.

use crate::BundledSitlError;
use std::time::Duration;
use swarmctl::fly::FrameSource;
use swarmctl::link::frames;
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;
use swarmctl_sitl::faults::{FaultSpec, faults_for, unknown_drone};
use swarmctl_sitl::{Flavour, GeoPoint, VehicleConfig};

/// Vehicle configurations for every drone of `plan` (plan order, system ids 1, 2, …),
/// each vehicle in its own local frame, as real autopilots are (see
/// [`vehicle_configs_in`]).
pub fn vehicle_configs(
    mission: &Mission,
    plan: &DiscretePlan,
    flavour: Flavour,
    faults: &[FaultSpec],
) -> Result<Vec<VehicleConfig>, BundledSitlError> {
    vehicle_configs_in(mission, plan, flavour, faults, FrameSource::PerVehicle)
}

/// Vehicle configurations for every drone of `plan`, standing on its pad, with
/// the mission's limits and the `faults` that name it. With
/// [`FrameSource::PerVehicle`] each vehicle's local frame starts where it stands
/// and its GPS origin and home are where it stands, from the mission's
/// `world.geo_origin` (PX4's default SITL home when it has none); with
/// [`FrameSource::Shared`] every vehicle reports in the mission frame.
pub fn vehicle_configs_in(
    mission: &Mission,
    plan: &DiscretePlan,
    flavour: Flavour,
    faults: &[FaultSpec],
    frames: FrameSource,
) -> Result<Vec<VehicleConfig>, BundledSitlError> {
    if plan.drones.len() > 254 {
        return Err(BundledSitlError::TooManyDrones(plan.drones.len()));
    }
    let ids: Vec<&str> = plan.drones.iter().map(|d| d.id.as_str()).collect();
    check_fault_drones(faults, &ids)?;
    let standing = plan.drones.iter().map(|d| {
        let start = mission.airspace.center_m(d.path[0]);
        (d.id.as_str(), [start.x, start.y, 0.0])
    });
    Ok(configs_standing(mission, standing, flavour, faults, frames))
}

/// Vehicle configurations for the mission's drones `ids` (a relay's share, in
/// that order, system ids 1, 2, …), each standing on its pad, with the mission's
/// limits and the `faults` that name it, each in its own local frame.
pub fn relay_vehicle_configs(
    mission: &Mission,
    ids: &[String],
    flavour: Flavour,
    faults: &[FaultSpec],
) -> Result<Vec<VehicleConfig>, BundledSitlError> {
    if ids.len() > 254 {
        return Err(BundledSitlError::TooManyDrones(ids.len()));
    }
    let mut standing = Vec::new();
    for id in ids {
        let Some((_, drone)) = mission.drones().find(|(_, d)| d.id == *id) else {
            let known: Vec<&str> = mission.drones().map(|(_, d)| d.id.as_str()).collect();
            return Err(BundledSitlError::NotInMission {
                drone: id.clone(),
                known: known.join(", "),
            });
        };
        standing.push((id.as_str(), mission.pad_ground_m(drone)));
    }
    let names: Vec<&str> = ids.iter().map(String::as_str).collect();
    check_fault_drones(faults, &names)?;
    Ok(configs_standing(
        mission,
        standing.into_iter(),
        flavour,
        faults,
        FrameSource::PerVehicle,
    ))
}

/// One configuration per `(drone id, ground ENU metres)`, system ids from 1.
fn configs_standing<'a>(
    mission: &Mission,
    standing: impl Iterator<Item = (&'a str, [f64; 3])>,
    flavour: Flavour,
    faults: &[FaultSpec],
    frames: FrameSource,
) -> Vec<VehicleConfig> {
    let origin = mission
        .geo_origin
        .map_or_else(GeoPoint::default, |g| GeoPoint {
            lat_deg: g.lat_deg,
            lon_deg: g.lon_deg,
            alt_amsl_m: g.alt_m,
        });
    standing
        .enumerate()
        .map(|(i, (id, ground_enu_m))| {
            let ground_ned_m = frames::ned_f32_from_enu(ground_enu_m);
            let mut c = VehicleConfig::new(i as u8 + 1, flavour).at(origin, ground_ned_m);
            if frames == FrameSource::PerVehicle {
                c = c.own_frame();
            }
            c.max_speed_mps = mission.limits.max_speed_mps as f32;
            c.max_accel_mps2 = mission.limits.max_accel_mps2 as f32;
            c.faults = faults_for(id, faults);
            // The link-loss failsafe swarmctl expects (see the README): hold where you
            // are, so the plan graph keeps everyone else clear of the silent drone.
            c.offboard_loss_land_after = Duration::MAX;
            c
        })
        .collect()
}

/// Refuses a `--fault` naming a drone not among `ids`.
fn check_fault_drones(faults: &[FaultSpec], ids: &[&str]) -> Result<(), BundledSitlError> {
    match unknown_drone(faults, ids) {
        Some(drone) => Err(BundledSitlError::UnknownDrone {
            drone: drone.to_string(),
            known: ids.join(", "),
        }),
        None => Ok(()),
    }
}
