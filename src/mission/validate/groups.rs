//! Groups, their drones and their goals: names and ids unique across the mission,
//! every start and goal a free voxel used once, at least one goal per drone.
//!
//! Pads written in the file are read here (their placement, defaults and clashes
//! are `pads`' job, once every drone is known).

use super::fields::{check_drone_id, check_endpoint};
use super::report::Report;
use super::world::Bounds;
use crate::mission::schema::{DroneSpec, GroupSpec, RawVoxel};
use crate::mission::types::{Drone, Group, PadSource};
use crate::world::{Voxel, VoxelGrid};
use std::collections::HashMap;

/// MAVLink system ids a vehicle may use (0 is broadcast, 255 is the ground station).
const SYSTEM_IDS: std::ops::RangeInclusive<i64> = 1..=254;

/// Checks every group, in file order. A drone whose start is unusable is left out
/// of its group (its problem is reported), as is a goal that is not a free voxel.
pub(super) fn check_groups(
    specs: &[GroupSpec],
    world: &VoxelGrid,
    bounds: &Bounds,
    relay_of: &HashMap<String, String>,
    report: &mut Report,
) -> Vec<Group> {
    let mut checker = Checker {
        world,
        bounds,
        relay_of,
        report,
        seen: Seen::default(),
    };
    let groups = specs
        .iter()
        .enumerate()
        .map(|(gi, g)| checker.group(gi, g))
        .collect();
    check_endpoints_all_or_none(specs, report);
    groups
}

/// A mission flies its own vehicles (every drone names its endpoint) or the
/// bundled simulator (none does); a mix cannot be flown, so `check` says so, as
/// `fly` would, naming each drone without one.
fn check_endpoints_all_or_none(specs: &[GroupSpec], report: &mut Report) {
    let drones = || {
        specs
            .iter()
            .enumerate()
            .flat_map(|(gi, g)| g.drones.iter().enumerate().map(move |(di, d)| (gi, di, d)))
    };
    let total = drones().count();
    let with = drones().filter(|(_, _, d)| d.endpoint.is_some()).count();
    if with == 0 || with == total {
        return;
    }
    for (gi, di, d) in drones().filter(|(_, _, d)| d.endpoint.is_none()) {
        report.add(
            format!("groups[{gi}].drones[{di}].endpoint"),
            format!(
                "drone {:?} has no endpoint but {with} of the {total} drones have one: give all drones one, or none (to fly the bundled simulator)",
                d.id
            ),
        );
    }
}

/// What earlier groups and drones already use, each with the path of its first user
/// so a clash names both places.
#[derive(Default)]
struct Seen<'a> {
    group_names: HashMap<&'a str, usize>,
    drone_ids: HashMap<&'a str, String>,
    /// By relay (a relay is a MAVLink network of its own; `None`: the controller's).
    system_ids: HashMap<(Option<&'a str>, i64), String>,
    starts: HashMap<Voxel, String>,
    goals: HashMap<Voxel, String>,
}

/// The world the groups are placed in, and what is found while checking them.
struct Checker<'a, 'r> {
    world: &'a VoxelGrid,
    bounds: &'a Bounds,
    relay_of: &'a HashMap<String, String>,
    report: &'r mut Report,
    seen: Seen<'a>,
}

impl<'a> Checker<'a, '_> {
    fn group(&mut self, gi: usize, g: &'a GroupSpec) -> Group {
        let gpath = format!("groups[{gi}]");
        if g.name.trim().is_empty() {
            self.report
                .add(format!("{gpath}.name"), "must not be empty");
        } else if let Some(first) = self.seen.group_names.insert(&g.name, gi) {
            self.report.add(
                format!("{gpath}.name"),
                format!("group name {:?} is already used by groups[{first}]", g.name),
            );
        }
        if g.drones.is_empty() {
            self.report.add(
                format!("{gpath}.drones"),
                format!("group {:?} has no drones", g.name),
            );
        }
        if g.goals.is_empty() {
            self.report.add(
                format!("{gpath}.goals"),
                format!(
                    "group {:?} has no goals; give at least one (drones beyond the goals are spares)",
                    g.name
                ),
            );
        }
        let with_start = g.drones.iter().filter(|d| d.start.is_some()).count();
        if with_start != 0 && with_start != g.drones.len() {
            self.report.add(
                format!("{gpath}.drones"),
                format!(
                    "group {:?}: {with_start} of its {} drones have a start; give every drone of a group a start, or none (then they fly from their pads straight to the goals)",
                    g.name,
                    g.drones.len()
                ),
            );
        }
        let drones = g
            .drones
            .iter()
            .enumerate()
            .filter_map(|(di, d)| self.drone(format!("{gpath}.drones[{di}]"), d))
            .collect();
        let goals = g
            .goals
            .iter()
            .enumerate()
            .filter_map(|(ki, &raw)| self.goal(format!("{gpath}.goals[{ki}]"), raw))
            .collect();
        let group = Group {
            name: g.name.clone(),
            drones,
            goals,
            free_pads: Vec::new(),
        };
        self.check_spare_holds(&gpath, &group, &group.goals, "its goals");
        group
    }

    /// A spare holds at its start (see `Group::spare_holds`): that start must not
    /// be one of the goals of the formation, or the group could not fill them all.
    fn check_spare_holds(&mut self, gpath: &str, group: &Group, goals: &[Voxel], which: &str) {
        let spares = group.drones.len().saturating_sub(goals.len());
        let first_spare = group.drones.len() - spares;
        for (k, hold) in group.spare_holds(goals.len()).into_iter().enumerate() {
            if goals.contains(&hold) {
                self.report.add(
                    format!("{gpath}.drones[{}].start", first_spare + k),
                    format!(
                        "group {:?} has {} drones for {} goals, so its last {spares} are spares and hold at their starts, but {hold} is one of {which}; give the spare another start",
                        group.name,
                        group.drones.len(),
                        goals.len()
                    ),
                );
            }
        }
    }

    /// The drone at `dpath`, or `None` when its start is unusable.
    fn drone(&mut self, dpath: String, d: &'a DroneSpec) -> Option<Drone> {
        if let Err(why) = check_drone_id(&d.id) {
            self.report.add(format!("{dpath}.id"), why);
        } else if let Some(first) = self.seen.drone_ids.insert(&d.id, dpath.clone()) {
            self.report.add(
                format!("{dpath}.id"),
                format!("drone id {:?} is already used by {first}", d.id),
            );
        }
        let start = match d.start {
            Some(raw) => Some(self.free_voxel(&format!("{dpath}.start"), raw)?),
            None => None,
        };
        if let Some(v) = start
            && let Some(first) = self.seen.starts.insert(v, dpath.clone())
        {
            self.report.add(
                format!("{dpath}.start"),
                format!("{v} is already the start of {first}"),
            );
        }
        let pad = match d.pad {
            Some(raw) => Some(self.pad(&format!("{dpath}.pad"), raw)?),
            None => None,
        };
        if pad.is_none() && start.is_none() {
            self.report.add(
                dpath.clone(),
                format!(
                    "drone {:?} has neither a start nor a pad: give a pad [x, y] (where it stands) or a start voxel",
                    d.id
                ),
            );
        }
        if let Some(Err(why)) = d.endpoint.as_deref().map(check_endpoint) {
            self.report.add(format!("{dpath}.endpoint"), why);
        }
        let system_id = self.system_id(&dpath, &d.id, d.system_id);
        Some(Drone {
            id: d.id.clone(),
            start,
            // Pads left out are chosen by `pads` once every drone is known.
            pad: pad.unwrap_or([0, 0]),
            pad_source: if pad.is_some() {
                PadSource::Given
            } else {
                PadSource::Assigned
            },
            endpoint: d.endpoint.clone(),
            system_id,
        })
    }

    /// The vehicle's MAVLink system id, when one is given and usable.
    fn system_id(&mut self, dpath: &str, drone: &str, id: Option<i64>) -> Option<u8> {
        let id = id?;
        let Some(vehicle_id) = u8::try_from(id).ok().filter(|_| SYSTEM_IDS.contains(&id)) else {
            self.report.add(
                format!("{dpath}.system_id"),
                format!(
                    "{id} is not a vehicle system id (1 to 254; 0 is broadcast, 255 the ground station)"
                ),
            );
            return None;
        };
        let relay = self.relay_of.get(drone).map(String::as_str);
        if let Some(first) = self.seen.system_ids.insert((relay, id), dpath.to_string()) {
            let network = relay.map_or(String::new(), |r| format!(" in relay {r}'s network"));
            self.report.add(
                format!("{dpath}.system_id"),
                format!("system id {id} is already used by {first}{network}"),
            );
        }
        Some(vehicle_id)
    }

    /// A written pad, when it lies within `PAD_REACH` voxels of the world's footprint.
    fn pad(&mut self, path: &str, raw: [i64; 2]) -> Option<[i32; 2]> {
        let reach = i64::from(super::bounds::PAD_REACH);
        let [dx, dy, _] = self.bounds.dimensions();
        if let Some(cell) = self.bounds.launch_cell(raw) {
            Some(cell)
        } else {
            self.report.add(
                path,
                format!(
                    "pad {raw:?} is too far from the world: pads lie at most {reach} voxels beside it (x from {} to {}, y from {} to {})",
                    -reach,
                    i64::from(dx) + reach - 1,
                    -reach,
                    i64::from(dy) + reach - 1
                ),
            );
            None
        }
    }

    /// The goal at `kpath`, when it is a free voxel (a goal used twice is reported
    /// but kept, so the group's goal count stays as written).
    fn goal(&mut self, kpath: String, raw: RawVoxel) -> Option<Voxel> {
        let v = self.free_voxel(&kpath, raw)?;
        if let Some(first) = self.seen.goals.insert(v, kpath.clone()) {
            self.report
                .add(kpath, format!("goal {v} is already used by {first}"));
        }
        Some(v)
    }

    /// The voxel at `raw` when it is inside the world and not an obstacle.
    fn free_voxel(&mut self, path: &str, raw: RawVoxel) -> Option<Voxel> {
        super::world::free_voxel(self.world, self.bounds, path, raw, self.report)
    }
}
