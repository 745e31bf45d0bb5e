//! Target assignment and path finding (TAPF): one collision-free voxel path per drone.

mod discrete_plan;
mod lower_bound;
mod matching;

pub use discrete_plan::{DiscretePlan, DronePlan};
pub use lower_bound::{group_lower_bound, makespan_lower_bound};
pub use matching::maximum_matching;
