//! Why a discrete plan could not be turned into a schedule.

use crate::world::Voxel;

/// Everything that can go wrong between a [`DiscretePlan`](crate::plan::DiscretePlan)
/// and a [`Schedule`](super::Schedule).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScheduleError {
    /// The safety argument needs `safety_distance_m <= voxel_size_m` (see the module docs).
    #[error(
        "safety distance {safety_distance_m} m exceeds the voxel size {voxel_size_m} m: drones \
         waiting in face-adjacent voxels are only {voxel_size_m} m apart, so no schedule of a \
         voxel plan can keep {safety_distance_m} m; use voxels at least as large as the safety \
         distance or a smaller safety distance"
    )]
    SafetyDistanceTooLarge {
        safety_distance_m: f64,
        voxel_size_m: f64,
    },
    /// Limits must be positive and finite.
    #[error("limit {name} must be positive and finite, got {value}")]
    BadLimit { name: &'static str, value: f64 },
    /// The plan's shape is wrong (path length, jumps, voxels outside the world).
    #[error("drone {drone}: {reason}")]
    InvalidPlan { drone: String, reason: String },
    /// Two drones occupy one voxel at one step.
    #[error("drones {first} and {second} both occupy voxel {voxel} at step {step}")]
    VertexConflict {
        voxel: Voxel,
        step: u32,
        first: String,
        second: String,
    },
    /// Two drones trade voxels along one edge in one step.
    #[error("drones {first} and {second} swap voxels {from} and {to} at step {step}")]
    SwapConflict {
        from: Voxel,
        to: Voxel,
        step: u32,
        first: String,
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
    CyclicPlan { drones: Vec<String> },
    /// A general simple temporal network has no solution.
    #[error("the temporal constraints are inconsistent (negative cycle in the distance graph)")]
    Inconsistent,
}
