//! The fault matrix: one mission flown on the bundled SITL under each fault a
//! real swarm meets (lossy, slow and reordering links, a link cut or lost, a
//! drone refusing to arm, slow, or low on battery), each with the behaviour swarmctl promises, checked
//! against what happened.
//!
//! Separation is measured twice: from telemetry during plan execution (what the
//! executor saw) and from the simulator's true positions over the whole flight,
//! takeoff and landing included, for every airborne pair (what really happened,
//! including drones the executor could no longer hear).
//!
//! The matrix is split by concept: `cases` lists the scenarios and what each
//! must do, `run` flies one of them and watches the simulator's truth,
//! `judge` holds what happened against the promise, and `report` puts the
//! outcome into words and the Markdown table.

mod cases;
mod judge;
mod report;
mod run;

pub use cases::{Expect, Scenario, scenarios};
pub use report::{ScenarioReport, markdown_table};
pub use run::run_scenario;
