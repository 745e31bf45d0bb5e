//! A valid plan fast, not necessarily of least makespan: the incumbent the exact
//! search then has to beat.
//!
//! Each group's drones start out for distinct goals of a bottleneck assignment
//! (the lower bound's), then every drone steps towards its goal with PIBT ([`pibt`]),
//! trading goals within its group when it runs into a drone of the group parked
//! on its own goal, or when two of them want each other's cells (TSWAP's rule,
//! Okumura & Défago, AIJ 2023): the group reaches its goals as a set, whoever
//! takes which. A drone's priority grows each step it is away from its goal.
//!
//! Not complete: PIBT may stall with a few drones stepping aside and back. It
//! then hands over the configuration with the most drones on their goals, and
//! the caller finishes from there with the exact search, a small instance by
//! then. Past its step budget or deadline there is no first plan (the exact
//! search answers alone).

mod goal_distances;
mod pibt;

use super::network::GroupCells;
use super::space::{NONE, Space};
use goal_distances::GoalDistances;
use pibt::Pibt;
use std::time::Instant;

/// A first plan: per group, per drone (in start order), its cell at every step.
#[derive(Debug, Clone)]
pub(crate) struct FirstPlan {
    pub paths: Vec<Vec<Vec<u32>>>,
    pub makespan: u32,
    /// Whether every drone ends on a goal. If not, PIBT stalled (a few drones
    /// stepping aside and back, typically two in a row of pads wanting each
    /// other's): the paths end at the step when most drones were on their goals,
    /// for an exact search to finish from there.
    pub complete: bool,
}

/// Steps without one more drone on its goal after which PIBT is stalled.
const PATIENCE_STEPS: u32 = 24;

/// How far the first plan has got, for progress reports.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stepping {
    pub step: u32,
    pub at_goal: usize,
    pub drones: usize,
}

/// A first plan for `groups` in `space`, each drone heading first for its goal in
/// `assigned` (per group, per drone: a bottleneck assignment), or `None` when none
/// was found within `max_steps` steps or by `deadline_at`, or the distance
/// searches passed their budget. `seed` breaks ties.
pub(crate) fn first_plan(
    space: &Space,
    groups: &[GroupCells],
    assigned: &[Vec<u32>],
    (max_steps, deadline_at): (u32, Instant),
    seed: u64,
    on_step: &mut dyn FnMut(Stepping),
) -> Option<FirstPlan> {
    let mut distances = GoalDistances::new(space);
    let mut group_of = Vec::new();
    let mut at = Vec::new();
    let mut goal = Vec::new();
    for (g, (cells, goals)) in groups.iter().zip(assigned).enumerate() {
        group_of.extend(std::iter::repeat_n(g as u32, cells.starts.len()));
        at.extend_from_slice(&cells.starts);
        goal.extend_from_slice(goals);
    }
    if goal.len() != at.len() {
        return None;
    }
    let drones = at.len();
    let hash = |d: u32, c: u32, step: u32| {
        mix(seed ^ mix(u64::from(step)) ^ (u64::from(d) << 32 | u64::from(c))) as u32
    };
    // Ties between equal priorities break by a fixed per-drone fraction.
    let fraction: Vec<f64> = (0..drones as u32)
        .map(|d| f64::from(hash(d, NONE, 0) >> 8) / f64::from(1u32 << 24))
        .collect();
    let mut priority = fraction.clone();
    let mut trail: Vec<Vec<u32>> = at.iter().map(|&c| vec![c]).collect();
    let mut occupant = vec![NONE; space.len()];
    let mut pibt = Pibt::new(space, drones);
    let mut order: Vec<u32> = (0..drones as u32).collect();
    // The step with the most drones on their goals so far, and how many.
    let mut best = (0, 0);
    for step in 0..=max_steps {
        let at_goal = (0..drones).filter(|&d| at[d] == goal[d]).count();
        on_step(Stepping {
            step,
            at_goal,
            drones,
        });
        if at_goal == drones {
            return Some(FirstPlan {
                paths: regroup(groups.iter().map(|g| g.starts.len()), trail),
                makespan: step,
                complete: true,
            });
        }
        if at_goal > best.1 {
            best = (step, at_goal);
        }
        if step >= best.0 + PATIENCE_STEPS {
            for path in &mut trail {
                path.truncate(best.0 as usize + 1);
            }
            return Some(FirstPlan {
                paths: regroup(groups.iter().map(|g| g.starts.len()), trail),
                makespan: best.0,
                complete: false,
            });
        }
        if step == max_steps || Instant::now() >= deadline_at || distances.exhausted() {
            return None;
        }
        for (d, &c) in at.iter().enumerate() {
            occupant[c as usize] = d as u32;
        }
        trade_goals(space, &at, &occupant, &group_of, &mut goal, &mut distances);
        for (d, &c) in at.iter().enumerate() {
            occupant[c as usize] = NONE;
            priority[d] = if c == goal[d] {
                fraction[d]
            } else {
                priority[d] + 1.0
            };
        }
        order.sort_by(|&a, &b| priority[b as usize].total_cmp(&priority[a as usize]));
        let mut distance = |d: u32, c: u32| distances.get(goal[d as usize], c);
        // Ties between equally near cells break differently each step, or two
        // drones could step aside and back for ever.
        let tie = |d: u32, c: u32| hash(d, c, step);
        at = pibt.step(&at, &order, &mut distance, &tie);
        for (path, &c) in trail.iter_mut().zip(&at) {
            path.push(c);
        }
    }
    None
}

/// TSWAP's rule: a drone whose best next cell holds a drone of its group parked on
/// that drone's goal, or wanting this drone's cell, trades goals with it.
fn trade_goals(
    space: &Space,
    at: &[u32],
    occupant: &[u32],
    group_of: &[u32],
    goal: &mut [u32],
    distances: &mut GoalDistances,
) {
    let mut best_move = |d: usize, goal: &[u32]| -> Option<u32> {
        let moves = &space.moves(at[d])[1..];
        moves
            .iter()
            .copied()
            .min_by_key(|&c| distances.get(goal[d], c))
    };
    for d in 0..at.len() {
        if at[d] == goal[d] {
            continue;
        }
        let Some(v) = best_move(d, goal) else {
            continue;
        };
        let other = occupant[v as usize];
        if other == NONE || group_of[other as usize] != group_of[d] {
            continue;
        }
        let o = other as usize;
        let parked = at[o] == goal[o];
        if parked || best_move(o, goal) == Some(at[d]) {
            goal.swap(d, o);
        }
    }
}

/// Per-drone trails (flattened across groups in order) back into per-group
/// lists of the given sizes.
pub(super) fn regroup(
    sizes: impl IntoIterator<Item = usize>,
    trail: Vec<Vec<u32>>,
) -> Vec<Vec<Vec<u32>>> {
    let mut trail = trail.into_iter();
    sizes
        .into_iter()
        .map(|size| trail.by_ref().take(size).collect())
        .collect()
}

/// SplitMix64's finaliser: a cheap, well-mixed hash for tie-breaking.
fn mix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}
