//! Rerun recordings of swarmctl plans and flights.
//!
//! This is the only crate in the workspace that links `rerun`, so the SDK's long
//! build stays out of every other crate. It does not depend on `swarmctl` (the
//! `swarmctl` binary depends on it); instead it takes its own small, plain input
//! types: a [`Scene`] for what was planned and a streaming [`Recorder`] for what
//! was flown. Converting swarmctl's types into these lives in `swarmctl::record`.
//!
//! Frames and units: positions are ENU metres (x east, y north, z up), times are
//! seconds. Entity paths are in [`paths`]: a swarm is a few entities holding every
//! drone as one instance labelled with its id, so a recording costs a few chunks
//! per flush whatever the number of drones.

mod blueprint;
mod error;
mod metrics;
pub mod paths;
mod plan;
mod recorder;
mod scene;
mod sink;
mod style;
mod swarm;
mod world;

pub use error::VizError;
pub use plan::write_scene;
pub use recorder::{
    FlightSample, RECORDER_THREAD, Recorder, RecorderHandle, RecorderOptions, RecorderStats,
};
pub use scene::{Bounds, Drone, Group, ObstacleBox, PlanEvent, Scene, TimeAxis};
pub use sink::Sink;

/// Timeline of the schedule: seconds since the plan's start.
pub const PLAN_TIMELINE: &str = "plan_time";
/// Timeline of a flight: seconds since the first arm command.
pub const FLIGHT_TIMELINE: &str = "flight_time";
