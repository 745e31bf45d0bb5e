//! A bare discrete plan (what `swarmctl fly` holds) compiled for recording.

use super::RecordError;
use crate::compiled::{self, CompiledPlan};
use crate::mission::Mission;
use crate::plan::{DiscretePlan, PlanStats, Solution};

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
