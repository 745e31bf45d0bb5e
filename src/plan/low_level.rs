//! One group at a time: the least horizon under the group's constraints, then the
//! cheapest routing at the horizon the conflict tree asks for.

use super::constraints::Constraints;
use super::max_flow::grow_until_routed;
use super::min_cost_flow::route_at_least_cost;
use super::network::{GroupCells, Network, Reservation};
use super::rotation::remove_cycles;
use super::space::Space;
use std::time::Instant;

/// A group's routing inside one conflict-tree node.
#[derive(Debug, Clone)]
pub(crate) struct GroupRouting {
    /// The least horizon at which the group can be routed under its constraints.
    pub min_horizon: u32,
    /// One path per drone, in the group's drone order (compact cells), all of equal length.
    pub paths: Vec<Vec<u32>>,
}

/// Work done, for the planner's counters.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LowLevelWork {
    pub augmentations: u64,
}

/// The least horizon at which the group can be routed, within `(at_least,
/// max_horizon)`; `on_layer` hears each horizon tried before `deadline_at`.
pub(crate) fn min_horizon(
    space: &Space,
    group: &GroupCells,
    constraints: &Constraints,
    (at_least, max_horizon): (u32, u32),
    (deadline_at, on_layer): (Instant, &mut dyn FnMut(u32)),
    work: &mut LowLevelWork,
) -> Option<u32> {
    if Instant::now() >= deadline_at {
        return None;
    }
    let from_constraints = constraints
        .latest_goal_step(&group.is_goal)
        .map_or(0, |t| t + 1);
    let mut network = Network::new(space, group, constraints, at_least.max(from_constraints));
    work.augmentations += grow_until_routed(&mut network, max_horizon, deadline_at, on_layer)?;
    Some(network.horizon)
}

/// Routes the group at `horizon`, steering around `others` where it can, then with the
/// fewest steps spent away from goals; swaps and rotations inside the group are
/// replaced by waits. `on_routed` hears how many drones have a path, phase by phase;
/// `None` past `deadline_at`.
pub(crate) fn route(
    space: &Space,
    group: &GroupCells,
    constraints: &Constraints,
    horizon: u32,
    others: &Reservation,
    (deadline_at, on_routed): (Instant, &mut dyn FnMut(usize)),
    work: &mut LowLevelWork,
) -> Option<Vec<Vec<u32>>> {
    if Instant::now() >= deadline_at {
        return None;
    }
    let mut network = Network::new(space, group, constraints, horizon);
    // One meeting with another group must outweigh any number of extra steps.
    let steps_at_most = group.starts.len() as i64 * (i64::from(horizon) + 1);
    network.set_penalty(others, steps_at_most + 1);
    work.augmentations += route_at_least_cost(&mut network, deadline_at, on_routed)?;
    let mut paths = network.paths();
    remove_cycles(&mut paths, space.len());
    Some(paths)
}
