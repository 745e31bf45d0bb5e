//! The parts of the `swarmctl` command that are more than argument parsing: the
//! Rerun recording glue (swarmctl's types into `swarmctl-viz`'s) and the live
//! status view. The binary's commands live in `main.rs`; this library exists so
//! benchmarks can drive the recorder exactly as `swarmctl fly` does.

pub mod error_text;
pub mod record;
pub mod status;
