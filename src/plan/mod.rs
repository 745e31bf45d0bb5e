//! Target assignment and path finding (TAPF): one collision-free voxel path per drone,
//! each group's goals assigned to its drones, with the least possible makespan.
//!
//! Each leg is planned anytime (`anytime`): a first plan fast (`open_sky`:
//! straight lines where nothing stands between the formations; else
//! `first_plan`: PIBT towards a bottleneck assignment of goals), then the exact
//! search below to beat it, stopping when it meets the lower bound, proves it
//! optimal, or runs out of time; the plan states the gap between its makespan
//! and the bound proven.
//!
//! [`solve_tapf`] runs CBM: a conflict tree over groups whose low level routes one
//! group at a time as a flow on a time-expanded network. When the tree grows past a
//! node budget, an exact method starts beside it on a second thread: a bounded proof
//! of impossibility (`feasibility`), then a SAT encoding of the whole time-expanded
//! network (`sat`), horizon by horizon from the tree's proven lower bound. The first
//! to finish answers; both are makespan-optimal. [`solve`] plans a whole
//! flight pad to pad as the mission's legs (takeoff, formations, landing), one CBM
//! instance each, in the mission's airspace. [`validate_plan`] checks any plan
//! against its mission and shares no code with the solver. [`replan`] plans the
//! rest of a flight from where the drones are, without the lost ones, and
//! [`validate_rest`] checks such a plan the same way. Reading a plan file back
//! (`swarmctl fly --plan`) is `compiled::file`'s job, above this module.

mod anytime;
mod cbm;
mod conflict;
mod constraints;
mod discrete_plan;
mod error;
mod feasibility;
mod first_plan;
mod flight;
mod low_level;
mod lower_bound;
mod matching;
mod max_flow;
mod min_cost_flow;
mod network;
mod open_sky;
mod options;
mod pair_distances;
mod paths;
mod replan;
mod rotation;
mod sat;
mod solve;
mod space;
mod stats;
mod validator;

pub use discrete_plan::{DiscretePlan, DronePlan, PlanLeg};
pub use error::PlanError;
pub use flight::{solve, solve_with_progress};
pub use lower_bound::{group_lower_bound, makespan_lower_bound};
pub use matching::maximum_matching;
pub use options::PlanOptions;
pub use replan::{Replanned, replan, replan_with_progress};
pub use solve::{Solution, TapfGroup, TapfSolution, solve_tapf};
pub use stats::{LegStats, PlanPhase, PlanStats, Progress};
pub use validator::{PlanViolation, validate_plan, validate_rest};
