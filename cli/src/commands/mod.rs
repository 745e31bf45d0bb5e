//! One file per subcommand: argument struct and the code that reports its result.

pub mod bench;
pub mod bench_flight;
pub mod check;
pub mod fly;
pub mod generate;
pub mod pads;
pub mod plan;
pub mod replay;
pub mod sitl;
pub mod template;
