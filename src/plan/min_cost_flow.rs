//! Routing a group at a fixed horizon at least cost (primal-dual min-cost flow).
//!
//! Each phase runs Dijkstra on reduced costs (Johnson potentials keep them
//! non-negative even on residual back edges), lifts the potentials, then routes as
//! many units as possible along zero-reduced-cost edges. The number of phases is the
//! number of distinct shortest-path costs, not the number of drones, which is what
//! makes a single group of hundreds of drones one quick flow.

use super::max_flow::saturate;
use super::network::{EdgeBuf, Network};
use super::paths::{PathSearch, route_all};
use super::space::NONE;
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::time::Instant;

const INFINITE: i64 = i64::MAX / 4;

/// Phases of least-cost routing before the drones still unrouted are routed by
/// maximum flow, at any cost. Counted, not timed, so plans stay deterministic.
///
/// Paper-scale groups need well under this; at drone-show scale the first phase
/// routes nearly every drone (see [`goal_potentials`]) and the last few take one
/// phase, a search of the whole network, each: with 10,000 drones in one group,
/// 9,976 were routed after 109 s and then one to three per phase of about 2 s
/// (dev build).
const LEAST_COST_PHASES: usize = 24;

/// Starting potentials: minus each cell's distance to the group's nearest goal (the
/// sink's is 0), which makes every search goal-directed, as A* is.
///
/// They are valid — every reduced cost `cost + p(u) - p(v)` non-negative — while
/// there is no flow: a move costs at least 1 (one step; more with a penalty) and
/// changes the distance to the nearest goal by at most 1; waiting keeps it, and
/// costs 0 only at a goal, where it is 0; vertex edges stay in their cell; a goal
/// drains to the sink at distance 0. Moves along a shortest way to the goals then
/// cost nothing, so the first search settles the sink without exploring the whole
/// time-expanded network (with zero potentials it explores every node closer than
/// the sink: nearly all of it, once per phase — the cost that dominated at
/// drone-show scale), and drones that can fly straight to a goal are routed in the
/// first phase together.
fn goal_potentials(network: &Network) -> Vec<i64> {
    let to_goal = &network.group.to_goal;
    let cells = to_goal.len();
    let mut potential: Vec<i64> = (0..network.node_count())
        .map(|n| match to_goal[(n >> 1) % cells] {
            NONE => 0, // walled off from every goal: never on a route
            d => -i64::from(d),
        })
        .collect();
    let sink = network.sink();
    potential[sink] = 0;
    potential
}

/// Nodes settled between two looks at the clock in one search (a few
/// milliseconds of work).
const DEADLINE_CHECK_EVERY: u32 = 1 << 16;

/// Routes every drone of the group at the network's horizon at least total cost.
/// Returns the number of augmenting paths, or `None` if the horizon is too short or
/// `deadline_at` passed (checked within each phase); `on_routed` hears the number
/// of drones routed after each phase.
pub(crate) fn route_at_least_cost(
    network: &mut Network,
    deadline_at: Instant,
    on_routed: &mut dyn FnMut(usize),
) -> Option<u64> {
    let needed = network.group.starts.len();
    let nodes = network.node_count();
    let sink = network.sink();
    let mut potential = goal_potentials(network);
    let mut distance = vec![INFINITE; nodes];
    let mut heap = BinaryHeap::new();
    let mut edges: EdgeBuf = [(0, 0); 9];
    let mut augmentations = 0;
    let mut phases = 0;
    while network.flow < needed {
        if phases == LEAST_COST_PHASES {
            // The long tail: a few drones per phase, each phase a search of the
            // whole network. The rest get any routing at the horizon.
            let rest = saturate(network, deadline_at, &mut Vec::new())?;
            on_routed(network.flow);
            return (network.flow == needed).then_some(augmentations + rest);
        }
        phases += 1;
        distance.fill(INFINITE);
        heap.clear();
        for s in network.open_starts() {
            // The source's potential stays 0: its distance is always 0.
            distance[s] = -potential[s];
            heap.push(Reverse((distance[s], s)));
        }
        let mut popped: u32 = 0;
        while let Some(Reverse((d, u))) = heap.pop() {
            if d > distance[u] {
                continue;
            }
            if u == sink {
                break;
            }
            // One search of a show-sized network takes seconds: the deadline is
            // looked at inside it too.
            popped = popped.wrapping_add(1);
            if popped.is_multiple_of(DEADLINE_CHECK_EVERY) && Instant::now() >= deadline_at {
                return None;
            }
            let count = network.residual_edges(u, &mut edges);
            for &(v, cost) in &edges[..count] {
                let candidate = d + cost + potential[u] - potential[v];
                debug_assert!(
                    cost + potential[u] - potential[v] >= 0,
                    "negative reduced cost"
                );
                if candidate < distance[v] {
                    distance[v] = candidate;
                    heap.push(Reverse((candidate, v)));
                }
            }
        }
        let to_sink = distance[sink];
        if to_sink >= INFINITE {
            return None;
        }
        // Nodes not settled before the sink are lifted by the sink's distance, which
        // keeps every residual reduced cost non-negative.
        for (p, &d) in potential.iter_mut().zip(&distance) {
            *p += d.min(to_sink);
        }
        let potential = &potential;
        let admissible = |u: usize, v: usize, cost: i64| cost + potential[u] - potential[v] == 0;
        let routed = route_all(network, &mut PathSearch::new(nodes), admissible);
        if routed == 0 {
            // Cannot happen with exact potentials; guard against looping forever.
            return None;
        }
        augmentations += routed;
        on_routed(network.flow);
        if network.flow < needed && Instant::now() >= deadline_at {
            return None;
        }
    }
    Some(augmentations)
}
