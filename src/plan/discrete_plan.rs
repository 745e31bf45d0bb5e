//! The planner's output: one voxel path per drone on a shared clock of unit steps.

use crate::mission::LegKind;
use crate::world::Voxel;
use serde::{Deserialize, Serialize};

/// A whole flight's plan, pad to pad: one path per drone, all of equal length, made
/// of legs flown one after the other.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DiscretePlan {
    /// The step at which the last drone arrives for good.
    pub makespan_steps: u32,
    /// Sum over drones of the step at which each arrives for good.
    pub sum_of_costs_steps: u64,
    /// One entry per drone, in mission order (group by group, file order within).
    pub drones: Vec<DronePlan>,
    /// The legs in flight order; leg `k` spans steps from the previous leg's
    /// `end_step` (0 for the first) to its own.
    pub legs: Vec<PlanLeg>,
}

/// One leg of a plan: takeoff, a formation, landing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanLeg {
    /// `takeoff`, `formation`, a stage's name, or `landing`.
    pub name: String,
    /// What the leg is for.
    pub kind: LegKind,
    /// The step at which the leg ends: every drone is at its leg target from then
    /// until the next leg begins.
    pub end_step: u32,
    /// Seconds every drone holds at the leg's end once the whole swarm is there.
    pub hold_s: f64,
    /// The leg's own makespan, steps.
    pub makespan_steps: u32,
    /// The leg's makespan lower bound (bottleneck assignment), steps.
    pub lower_bound_steps: u32,
    /// The largest makespan the planner proved unavoidable for the leg, steps:
    /// `makespan_steps` when the leg is proven optimal, less when the deadline
    /// left a gap. `None` in plan files written before plans could have a gap
    /// (every leg was then optimal).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub proven_bound_steps: Option<u32>,
}

impl PlanLeg {
    /// How many steps the leg may be above the optimum: 0 when proven optimal.
    pub fn gap_steps(&self) -> u32 {
        self.proven_bound_steps
            .map_or(0, |bound| self.makespan_steps.saturating_sub(bound))
    }
}

impl DiscretePlan {
    /// How many steps the whole flight may be above the optimum of flying its legs
    /// one after the other: the legs' gaps added up.
    pub fn gap_steps(&self) -> u32 {
        self.legs.iter().map(PlanLeg::gap_steps).sum()
    }
}

/// One drone's assignment and path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DronePlan {
    /// The drone's id in the mission.
    pub id: String,
    /// The name of the drone's group.
    pub group: String,
    /// Where its path ends: the pad-layer cell it lands from.
    pub goal: Voxel,
    /// The voxel at every step from 0 (above its pad) to `makespan_steps` inclusive;
    /// the last voxel is repeated once reached.
    pub path: Vec<Voxel>,
}

impl DronePlan {
    /// The first step from which the drone stays at its goal.
    pub fn arrival_step(&self) -> u32 {
        let last_away = self.path.iter().rposition(|&v| v != self.goal);
        last_away.map_or(0, |i| i as u32 + 1)
    }
}
