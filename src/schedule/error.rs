//! Why a discrete plan could not be turned into a schedule.

use crate::world::Voxel;

/// Everything that can go wrong between a [`DiscretePlan`](crate::plan::DiscretePlan)
/// and a [`Schedule`](super::Schedule).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScheduleError {
    /// The safety argument needs the setpoint separation (safety distance plus twice
    /// the tracking error) at most the spacing of cell centres (see the module docs).
    #[error(
        "setpoint separation {safety_distance_m} m (safety distance plus twice the tracking \
         error) exceeds the spacing of cell centres {voxel_size_m} m: drones waiting in \
         neighbouring cells are only {voxel_size_m} m apart, so no schedule of a voxel plan \
         can keep {safety_distance_m} m; use larger voxels, or a smaller safety distance or \
         tracking error"
    )]
    SafetyDistanceTooLarge {
        /// The separation setpoints must keep, metres.
        safety_distance_m: f64,
        /// The mission's voxel edge length, metres.
        voxel_size_m: f64,
    },
    /// Limits must be positive and finite.
    #[error("limit {name} must be positive and finite, got {value}")]
    BadLimit {
        /// The limit's field name, e.g. `max_speed_mps`.
        name: &'static str,
        /// The value it had, in the field's unit.
        value: f64,
    },
    /// The plan's shape is wrong (path length, jumps, voxels outside the world).
    #[error("drone {drone}: {reason}")]
    InvalidPlan {
        /// The drone's id.
        drone: String,
        /// What is wrong with its path.
        reason: String,
    },
    /// Two drones occupy one voxel at one step.
    #[error("drones {first} and {second} both occupy voxel {voxel} at step {step}")]
    VertexConflict {
        /// The shared voxel.
        voxel: Voxel,
        /// The plan step they share it at.
        step: u32,
        /// One drone's id.
        first: String,
        /// The other's.
        second: String,
    },
    /// Two drones in cells of one column within the ellipsoid's vertical reach at
    /// one step.
    #[error(
        "drones {first} and {second} are in voxels {first_voxel} and {second_voxel}, stacked \
         within the ellipsoid's vertical reach, at step {step}"
    )]
    StackedConflict {
        /// Where `first` is.
        first_voxel: Voxel,
        /// Where `second` is.
        second_voxel: Voxel,
        /// The plan step.
        step: u32,
        /// One drone's id.
        first: String,
        /// The other's.
        second: String,
    },
    /// Two drones trade voxels along one edge in one step.
    #[error("drones {first} and {second} swap voxels {from} and {to} at step {step}")]
    SwapConflict {
        /// Where `first` starts the move.
        from: Voxel,
        /// Where `second` starts it.
        to: Voxel,
        /// The plan step the move starts at.
        step: u32,
        /// One drone's id.
        first: String,
        /// The other's.
        second: String,
    },
    /// The precedences form a cycle: drones rotate through each other's voxels in one step,
    /// which needs perfectly simultaneous motion and cannot keep a safety distance robustly.
    #[error(
        "the plan's precedences form a cycle among drones {}: they follow each other round a \
         loop in the same step (a rotation), which no schedule can execute with a safety \
         distance; the planner must not produce rotations",
        drones.join(", ")
    )]
    CyclicPlan {
        /// The ids of the drones on the cycle.
        drones: Vec<String>,
    },
    /// A general simple temporal network has no solution.
    #[error("the temporal constraints are inconsistent (negative cycle in the distance graph)")]
    Inconsistent,
}
