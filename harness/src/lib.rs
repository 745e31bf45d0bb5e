//! Reproducible benchmark suites behind `swarmctl bench`: the planner suites,
//! the fault matrix, the soak, load and relay-load runners, the timing of
//! flights against their schedules, and the side-by-side runs with the public
//! solvers.
//!
//! Each suite is a list of seeded instances; the report gives medians and maxima, so
//! a noisy shared machine shows as spread rather than as a wrong figure.

mod error;
pub mod fault_matrix;
pub mod load;
pub mod peers;
mod plan_suite;
pub mod relays;
pub mod resources;
mod stats;
pub mod timing;

pub use error::HarnessError;
pub use load::{LoadOptions, LoadReport, run_load};
pub use plan_suite::{PlanSuite, PlanSuiteReport, run_plan_suite};
pub use resources::{ProcessResources, process_resources};
pub use stats::median;

/// The process's peak resident memory in bytes (Linux `VmHWM`), if known.
/// Kept under its old name for callers of the crate root; it is
/// [`resources::peak_rss_bytes`].
pub fn peak_memory_bytes() -> Option<u64> {
    resources::peak_rss_bytes()
}
