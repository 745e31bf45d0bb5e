//! What is flown: a plan file checked against the mission, or a plan made now
//! and checked as `swarmctl plan` does — either refused before anything starts.

use anyhow::Context;
use std::path::Path;
use swarmctl::compiled::{self, CheckedPlan};
use swarmctl::mission::Mission;
use swarmctl::plan;

/// The plan file, refused before anything starts unless it is a valid plan for
/// `mission` whose composition passes the checker and is what the file holds
/// (see `swarmctl::compiled::file`).
pub(super) fn load_plan(path: &Path, mission: &Mission) -> anyhow::Result<CheckedPlan> {
    Ok(swarmctl::compiled::file::load(path, mission)?)
}

/// Plans the mission now, then composes and checks the plan as `swarmctl plan`
/// does, the whole within `deadline_s` of `began` (see `plan::deadline_options`);
/// refused, naming the violation, before anything starts.
/// With `optimal`, only a plan proven makespan-optimal is accepted.
pub(super) fn plan_now(
    mission: &Mission,
    (deadline_s, began): (f64, std::time::Instant),
    optimal: bool,
) -> anyhow::Result<CheckedPlan> {
    let options = crate::commands::plan::deadline_options(deadline_s, began, optimal)?;
    let solution = plan::solve(mission, &options).with_context(|| {
        format!(
            "planning {}{}",
            mission.name,
            crate::commands::plan::reach_hint(mission)
        )
    })?;
    let p = &solution.plan;
    let proven: u32 = solution
        .stats
        .legs
        .iter()
        .map(|l| l.proven_bound_steps)
        .sum();
    println!(
        "planned {}: makespan {} steps, {} in {:.2} s",
        mission.name,
        p.makespan_steps,
        crate::commands::plan::bound_and_gap(
            p.makespan_steps,
            proven,
            solution.stats.initial_lower_bound_steps
        ),
        solution.stats.total_time.as_secs_f64()
    );
    let lower_bound_steps = solution.stats.initial_lower_bound_steps;
    compiled::compile_plan(mission, &solution.plan, lower_bound_steps).with_context(|| {
        format!(
            "checking the plan of {} before flight (nothing was started)",
            mission.name
        )
    })
}
