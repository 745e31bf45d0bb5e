//! Routing a group at a fixed horizon at least cost (primal-dual min-cost flow).
//!
//! Each phase runs Dijkstra on reduced costs (Johnson potentials keep them
//! non-negative even on residual back edges), lifts the potentials, then routes as
//! many units as possible along zero-reduced-cost edges. The number of phases is the
//! number of distinct shortest-path costs, not the number of drones, which is what
//! makes a single group of hundreds of drones one quick flow.

use super::network::{EdgeBuf, Network};
use super::paths::{PathSearch, route_all};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

const INFINITE: i64 = i64::MAX / 4;

/// Routes every drone of the group at the network's horizon at least total cost.
/// Returns the number of augmenting paths, or `None` if the horizon is too short.
pub(crate) fn route_at_least_cost(network: &mut Network) -> Option<u64> {
    let needed = network.group.starts.len();
    let nodes = network.node_count();
    let sink = network.sink();
    // All original costs are non-negative and there is no flow yet: zero potentials are valid.
    let mut potential = vec![0i64; nodes];
    let mut distance = vec![INFINITE; nodes];
    let mut heap = BinaryHeap::new();
    let mut edges: EdgeBuf = [(0, 0); 9];
    let mut augmentations = 0;
    while network.flow < needed {
        distance.fill(INFINITE);
        heap.clear();
        for s in network.open_starts() {
            // The source's potential stays 0: its distance is always 0.
            distance[s] = -potential[s];
            heap.push(Reverse((distance[s], s)));
        }
        while let Some(Reverse((d, u))) = heap.pop() {
            if d > distance[u] {
                continue;
            }
            if u == sink {
                break;
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
    }
    Some(augmentations)
}
