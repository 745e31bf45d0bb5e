//! The smallest horizon at which a group's drones all reach distinct goals (Dinic).

use super::network::{EdgeBuf, Network};
use super::paths::{PathSearch, route_all};
use std::collections::VecDeque;
use std::time::Instant;

const UNSEEN: u32 = u32::MAX;

/// Grows `network`'s horizon one layer at a time, keeping the flow found so far,
/// until every drone is routed; `None` if that needs more than `max_horizon` steps
/// or takes past `deadline_at`; `on_layer` hears each horizon as it is tried.
/// Returns the number of augmenting paths used.
pub(crate) fn grow_until_routed(
    network: &mut Network,
    max_horizon: u32,
    deadline_at: Instant,
    on_layer: &mut dyn FnMut(u32),
) -> Option<u64> {
    let needed = network.group.starts.len();
    let mut augmentations = 0;
    let mut level = Vec::new();
    loop {
        on_layer(network.horizon);
        // One depth-first sweep along any residual path first: it gives each node up
        // at most once, so it costs at most one pass over the network, and on a big
        // group it routes nearly every drone, where each of Dinic's phases is a
        // breadth-first pass over the whole network. Any augmenting path keeps the
        // flow valid, and the phases below finish the maximum flow exactly.
        augmentations += route_all(
            network,
            &mut PathSearch::new(network.node_count()),
            |_, _, _| true,
        );
        augmentations += saturate(network, deadline_at, &mut level)?;
        if network.flow == needed {
            return Some(augmentations);
        }
        if network.horizon >= max_horizon || Instant::now() >= deadline_at {
            return None;
        }
        network.grow();
    }
}

/// Dinic's phases at the network's horizon until every drone is routed or no
/// augmenting path is left (the flow is then maximum); `None` past `deadline_at`.
/// Returns the number of augmenting paths used.
pub(crate) fn saturate(
    network: &mut Network,
    deadline_at: Instant,
    level: &mut Vec<u32>,
) -> Option<u64> {
    let needed = network.group.starts.len();
    let mut augmentations = 0;
    while network.flow < needed {
        if !levels(network, level) {
            break;
        }
        let admissible = |u: usize, v: usize, _cost: i64| level[v] == level[u].wrapping_add(1);
        let found = route_all(
            network,
            &mut PathSearch::new(network.node_count()),
            admissible,
        );
        if found == 0 {
            break;
        }
        augmentations += found;
        if network.flow < needed && Instant::now() >= deadline_at {
            return None;
        }
    }
    Some(augmentations)
}

/// Breadth-first levels from the open starts; true if the sink is reachable.
fn levels(network: &Network, level: &mut Vec<u32>) -> bool {
    level.clear();
    level.resize(network.node_count(), UNSEEN);
    let sink = network.sink();
    let mut queue = VecDeque::new();
    for s in network.open_starts() {
        level[s] = 0;
        queue.push_back(s);
    }
    let mut edges: EdgeBuf = [(0, 0); 9];
    while let Some(u) = queue.pop_front() {
        if level[sink] != UNSEEN && level[u] >= level[sink] {
            break;
        }
        let count = network.residual_edges(u, &mut edges);
        for &(v, _) in &edges[..count] {
            if level[v] == UNSEEN {
                level[v] = level[u] + 1;
                if v != sink {
                    queue.push_back(v);
                }
            }
        }
    }
    level[sink] != UNSEEN
}
