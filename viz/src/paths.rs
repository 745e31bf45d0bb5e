//! Entity paths, built from drone ids so any id (even one with `/`) is one part.

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

pub fn world_bounds() -> EntityPath {
    path(&["world", "bounds"])
}
pub fn obstacles() -> EntityPath {
    path(&["world", "obstacles"])
}
pub fn starts(group: &str) -> EntityPath {
    path(&["world", "plan", "starts", group])
}
pub fn goals(group: &str) -> EntityPath {
    path(&["world", "plan", "goals", group])
}
pub fn plan_path(drone: &str) -> EntityPath {
    path(&["world", "plan", "paths", drone])
}
/// A drone's scheduled position (`kind` is `plan` or `flight`).
pub fn drone(kind: &str, drone: &str) -> EntityPath {
    path(&["world", kind, "drones", drone])
}
/// The sphere around a drone whose overlap with another means a safety breach.
pub fn safety(kind: &str, drone: &str) -> EntityPath {
    path(&["world", kind, "safety", drone])
}
/// The path a drone actually flew.
pub fn flown_path(drone: &str) -> EntityPath {
    path(&["world", "flight", "paths", drone])
}
pub fn speed(kind: &str, drone: &str) -> EntityPath {
    path(&["metrics", kind, "speed_mps", drone])
}
pub fn min_separation(kind: &str) -> EntityPath {
    path(&["metrics", kind, "min_separation_m"])
}
pub fn safety_distance(kind: &str) -> EntityPath {
    path(&["metrics", kind, "safety_distance_m"])
}
pub fn events(kind: &str) -> EntityPath {
    path(&["events", kind])
}
