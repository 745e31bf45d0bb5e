//! Turns a parsed [`MissionFile`] into a [`Mission`], reporting every problem at once.

use super::error::Problem;
use super::schema::{MissionFile, ObstacleSpec, RawVoxel};
use super::types::{Drone, Group, KeySource, Limits, LinkSettings, Mission};
use crate::world::{Voxel, VoxelGrid};
use std::collections::{BTreeMap, HashMap};

/// Largest accepted edge of the world, in voxels.
pub const MAX_DIMENSION: i64 = 4096;
/// Largest accepted world, in voxels (the planner's time-expanded networks grow with it).
pub const MAX_VOXELS: i64 = 1 << 24;
/// MAVLink system ids a vehicle may use (0 is broadcast, 255 is the ground station).
const SYSTEM_IDS: std::ops::RangeInclusive<i64> = 1..=254;
/// PX4 leaves offboard below 2 Hz; far above 100 Hz no autopilot listens.
const SETPOINT_RATES_HZ: std::ops::RangeInclusive<f64> = 2.5..=100.0;

/// Checks a parsed mission. Returns every problem found, not just the first.
pub fn validate(file: &MissionFile) -> Result<Mission, Vec<Problem>> {
    let mut problems = Vec::new();
    let mut report = |path: String, message: String| problems.push(Problem::new(path, message));

    if file.name.trim().is_empty() {
        report("name".into(), "must not be empty".into());
    }

    // World bounds first: nothing else can be checked without them.
    let dims = file.world.dimensions;
    let mut dims_ok = true;
    for (axis, &d) in ["x", "y", "z"].iter().zip(&dims) {
        if !(1..=MAX_DIMENSION).contains(&d) {
            dims_ok = false;
            report(
                "world.dimensions".into(),
                format!("{axis} extent {d} must be between 1 and {MAX_DIMENSION} voxels"),
            );
        }
    }
    if dims_ok && dims.iter().product::<i64>() > MAX_VOXELS {
        dims_ok = false;
        report(
            "world.dimensions".into(),
            format!(
                "{dims:?} holds {} voxels; at most {MAX_VOXELS} are supported",
                dims.iter().product::<i64>()
            ),
        );
    }
    let voxel_size_m = file.world.voxel_size_m;
    check_positive(&mut report, "world.voxel_size_m", voxel_size_m, "m");
    if file.world.origin_m.iter().any(|c| !c.is_finite()) {
        report("world.origin_m".into(), "must be finite numbers".into());
    }
    let limits = &file.limits;
    check_positive(
        &mut report,
        "limits.max_speed_mps",
        limits.max_speed_mps,
        "m/s",
    );
    check_positive(
        &mut report,
        "limits.max_accel_mps2",
        limits.max_accel_mps2,
        "m/s²",
    );
    check_positive(
        &mut report,
        "limits.safety_distance_m",
        limits.safety_distance_m,
        "m",
    );
    let link = &file.link;
    if !SETPOINT_RATES_HZ.contains(&link.setpoint_rate_hz) {
        report(
            "link.setpoint_rate_hz".into(),
            format!(
                "{} Hz is outside {}..={} Hz (autopilots drop offboard control below 2 Hz)",
                link.setpoint_rate_hz,
                SETPOINT_RATES_HZ.start(),
                SETPOINT_RATES_HZ.end()
            ),
        );
    }
    check_positive(&mut report, "link.link_timeout_s", link.link_timeout_s, "s");
    let signing = match &link.signing {
        None => None,
        Some(spec) => match (&spec.key_file, &spec.key_env) {
            (Some(file), None) if !file.as_os_str().is_empty() => {
                Some(KeySource::File(file.clone()))
            }
            (None, Some(var)) if !var.trim().is_empty() => Some(KeySource::Env(var.clone())),
            (Some(_), Some(_)) => {
                report(
                    "link.signing".into(),
                    "give key_file or key_env, not both".into(),
                );
                None
            }
            _ => {
                report(
                    "link.signing".into(),
                    "needs key_file (a file with 64 hex digits) or key_env (an environment variable holding them)".into(),
                );
                None
            }
        },
    };

    if file.groups.is_empty() {
        report(
            "groups".into(),
            "a mission needs at least one group of drones".into(),
        );
    }
    if !dims_ok {
        return Err(problems);
    }
    let dims = dims.map(|d| d as u32);
    let mut world = VoxelGrid::new(dims, voxel_size_m, file.world.origin_m);
    let in_world = |raw: RawVoxel| -> Option<Voxel> {
        let ok = raw
            .iter()
            .zip(&dims)
            .all(|(&c, &d)| (0..i64::from(d)).contains(&c));
        ok.then(|| Voxel::new(raw[0] as u32, raw[1] as u32, raw[2] as u32))
    };
    let outside = |raw: RawVoxel| {
        format!(
            "{raw:?} is outside the world (dimensions {:?}, coordinates from 0 to {:?})",
            dims,
            dims.map(|d| d - 1)
        )
    };

    for (i, obstacle) in file.world.obstacles.iter().enumerate() {
        let path = format!("world.obstacles[{i}]");
        match obstacle {
            ObstacleSpec::Cell(raw) => match in_world(*raw) {
                Some(v) => world.block(v),
                None => report(path, outside(*raw)),
            },
            ObstacleSpec::Box(b) => {
                let (min, max) = match (in_world(b.min), in_world(b.max)) {
                    (Some(min), Some(max)) => (min, max),
                    (min, _) => {
                        let (field, raw) = if min.is_none() {
                            ("min", b.min)
                        } else {
                            ("max", b.max)
                        };
                        report(format!("{path}.{field}"), outside(raw));
                        continue;
                    }
                };
                if min.x > max.x || min.y > max.y || min.z > max.z {
                    report(path, format!("min {min} exceeds max {max} on some axis"));
                    continue;
                }
                for z in min.z..=max.z {
                    for y in min.y..=max.y {
                        for x in min.x..=max.x {
                            world.block(Voxel::new(x, y, z));
                        }
                    }
                }
            }
        }
    }

    let mut group_names: HashMap<&str, usize> = HashMap::new();
    let mut drone_ids: HashMap<&str, String> = HashMap::new();
    let mut system_ids: HashMap<i64, String> = HashMap::new();
    let mut starts: HashMap<Voxel, String> = HashMap::new();
    let mut goals_seen: HashMap<Voxel, String> = HashMap::new();
    let mut groups = Vec::with_capacity(file.groups.len());

    for (gi, g) in file.groups.iter().enumerate() {
        let gpath = format!("groups[{gi}]");
        if g.name.trim().is_empty() {
            report(format!("{gpath}.name"), "must not be empty".into());
        } else if let Some(first) = group_names.insert(&g.name, gi) {
            report(
                format!("{gpath}.name"),
                format!("group name {:?} is already used by groups[{first}]", g.name),
            );
        }
        if g.drones.is_empty() {
            report(
                format!("{gpath}.drones"),
                format!("group {:?} has no drones", g.name),
            );
        }
        if g.goals.len() != g.drones.len() {
            report(
                format!("{gpath}.goals"),
                format!(
                    "group {:?} has {} goal(s) for {} drone(s); give exactly one goal per drone",
                    g.name,
                    g.goals.len(),
                    g.drones.len()
                ),
            );
        }
        let mut drones = Vec::with_capacity(g.drones.len());
        for (di, d) in g.drones.iter().enumerate() {
            let dpath = format!("{gpath}.drones[{di}]");
            if let Err(why) = check_drone_id(&d.id) {
                report(format!("{dpath}.id"), why);
            } else if let Some(first) = drone_ids.insert(&d.id, dpath.clone()) {
                report(
                    format!("{dpath}.id"),
                    format!("drone id {:?} is already used by {first}", d.id),
                );
            }
            let start = match in_world(d.start) {
                None => {
                    report(format!("{dpath}.start"), outside(d.start));
                    None
                }
                Some(v) if world.is_blocked(v) => {
                    report(
                        format!("{dpath}.start"),
                        format!("{v} is inside an obstacle"),
                    );
                    None
                }
                Some(v) => {
                    if let Some(first) = starts.insert(v, dpath.clone()) {
                        report(
                            format!("{dpath}.start"),
                            format!("{v} is already the start of {first}"),
                        );
                    }
                    Some(v)
                }
            };
            if let Some(Err(why)) = d.endpoint.as_deref().map(check_endpoint) {
                report(format!("{dpath}.endpoint"), why);
            }
            let system_id = match d.system_id {
                None => None,
                Some(id) if !SYSTEM_IDS.contains(&id) => {
                    report(
                        format!("{dpath}.system_id"),
                        format!(
                            "{id} is not a vehicle system id (1 to 254; 0 is broadcast, 255 the ground station)"
                        ),
                    );
                    None
                }
                Some(id) => {
                    if let Some(first) = system_ids.insert(id, dpath.clone()) {
                        report(
                            format!("{dpath}.system_id"),
                            format!("system id {id} is already used by {first}"),
                        );
                    }
                    Some(id as u8)
                }
            };
            if let Some(start) = start {
                drones.push(Drone {
                    id: d.id.clone(),
                    start,
                    endpoint: d.endpoint.clone(),
                    system_id,
                });
            }
        }
        let mut goals = Vec::with_capacity(g.goals.len());
        for (ki, &raw) in g.goals.iter().enumerate() {
            let kpath = format!("{gpath}.goals[{ki}]");
            match in_world(raw) {
                None => report(kpath, outside(raw)),
                Some(v) if world.is_blocked(v) => {
                    report(kpath, format!("{v} is inside an obstacle"))
                }
                Some(v) => {
                    if let Some(first) = goals_seen.insert(v, kpath.clone()) {
                        report(kpath, format!("goal {v} is already used by {first}"));
                    }
                    goals.push(v);
                }
            }
        }
        groups.push(Group {
            name: g.name.clone(),
            drones,
            goals,
        });
    }

    if !problems.is_empty() {
        return Err(problems);
    }
    check_reachability(&world, &groups, &mut problems);
    if !problems.is_empty() {
        return Err(problems);
    }
    Ok(Mission {
        name: file.name.clone(),
        description: file.description.clone(),
        world,
        limits: Limits {
            max_speed_mps: limits.max_speed_mps,
            max_accel_mps2: limits.max_accel_mps2,
            safety_distance_m: limits.safety_distance_m,
        },
        link: LinkSettings {
            autopilot: link.autopilot,
            setpoint_rate_hz: link.setpoint_rate_hz,
            link_timeout_s: link.link_timeout_s,
            signing,
        },
        groups,
    })
}

fn check_positive(report: &mut impl FnMut(String, String), path: &str, value: f64, unit: &str) {
    if !(value.is_finite() && value > 0.0) {
        report(
            path.into(),
            format!("must be a positive number of {unit}, got {value}"),
        );
    }
}

/// Ids appear in command-line flags (`--fault slow=ID:0.5`) and log paths, so they
/// keep to characters that need no quoting there.
fn check_drone_id(id: &str) -> Result<(), String> {
    if id.is_empty() {
        return Err("must not be empty".into());
    }
    if id.len() > 64 {
        return Err(format!("{id:?} is longer than 64 characters"));
    }
    if let Some(c) = id
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.')))
    {
        return Err(format!(
            "{id:?} contains {c:?}; use letters, digits, '-', '_' or '.'"
        ));
    }
    Ok(())
}

/// Accepts the connection strings rust-mavlink understands.
fn check_endpoint(endpoint: &str) -> Result<(), String> {
    const NETWORK: [&str; 5] = ["udpin", "udpout", "udpcast", "tcpin", "tcpout"];
    let Some((scheme, rest)) = endpoint.split_once(':') else {
        return Err(format!(
            "{endpoint:?} lacks a scheme; write e.g. \"udpout:127.0.0.1:14541\""
        ));
    };
    if scheme == "serial" {
        return match rest.rsplit_once(':') {
            Some((port, baud)) if !port.is_empty() && baud.parse::<u32>().is_ok() => Ok(()),
            _ => Err(format!(
                "{endpoint:?}: write serial endpoints as \"serial:/dev/ttyUSB0:57600\""
            )),
        };
    }
    if !NETWORK.contains(&scheme) {
        return Err(format!(
            "unknown scheme {scheme:?} in {endpoint:?}; use one of {}, serial",
            NETWORK.join(", ")
        ));
    }
    match rest.rsplit_once(':') {
        Some((host, port)) if !host.is_empty() && port.parse::<u16>().is_ok_and(|p| p > 0) => {
            Ok(())
        }
        _ => Err(format!(
            "{endpoint:?}: expected {scheme}:HOST:PORT with a port from 1 to 65535"
        )),
    }
}

/// Every drone must reach a distinct goal of its own group. Free space splits into
/// connected components, and within one component every drone reaches every goal, so
/// a group can be matched exactly when each component holds as many of its goals as
/// of its drones (Hall's condition on a union of complete bipartite graphs).
fn check_reachability(world: &VoxelGrid, groups: &[Group], problems: &mut Vec<Problem>) {
    let label = world.components();
    let component = |v: Voxel| world.cell(v).map(|c| label[c]);
    for (gi, g) in groups.iter().enumerate() {
        let mut balance: BTreeMap<Option<u32>, (Vec<usize>, usize)> = BTreeMap::new();
        for (di, d) in g.drones.iter().enumerate() {
            balance.entry(component(d.start)).or_default().0.push(di);
        }
        for &goal in &g.goals {
            balance.entry(component(goal)).or_default().1 += 1;
        }
        for (drones, goal_count) in balance.values() {
            if drones.len() <= *goal_count {
                continue;
            }
            let ids: Vec<&str> = drones.iter().map(|&di| g.drones[di].id.as_str()).collect();
            let path = if drones.len() == 1 {
                format!("groups[{gi}].drones[{}]", drones[0])
            } else {
                format!("groups[{gi}]")
            };
            let message = if *goal_count == 0 {
                format!(
                    "group {:?}: drone(s) {} can reach no goal of their group (walled off by obstacles)",
                    g.name,
                    ids.join(", ")
                )
            } else {
                format!(
                    "group {:?}: drones {} share a region of free space with only {goal_count} of the group's goals, so they cannot all reach distinct goals",
                    g.name,
                    ids.join(", ")
                )
            };
            problems.push(Problem::new(path, message));
        }
    }
}
