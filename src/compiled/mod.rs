//! A compiled plan: the discrete plan, its schedule and the trajectories to stream.
//!
//! This is what `swarmctl plan -o PLAN.json` writes and what `swarmctl fly` flies,
//! planned there and then or read with `--plan`. [`compile_plan`] is the one
//! composition of a discrete plan into it (schedule, execution graph, sampled
//! trajectories) and runs the independent checker on the whole flight; it refuses
//! a plan that breaks any limit, and its [`CheckedPlan`] is the only thing the
//! flight executor flies. [`file::load`] reads a plan file back for flight,
//! composes its discrete plan the same way and refuses one that does not fit its
//! mission, fails the check or holds anything else than what it composes to. A
//! replan in flight composes with [`compose`] and checks its spliced trajectories
//! with [`check_flight`].

use crate::mission::Mission;
use crate::plan::{DiscretePlan, PlanLeg, Solution};
use crate::schedule::{self, ExecutionPlan, ScheduleError};
use crate::trajectory::{self, Trajectories};
use crate::verify::{self, CheckError, SeparationReport};
use crate::world::Voxel;
use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

pub mod figures;
pub mod file;

pub use figures::CheckFigures;
pub use file::PlanFileError;

/// What [`compile_plan`] takes per drone and step of the plan, with room to
/// spare: what a caller keeps back from a planning deadline
/// (`PlanOptions::reserve_per_drone_step`) so the plan is scheduled and checked
/// by the deadline too. Measured on a release build on a 2-core machine
/// (README, Performance; `swarmctl plan` less its planning, so reading the
/// mission and printing included): 16 µs at 1,000 drones × 87 steps, 18 µs at
/// 5,000 × 86, 26 µs at 10,000 × 61 (the separation sweep grows with the
/// drones near each other).
pub const COMPILE_TIME_PER_DRONE_STEP: Duration = Duration::from_micros(25);

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

/// A compiled plan the independent checker passed, with the trajectories its
/// samples were taken from. Only [`compile_plan`] makes one (and [`file::load`]
/// through it), so holding one means the check ran on exactly these
/// trajectories: the flight executor takes nothing else.
#[derive(Debug, Clone)]
pub struct CheckedPlan {
    compiled: CompiledPlan,
    trajectories: Trajectories,
    figures: CheckFigures,
}

impl CheckedPlan {
    /// The plan file's content: discrete plan, execution graph, samples, report.
    pub fn compiled(&self) -> &CompiledPlan {
        &self.compiled
    }

    /// The trajectories that were sampled and checked: the runs the executor
    /// streams, joined with `compiled().execution` into routes.
    pub fn trajectories(&self) -> &Trajectories {
        &self.trajectories
    }

    /// What the check measured, in short (for the flight log).
    pub fn figures(&self) -> &CheckFigures {
        &self.figures
    }

    /// The discrete plan inside.
    pub fn discrete(&self) -> DiscretePlan {
        self.compiled.discrete()
    }

    /// The plan file's content alone.
    pub fn into_compiled(self) -> CompiledPlan {
        self.compiled
    }
}

/// A discrete plan composed for flight, not yet checked: the execution graph the
/// executor gates on and the trajectories it streams.
#[derive(Debug, Clone)]
pub struct Composition {
    /// The Temporal Plan Graph's events per drone, with times and gates.
    pub execution: ExecutionPlan,
    /// Every drone's rest-to-rest runs, plan order.
    pub trajectories: Trajectories,
}

/// Schedules `plan` in `mission` and derives its execution graph and trajectories:
/// the one place the chain plan → schedule → trajectories is written. Everything
/// that flies also goes through [`check_flight`] ([`compile_plan`] does both).
pub fn compose(mission: &Mission, plan: &DiscretePlan) -> Result<Composition, ScheduleError> {
    let tpg = schedule::build(mission, plan)?;
    let schedule = schedule::solve(&tpg)?;
    Ok(Composition {
        execution: schedule::execution_plan(&tpg, &schedule),
        trajectories: trajectory::from_schedule(&schedule),
    })
}

/// Where the checked trajectories begin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Begin {
    /// On the ground: a whole flight, each drone climbing from the ground below
    /// its start first.
    OnPads,
    /// In the air, each drone at rest at its start: a replan spliced in flight.
    Airborne,
}

/// Runs the independent checker on `trajectories` as they are flown in `mission`:
/// from the ground (after the climb, [`Begin::OnPads`]) or from where the drones
/// rest in the air ([`Begin::Airborne`]), to each drone's touchdown, sampled at the
/// setpoint rate. Returns the report, drones named by id, and its figures; the
/// caller refuses what it must. Errors only when the checker cannot run at all.
pub fn check_flight(
    mission: &Mission,
    trajectories: &Trajectories,
    begin: Begin,
) -> Result<(SeparationReport, CheckFigures), CheckError> {
    let started = Instant::now();
    let kinematics = mission.commanded_limits().kinematics();
    let flight = match begin {
        Begin::OnPads => trajectories.pad_to_pad(kinematics),
        Begin::Airborne => trajectories.to_ground(kinematics),
    };
    let rate_hz = mission.link.setpoint_rate_hz;
    let samples = flight.sample(rate_hz);
    let ids: Vec<&str> = trajectories.drones.iter().map(|d| d.id.as_str()).collect();
    let report = name_drones(verify::check(&samples, &mission.limits)?, &ids);
    let figures = CheckFigures::new(
        &report,
        &mission.limits,
        &ids,
        samples.first().map_or(0, Vec::len),
        1.0 / rate_hz,
        started.elapsed(),
    );
    Ok((report, figures))
}

/// Composes `plan` for `mission` ([`compose`]), samples its trajectories at the
/// mission's setpoint rate and checks the whole flight pad to pad
/// ([`check_flight`]); errors, naming every violation, if any limit breaks.
/// `lower_bound_steps` is the planner's bound, kept in the file for comparison
/// (0 when unknown).
pub fn compile_plan(
    mission: &Mission,
    plan: &DiscretePlan,
    lower_bound_steps: u32,
) -> Result<CheckedPlan, CompileError> {
    let Composition {
        execution,
        trajectories,
    } = compose(mission, plan)?;
    let (check, figures) = check_flight(mission, &trajectories, Begin::OnPads)?;
    if !check.ok() {
        return Err(CompileError::Limits(Box::new(check)));
    }
    let samples = trajectories.sample(mission.link.setpoint_rate_hz);
    let compiled = CompiledPlan {
        mission: mission.name.clone(),
        makespan_steps: plan.makespan_steps,
        sum_of_costs_steps: plan.sum_of_costs_steps,
        lower_bound_steps,
        makespan_s: trajectories.makespan_s,
        setpoint_period_s: 1.0 / mission.link.setpoint_rate_hz,
        legs: plan.legs.clone(),
        drones: compiled_drones(plan, samples),
        execution,
        check,
    };
    Ok(CheckedPlan {
        compiled,
        trajectories,
        figures,
    })
}

/// [`compile_plan`] for a planner's solution, as the plan file holds it.
pub fn compile(mission: &Mission, solution: &Solution) -> Result<CompiledPlan, CompileError> {
    let lower_bound_steps = solution.stats.initial_lower_bound_steps;
    Ok(compile_plan(mission, &solution.plan, lower_bound_steps)?.into_compiled())
}

/// The checker knows drones by index (`#3`); users know them by id.
fn name_drones(mut report: SeparationReport, ids: &[&str]) -> SeparationReport {
    for violation in &mut report.violations {
        for (i, id) in ids.iter().enumerate().rev() {
            *violation = violation.replace(&format!("#{i}"), &format!("{id:?}"));
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
