//! The `swarmctl` command line end to end, run as a user runs it: `check`,
//! `plan`, `gen`, `replay` and the Rerun recordings, `bench peers`, flights through relays, the
//! messages and exit codes an operator meets, starting a flight at a given
//! instant, and every shell block of the README.
// Tests may unwrap, expect and run long: a failure is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::too_many_lines)]

#[path = "../support/mod.rs"]
mod support;

mod bench_peers;
mod cli_check;
mod cli_plan;
mod closed_pipe;
mod operator;
mod readme;
mod relays;
mod start_at;
mod viz_recordings;
