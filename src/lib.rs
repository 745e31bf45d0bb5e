//! swarmctl: plan, schedule and fly drone swarms.
//!
//! The pipeline runs one way: [`mission::load`] → `plan::solve` → `schedule` →
//! `trajectory` → `fly`. Each stage is a pure function of the one before, except
//! `fly`, the only stage that talks to vehicles.
//!
//! The modules are layered, each importing only those before it: `world`, `profile`
//! (the speed profile both the scheduler and the trajectories use), `mission`,
//! `import` and `generate`, `plan`, `schedule`, `trajectory`, `verify`, `compiled`
//! (the plan file, written and read), `link`, `fly`. The checkers (`plan`'s
//! validator, `verify`) import nothing they check. The pipeline test `layering`
//! holds the order and finds import cycles between the files of a module.

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
