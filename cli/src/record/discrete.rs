//! A bare discrete plan (what `swarmctl fly` holds) compiled for recording.

use super::RecordError;
use swarmctl::compiled::{self, CompiledPlan};
use swarmctl::mission::Mission;
use swarmctl::plan::{DiscretePlan, PlanStats, Solution};

/// Schedules and samples `plan` exactly as `swarmctl plan` does, so a flight
/// recording can show the schedule the executor gated on. The search statistics
/// are unknown here and left empty; nothing in a recording reads them.
pub fn schedule_discrete(
    mission: &Mission,
    plan: &DiscretePlan,
) -> Result<CompiledPlan, RecordError> {
    let solution = Solution {
        plan: plan.clone(),
        stats: PlanStats::default(),
    };
    Ok(compiled::compile(mission, &solution)?)
}

/// The scene `swarmctl fly` records: the plan scheduled and sampled exactly as the
/// executor will fly it, without the separation checker `swarmctl plan` runs (the
/// executor does not run it either), so that starting a recording costs little.
pub fn scheduled_scene(
    mission: &Mission,
    plan: &DiscretePlan,
) -> Result<swarmctl_viz::Scene, RecordError> {
    let schedule_err = |e| RecordError::Compile(compiled::CompileError::Schedule(e));
    let tpg = swarmctl::schedule::build(mission, plan).map_err(schedule_err)?;
    let schedule = swarmctl::schedule::solve(&tpg).map_err(schedule_err)?;
    let execution = swarmctl::schedule::execution_plan(&tpg, &schedule);
    let samples =
        swarmctl::trajectory::from_schedule(&schedule).sample(mission.link.setpoint_rate_hz);
    let drones = compiled::compiled_drones(plan, samples);
    Ok(super::plan::drones_scene(mission, &drones, &execution))
}
