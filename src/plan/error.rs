//! Why the planner returned no plan.

use crate::world::Voxel;
use std::time::Duration;

/// Why no plan was returned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// The search ran out of time; the bound says how far it got.
    #[error(
        "no plan within the deadline of {deadline:?} ({ct_nodes} conflict-tree nodes expanded); \
         the optimal makespan is at least {best_lower_bound_steps} steps"
    )]
    Deadline {
        /// The deadline that was given ([`PlanOptions::deadline`](super::PlanOptions::deadline)).
        deadline: Duration,
        /// The makespan proven unavoidable when time ran out, steps.
        best_lower_bound_steps: u32,
        /// Conflict-tree nodes expanded before giving up.
        ct_nodes: u64,
    },
    /// The named group has a drone or goal outside the free space, or its drones
    /// cannot each reach a different goal.
    #[error("{0} cannot be matched to distinct reachable goals: some drone or goal is walled off")]
    Unreachable(String),
    /// No plan exists within the given horizon (steps); guards against runaway
    /// memory on instances no search could finish.
    #[error("no plan with a makespan of at most {0} steps")]
    HorizonExceeded(u32),
    /// No plan exists at any makespan, proven by searching every arrangement the
    /// named drones or groups can reach (`#i`: the i-th group of a TAPF instance).
    #[error(
        "no plan exists: {} cannot get past one another (all {arrangements} arrangements they can reach were searched, and in none is every drone on a goal); give them a passing place",
        .who.join(" and ")
    )]
    Impossible {
        /// The groups or drones that block each other, by name.
        who: Vec<String>,
        /// How many arrangements of them the proof searched.
        arrangements: u64,
    },
    /// The named groups or drones compete for voxels their targets share and there
    /// are too few for all of them: no arrangement puts every drone on a target of
    /// its own, so no search is run (see [`crate::mission::contested`]).
    #[error(
        "no plan exists: {} cannot all end on targets of their own: {} (a goal of one is where another must be: its start, a spare's hold, or where it stays)",
        .who.join(" and "),
        contest_text(.voxels, *.stacked)
    )]
    Contested {
        /// The groups or drones that compete, by name.
        who: Vec<String>,
        /// The voxels they compete for.
        voxels: Vec<Voxel>,
        /// The two voxels must both be taken but are stacked within the ellipsoid's
        /// vertical reach; otherwise there are too few of them.
        stacked: bool,
    },
    /// Every branch of the conflict tree was closed: the instance has no plan.
    #[error("the conflict tree was exhausted without a plan")]
    NoSolution,
    /// Planning one leg of the flight failed.
    #[error("leg {leg:?}: {reason}")]
    Leg {
        /// The leg's name (`takeoff`, `formation`, a stage's name, `landing`).
        leg: String,
        /// Why it failed (part of the message, so not a `source`: it would print twice).
        reason: Box<PlanError>,
    },
    /// A replan's live state does not fit its mission (see `plan::replan`).
    #[error("cannot replan: drone {drone}: {problem}")]
    LiveState {
        /// The drone the state names.
        drone: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A planner invariant broke; a bug, reported instead of panicking.
    #[error("internal planner error: {0}")]
    Internal(&'static str),
}

/// What the contest is about, for [`PlanError::Contested`].
fn contest_text(voxels: &[Voxel], stacked: bool) -> String {
    if stacked {
        format!(
            "they must take {} at once, stacked within the separation's vertical reach",
            voxel_list(voxels)
        )
    } else {
        format!(
            "they compete for {} and there are too few of those for them",
            voxel_list(voxels)
        )
    }
}

/// Voxels for a message: the first few, and how many more.
fn voxel_list(voxels: &[Voxel]) -> String {
    const SHOWN: usize = 6;
    let mut text: Vec<String> = voxels.iter().take(SHOWN).map(ToString::to_string).collect();
    if voxels.len() > SHOWN {
        text.push(format!("and {} more", voxels.len() - SHOWN));
    }
    text.join(", ")
}
