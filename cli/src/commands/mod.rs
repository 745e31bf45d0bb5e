//! One file per subcommand: argument struct and the code that reports its result.

pub mod bench;
pub mod bench_flight;
pub mod bench_relays;
pub mod check;
pub mod fly;
pub mod fly_relays;
pub mod generate;
pub mod pads;
pub mod plan;
pub mod relay;
pub mod replay;
pub mod sitl;
pub mod template;
