//! Flights against the bundled simulator: end-to-end missions, faults, signing,
//! the fault matrix, soak and load, and the controller's link under hostile input.
// Tests may unwrap, expect and run long: a failure is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::too_many_lines)]

#[path = "../support/mod.rs"]
mod support;

mod fault_matrix;
mod fly_common;
mod fly_downwash;
mod fly_faults;
mod fly_fence;
mod fly_formation;
mod fly_paper_scale;
mod fly_preflight;
mod fly_signing;
mod fly_swap;
mod fuzz_link;
mod load;
mod soak;
