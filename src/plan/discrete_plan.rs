//! The planner's output: one voxel path per drone on a shared clock of unit steps.

use crate::world::Voxel;
use serde::{Deserialize, Serialize};

/// A solution to a TAPF instance: one path per drone, all of equal length.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DiscretePlan {
    /// The step at which the last drone arrives for good.
    pub makespan_steps: u32,
    /// Sum over drones of the step at which each arrives for good.
    pub sum_of_costs_steps: u64,
    /// One entry per drone, in mission order (group by group, file order within).
    pub drones: Vec<DronePlan>,
}

/// One drone's assignment and path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DronePlan {
    /// The drone's id in the mission.
    pub id: String,
    /// The name of the drone's group.
    pub group: String,
    /// The goal of its group assigned to this drone (the path's last voxel).
    pub goal: Voxel,
    /// The voxel at every step from 0 to `makespan_steps` inclusive; the goal is
    /// repeated once reached.
    pub path: Vec<Voxel>,
}

impl DronePlan {
    /// The first step from which the drone stays at its goal.
    pub fn arrival_step(&self) -> u32 {
        let last_away = self.path.iter().rposition(|&v| v != self.goal);
        last_away.map_or(0, |i| i as u32 + 1)
    }
}
