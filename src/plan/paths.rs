//! Augmenting along admissible edges, shared by the max-flow and min-cost searches.

use super::network::{EdgeBuf, Network};

/// Scratch space for repeated depth-first searches within one phase.
pub(crate) struct PathSearch {
    dead: Vec<bool>,
    on_path: Vec<bool>,
    arc: Vec<u8>,
}

impl PathSearch {
    pub(crate) fn new(nodes: usize) -> Self {
        Self {
            dead: vec![false; nodes],
            on_path: vec![false; nodes],
            arc: vec![0; nodes],
        }
    }
}

/// Routes as many units as possible from the open starts to the sink using only edges
/// `admissible(u, v, cost)` accepts. Iterative, so long paths cannot overflow the stack.
/// Returns how many units were routed.
pub(crate) fn route_all(
    network: &mut Network,
    search: &mut PathSearch,
    admissible: impl Fn(usize, usize, i64) -> bool,
) -> u64 {
    let sink = network.sink();
    let needed = network.group.starts.len();
    let starts: Vec<usize> = network.open_starts().collect();
    let mut routed = 0;
    let mut edges: EdgeBuf = [(0, 0); 9];
    let mut path: Vec<usize> = Vec::new();
    for start in starts {
        if network.flow >= needed || search.dead[start] {
            continue;
        }
        path.clear();
        path.push(start);
        search.on_path[start] = true;
        while let Some(&u) = path.last() {
            if u == sink {
                break;
            }
            let count = network.residual_edges(u, &mut edges);
            let mut advanced = false;
            while (search.arc[u] as usize) < count {
                let (v, cost) = edges[search.arc[u] as usize];
                search.arc[u] += 1;
                if !search.dead[v] && !search.on_path[v] && admissible(u, v, cost) {
                    search.on_path[v] = true;
                    path.push(v);
                    advanced = true;
                    break;
                }
            }
            if !advanced {
                search.dead[u] = true;
                search.on_path[u] = false;
                path.pop();
            }
        }
        for &n in &path {
            search.on_path[n] = false;
        }
        if path.last() == Some(&sink) {
            // The sink stays reachable for later units; the nodes used may be revisited.
            for &n in &path {
                search.arc[n] = 0;
            }
            network.augment(&path);
            routed += 1;
        }
    }
    routed
}
