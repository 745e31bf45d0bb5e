//! Entity paths. `kind` is `plan` or `flight`.
//!
//! A swarm is logged as a few entities holding every drone as one instance (drone
//! `i` of the scene is instance `i`, labelled with its id), not as one entity per
//! drone: a recording of 100 drones then costs a few chunks per flush instead of
//! hundreds, which is what keeps live recording cheap next to the flight itself.

use rerun::{EntityPath, EntityPathPart};

fn path(parts: &[&str]) -> EntityPath {
    EntityPath::new(parts.iter().map(|p| EntityPathPart::new(*p)).collect())
}

/// The whole 3D scene; a 3D view is rooted here.
pub const WORLD: &str = "world";
/// Time series (speeds, separation); a time series view is rooted here.
pub const METRICS: &str = "metrics";
/// Text events (TPG waits, flight events).
pub const EVENTS: &str = "events";

/// The world's bounding box.
pub fn world_bounds() -> EntityPath {
    path(&["world", "bounds"])
}
/// The obstacle voxels, as boxes.
pub fn obstacles() -> EntityPath {
    path(&["world", "obstacles"])
}
/// Start markers of one group's drones.
pub fn starts(group: &str) -> EntityPath {
    path(&["world", "plan", "starts", group])
}
/// Goal markers of one group's drones.
pub fn goals(group: &str) -> EntityPath {
    path(&["world", "plan", "goals", group])
}
/// Every drone's position: one point per drone, labelled with its id.
pub fn drones(kind: &str) -> EntityPath {
    path(&["world", kind, "drones"])
}
/// The separation spheres (or ellipsoids) around the drones, drawn at half the
/// separation so that two overlap exactly when the drones breach it.
pub fn safety(kind: &str) -> EntityPath {
    path(&["world", kind, "safety"])
}
/// Planned voxel paths (`plan`) or flown paths (`flight`): one line strip per drone.
pub fn paths(kind: &str) -> EntityPath {
    path(&["world", kind, "paths"])
}
/// Every drone's speed: one series per drone, named by its id.
pub fn speeds(kind: &str) -> EntityPath {
    path(&["metrics", kind, "speed_mps"])
}
/// The swarm's minimum pairwise separation over time, metres.
pub fn min_separation(kind: &str) -> EntityPath {
    path(&["metrics", kind, "min_separation_m"])
}
/// The swarm's minimum scaled separation over time (ellipsoid only): separated
/// when at least 1.
pub fn min_scaled_separation(kind: &str) -> EntityPath {
    path(&["metrics", kind, "min_scaled_separation"])
}
/// The scaled separation's limit, 1, as a flat line beside it (ellipsoid only).
pub fn scaled_limit(kind: &str) -> EntityPath {
    path(&["metrics", kind, "scaled_limit"])
}
/// The safety distance as a flat line beside the separation, metres.
pub fn safety_distance(kind: &str) -> EntityPath {
    path(&["metrics", kind, "safety_distance_m"])
}
/// One drone's lateness against the schedule at each event it reached, seconds.
pub fn lateness(kind: &str, drone: &str) -> EntityPath {
    path(&["metrics", kind, "lateness_s", drone])
}
/// Text events: TPG waits in a plan, the flight log's events in a flight.
pub fn events(kind: &str) -> EntityPath {
    path(&["events", kind])
}
