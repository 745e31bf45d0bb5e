//! Which goal each drone of a group heads for first: a bottleneck assignment.

use super::goal_distances::{FAR, GoalDistances};
use crate::plan::matching::matched;

/// Gives each drone at `starts` a distinct goal of `goals`, every drone at most
/// `at_least` moves from its own if that can be done (`at_least` is the group's
/// bottleneck lower bound, so it usually can), else at the least such distance.
/// Each drone prefers its nearer goals. `None` if some drone can reach no free goal.
///
/// The makespan of any plan is at least its assignment's longest distance, so
/// starting from the bottleneck assignment leaves the drones' own moves no longer
/// than the bound; what the first plan loses to the optimum is waiting and detours.
pub(crate) fn bottleneck_assignment(
    distances: &mut GoalDistances,
    starts: &[u32],
    goals: &[u32],
    at_least: u32,
) -> Option<Vec<u32>> {
    // dist[g][d]: one table lookup per pair.
    let dist: Vec<Vec<u16>> = goals
        .iter()
        .map(|&g| {
            let table = distances.table(g);
            starts.iter().map(|&s| table[s as usize]).collect()
        })
        .collect();
    let mut thresholds: Vec<u16> = dist
        .iter()
        .flatten()
        .copied()
        .filter(|&d| d != FAR)
        .collect();
    thresholds.sort_unstable();
    thresholds.dedup();
    let within = |t: u16| {
        let adjacency: Vec<Vec<usize>> = (0..starts.len())
            .map(|d| {
                let mut near: Vec<usize> = (0..goals.len()).filter(|&g| dist[g][d] <= t).collect();
                near.sort_by_key(|&g| dist[g][d]);
                near
            })
            .collect();
        matched(&adjacency, goals.len())
    };
    let complete = |m: &[Option<usize>]| m.iter().all(Option::is_some);
    let first = thresholds.partition_point(|&t| u32::from(t) < at_least);
    let tried = within(thresholds.get(first).copied().unwrap_or(FAR - 1));
    let matching = if complete(&tried) {
        tried
    } else {
        // Matchability is monotone in the threshold: the least one that works.
        let rest = &thresholds[first..];
        let index = rest.partition_point(|&t| !complete(&within(t)));
        within(*rest.get(index)?)
    };
    matching.into_iter().map(|g| g.map(|g| goals[g])).collect()
}
