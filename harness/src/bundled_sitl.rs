//! Starting the bundled mock autopilots (`swarmctl-sitl`) for a mission that names
//! no endpoints: one vehicle per drone on an ephemeral loopback port, on the
//! ground below its start voxel, with the mission's limits and the `--fault` flags.

use std::net::{IpAddr, Ipv4Addr};
use std::time::Duration;
use swarmctl::fly::VehicleLink;
use swarmctl::fly::{FaultSpec, FrameSource};
use swarmctl::link::frames;
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;
use swarmctl_sitl::{Faults, Flavour, GeoPoint, LinkDrop, Swarm, VehicleConfig};

/// The bundled vehicles report a position and their pre-arm state at once: a
/// vehicle not ready this soon will not become ready (a `refuse-arm` fault).
pub const READY_TIMEOUT: Duration = Duration::from_secs(5);

/// Flight options for the bundled vehicles at `links`: the defaults, with the
/// bundled simulator's [`READY_TIMEOUT`].
pub fn fly_options(links: Vec<VehicleLink>) -> swarmctl::fly::FlyOptions {
    let mut options = swarmctl::fly::FlyOptions::new(links);
    options.ready_timeout = READY_TIMEOUT;
    options
}

/// The autopilot the bundled SITL imitates: `choice` (`--autopilot`: `px4` or
/// `ardupilot`) when given, else the mission's `link.autopilot`.
pub fn flavour(choice: Option<&str>, mission: &Mission) -> Flavour {
    match choice {
        Some("ardupilot") => Flavour::ArduPilot,
        Some(_) => Flavour::Px4,
        None => match mission.link.autopilot {
            swarmctl::mission::Autopilot::Px4 => Flavour::Px4,
            swarmctl::mission::Autopilot::Ardupilot => Flavour::ArduPilot,
        },
    }
}

/// A low battery turns critical (and the autopilot lands) this long after the warning.
const CRITICAL_AFTER_LOW: Duration = Duration::from_secs(45);

/// Why the bundled SITL could not be set up for a mission.
#[derive(Debug, thiserror::Error)]
pub enum BundledSitlError {
    /// A `--fault` flag targets a drone the plan does not fly.
    #[error("--fault names drone {drone:?}, which is not in the mission (drones: {known})")]
    UnknownDrone {
        /// The drone id the fault names.
        drone: String,
        /// The plan's drone ids, comma-separated, to show what was meant.
        known: String,
    },
    /// A relay was given a drone the mission does not have.
    #[error("no drone {drone:?} in the mission (drones: {known})")]
    NotInMission {
        /// The drone id given.
        drone: String,
        /// The mission's drone ids, comma-separated.
        known: String,
    },
    /// More drones than MAVLink system ids the SITL hands out (1–254); the field
    /// is how many the plan has.
    #[error("the bundled SITL gives system ids 1–254, so at most 254 drones ({0} given)")]
    TooManyDrones(usize),
    /// The vehicles could not be spawned (a socket could not be bound).
    #[error("cannot start the bundled SITL: {0}")]
    Spawn(#[from] swarmctl_sitl::SitlError),
}

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
    check_fault_drones(faults, plan.drones.iter().map(|d| d.id.as_str()))?;
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
    check_fault_drones(faults, ids.iter().map(String::as_str))?;
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
fn check_fault_drones<'a>(
    faults: &[FaultSpec],
    ids: impl Iterator<Item = &'a str> + Clone,
) -> Result<(), BundledSitlError> {
    for f in faults {
        if let Some(drone) = f.drone()
            && !ids.clone().any(|d| d == drone)
        {
            let known: Vec<&str> = ids.clone().collect();
            return Err(BundledSitlError::UnknownDrone {
                drone: drone.to_string(),
                known: known.join(", "),
            });
        }
    }
    Ok(())
}

/// The SITL faults of vehicle `drone`: link-wide faults apply to everyone,
/// drone faults only to the drone they name.
fn faults_for(drone: &str, faults: &[FaultSpec]) -> Faults {
    let mut out = Faults::default();
    for f in faults {
        match f {
            FaultSpec::Loss { percent } => out.loss_percent = *percent,
            FaultSpec::Latency { latency } => out.latency = *latency,
            FaultSpec::Slow { drone: d, factor } if d == drone => out.speed_factor = *factor,
            FaultSpec::Drop {
                drone: d,
                after,
                duration,
            } if d == drone => {
                out.link_drop = Some(LinkDrop {
                    after_takeoff: *after,
                    duration: *duration,
                })
            }
            FaultSpec::RefuseArm { drone: d } if d == drone => out.refuse_arm = true,
            FaultSpec::Duplicate { percent } => out.duplicate_percent = *percent,
            FaultSpec::Reorder { percent } => out.reorder_percent = *percent,
            FaultSpec::Lose { drone: d, after } if d == drone => {
                out.link_drop = Some(LinkDrop {
                    after_takeoff: *after,
                    duration: Duration::MAX,
                })
            }
            FaultSpec::Crash { drone: d, after } if d == drone => {
                out.crash_after_takeoff = Some(*after);
            }
            FaultSpec::LowBattery { drone: d, after } if d == drone => {
                out.low_battery_after = Some(*after);
                out.critical_battery_after = Some(*after + CRITICAL_AFTER_LOW);
            }
            FaultSpec::CriticalBattery { drone: d, after } if d == drone => {
                out.critical_battery_after = Some(*after)
            }
            _ => {}
        }
    }
    out
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
