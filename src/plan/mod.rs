//! Target assignment and path finding (TAPF): one collision-free voxel path per drone,
//! each group's goals assigned to its drones, with the least possible makespan.
//!
//! [`solve`] runs CBM: a conflict tree over groups whose low level routes one group at
//! a time as a flow on a time-expanded network. [`validate_plan`] checks any plan
//! against its mission and shares no code with the solver. [`file::load`] reads a plan
//! file for flight and refuses one that does not fit its mission.

mod cbm;
mod conflict;
mod constraints;
mod discrete_plan;
pub mod file;
mod low_level;
mod lower_bound;
mod matching;
mod max_flow;
mod min_cost_flow;
mod network;
mod paths;
mod rotation;
mod solve;
mod space;
mod validator;

pub use discrete_plan::{DiscretePlan, DronePlan};
pub use file::PlanFileError;
pub use lower_bound::{group_lower_bound, makespan_lower_bound};
pub use matching::maximum_matching;
pub use solve::{
    PlanError, PlanOptions, PlanStats, Progress, Solution, solve, solve_with_progress,
};
pub use validator::{PlanViolation, validate_plan};
