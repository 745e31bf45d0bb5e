//! A compiled plan: the discrete plan, its schedule and the trajectories to stream.
//!
//! This is what `swarmctl plan -o PLAN.json` writes and `swarmctl fly --plan` reads.
//! Compiling checks the sampled trajectories with the independent separation checker
//! and refuses a plan that breaks any limit. [`file::load`] reads a plan file back for
//! flight and refuses one that does not fit its mission.

use crate::mission::Mission;
use crate::plan::{DiscretePlan, PlanLeg, PlanStats, Solution};
use crate::schedule::{self, ExecutionPlan, ScheduleError};
use crate::verify::{self, CheckError, SeparationReport};
use crate::world::Voxel;
use serde::{Deserialize, Serialize};

pub mod file;

pub use file::PlanFileError;

/// The plan file (see ARCHITECTURE.md for the fixed fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompiledPlan {
    /// The mission's name, so a plan flown with another mission can say so.
    pub mission: String,
    /// Plan steps until the last drone arrives (the discrete plan's makespan).
    pub makespan_steps: u32,
    /// Sum over drones of the step each arrives for good.
    pub sum_of_costs_steps: u64,
    /// Collision-free lower bound on the makespan, for comparison.
    pub lower_bound_steps: u32,
    /// When the last drone comes to rest at its goal, seconds after the start.
    pub makespan_s: f64,
    /// Period of the `trajectory` samples, seconds.
    pub setpoint_period_s: f64,
    /// The flight's legs (takeoff, formations and stages, landing), with each leg's
    /// last step, hold, makespan and lower bound.
    pub legs: Vec<PlanLeg>,
    /// Every drone's plan and samples, in mission order.
    pub drones: Vec<CompiledDrone>,
    /// The Temporal Plan Graph's events per drone, with their cross-drone
    /// predecessors and slack: what a flight executor gates each drone on.
    pub execution: ExecutionPlan,
    /// What the independent checker measured on the whole flight: `trajectory` with
    /// the climb from each pad before it and the touchdown after it.
    pub check: SeparationReport,
}

/// One drone of a compiled plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompiledDrone {
    /// The drone's id in the mission.
    pub id: String,
    /// The name of its group.
    pub group: String,
    /// The ground cell `[x, y]` it takes off from.
    pub pad: [i32; 2],
    /// Where its path ends: the pad-layer cell it lands from.
    pub goal: Voxel,
    /// Its voxel at every plan step, `makespan_steps + 1` entries.
    pub path: Vec<Voxel>,
    /// `[t_s, x_m, y_m, z_m]` in ENU metres at the setpoint period, from above the pad
    /// to above the landing pad: exactly what is streamed on the plan clock (the
    /// climb from the pad before it and the touchdown after it are checked with the
    /// rest, see `check`).
    pub trajectory: Vec<[f64; 4]>,
}

/// Why a discrete plan could not be compiled.
#[derive(Debug, thiserror::Error)]
pub enum CompileError {
    /// The plan cannot be scheduled (e.g. it holds a rotation, or the safety
    /// distance exceeds the voxel size).
    #[error(transparent)]
    Schedule(#[from] ScheduleError),
    /// The samples could not be checked at all.
    #[error("the trajectory checker could not run: {0}")]
    Check(#[from] CheckError),
    /// The checker measured a limit broken; the report names the drones by id.
    #[error("the trajectories break the mission's limits:\n  {}", .0.violations.join("\n  "))]
    Limits(Box<SeparationReport>),
}

impl CompiledPlan {
    /// The discrete plan inside.
    pub fn discrete(&self) -> DiscretePlan {
        DiscretePlan {
            makespan_steps: self.makespan_steps,
            sum_of_costs_steps: self.sum_of_costs_steps,
            drones: self
                .drones
                .iter()
                .map(|d| crate::plan::DronePlan {
                    id: d.id.clone(),
                    group: d.group.clone(),
                    goal: d.goal,
                    path: d.path.clone(),
                })
                .collect(),
            legs: self.legs.clone(),
        }
    }
}

/// Schedules `solution`, samples its trajectories at the mission's setpoint rate and
/// checks them; errors if any limit breaks.
pub fn compile(mission: &Mission, solution: &Solution) -> Result<CompiledPlan, CompileError> {
    let plan = &solution.plan;
    let tpg = schedule::build(mission, plan)?;
    let schedule = schedule::solve(&tpg)?;
    let execution = schedule::execution_plan(&tpg, &schedule);
    let trajectories = crate::trajectory::from_schedule(&schedule);
    let samples = trajectories.sample(mission.link.setpoint_rate_hz);
    // The checker sees the whole flight, from the ground up and back down.
    let l = &mission.limits;
    let flight = trajectories.pad_to_pad(mission.commanded_limits().kinematics());
    let check = verify::check(&flight.sample(mission.link.setpoint_rate_hz), l)?;
    if !check.ok() {
        return Err(CompileError::Limits(Box::new(name_drones(check, plan))));
    }
    let stats: &PlanStats = &solution.stats;
    Ok(CompiledPlan {
        mission: mission.name.clone(),
        makespan_steps: plan.makespan_steps,
        sum_of_costs_steps: plan.sum_of_costs_steps,
        lower_bound_steps: stats.initial_lower_bound_steps,
        makespan_s: trajectories.makespan_s,
        setpoint_period_s: 1.0 / mission.link.setpoint_rate_hz,
        legs: plan.legs.clone(),
        drones: compiled_drones(plan, samples),
        execution,
        check,
    })
}

/// The checker knows drones by index (`#3`); users know them by id.
fn name_drones(mut report: SeparationReport, plan: &DiscretePlan) -> SeparationReport {
    for violation in &mut report.violations {
        for (i, d) in plan.drones.iter().enumerate().rev() {
            *violation = violation.replace(&format!("#{i}"), &format!("{:?}", d.id));
        }
    }
    report
}

/// Each drone's plan beside its sampled trajectory (same order).
pub fn compiled_drones(plan: &DiscretePlan, samples: Vec<Vec<[f64; 4]>>) -> Vec<CompiledDrone> {
    plan.drones
        .iter()
        .zip(samples)
        .map(|(d, trajectory)| CompiledDrone {
            id: d.id.clone(),
            group: d.group.clone(),
            pad: d.path.first().map_or([0, 0], |v| [v.x, v.y]),
            goal: d.goal,
            path: d.path.clone(),
            trajectory,
        })
        .collect()
}
