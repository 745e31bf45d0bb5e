//! Flights on the real autopilot firmware in `../shared/sitl/`: several ArduCopter
//! SITL instances (ArduPilot's own EKF, position controller and physics) and several
//! PX4 SITL instances with SIH (PX4's own estimator, offboard controller and
//! rigid-body simulator), each booted on loopback at its own home on its pad, so
//! each keeps its own local frame. swarmctl flies missions on them, and the
//! simulators' truth is measured apart from the telemetry swarmctl steered by.
//!
//! One flight at a time (each boots a whole swarm of firmware processes); the
//! bundled-simulator flights are in the `flights` binary.
// Tests may unwrap, expect and run long: a failure is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::too_many_lines)]

#[path = "../support/mod.rs"]
mod support;

mod arducopter;
mod fleet;
mod px4;
mod rogue;
mod truth;
