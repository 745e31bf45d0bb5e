//! The pipeline library on its own: mission files, planning, scheduling and plan
//! files, with no simulator, viewer or command line linked.
// Tests may unwrap, expect and run long: a failure is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::too_many_lines)]

#[path = "../support/mod.rs"]
mod support;

mod anytime;
mod architecture_doc;
mod ellipsoid;
mod file_sizes;
mod fuzz_plan;
mod ground_to_ground;
mod import_inputs;
mod layering;
mod mission_validation;
mod open_sky;
mod plan_optimality;
mod schedule_cases;
mod schedule_missions;
mod schedule_props;
mod valid_missions;
mod world_model;
