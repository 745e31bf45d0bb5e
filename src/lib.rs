//! swarmctl: plan, schedule and fly drone swarms.
//!
//! The pipeline runs one way: [`mission::load`] → `plan::solve` → `schedule` →
//! `trajectory` → `fly`. Each stage is a pure function of the one before, except
//! `fly`, the only stage that talks to vehicles.

pub mod compiled;
pub mod fly;
pub mod generate;
pub mod import;
pub mod link;
pub mod mission;
pub mod plan;
pub mod profile;
pub mod schedule;
pub mod trajectory;
pub mod verify;
pub mod world;
