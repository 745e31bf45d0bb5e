//! Maximum bipartite matching (Hopcroft–Karp), O(E·√V).

use std::collections::VecDeque;

const NONE: usize = usize::MAX;

/// Size of a maximum matching between `adjacency.len()` left vertices and
/// `right_count` right vertices; `adjacency[l]` lists the right vertices of `l`.
///
/// ```
/// use swarmctl::plan::maximum_matching;
/// // Both left vertices want right 0; only one can have it.
/// assert_eq!(maximum_matching(&[vec![0], vec![0]], 2), 1);
/// assert_eq!(maximum_matching(&[vec![0, 1], vec![0]], 2), 2);
/// ```
pub fn maximum_matching(adjacency: &[Vec<usize>], right_count: usize) -> usize {
    matched(adjacency, right_count).iter().flatten().count()
}

/// A maximum matching itself: for each left vertex, the right vertex it is matched
/// to. Each left vertex tries its adjacency in order, so listing the preferred
/// right vertices first biases the matching towards them.
pub(crate) fn matched(adjacency: &[Vec<usize>], right_count: usize) -> Vec<Option<usize>> {
    let left_count = adjacency.len();
    let mut match_left = vec![NONE; left_count];
    let mut match_right = vec![NONE; right_count];
    let mut layer = vec![u32::MAX; left_count];
    loop {
        // BFS from free left vertices builds the layered graph of shortest augmenting paths.
        let mut queue = VecDeque::new();
        for l in 0..left_count {
            if match_left[l] == NONE {
                layer[l] = 0;
                queue.push_back(l);
            } else {
                layer[l] = u32::MAX;
            }
        }
        let mut found = false;
        while let Some(l) = queue.pop_front() {
            for &r in &adjacency[l] {
                let next = match_right[r];
                if next == NONE {
                    found = true;
                } else if layer[next] == u32::MAX {
                    layer[next] = layer[l] + 1;
                    queue.push_back(next);
                }
            }
        }
        if !found {
            return match_left
                .iter()
                .map(|&r| (r != NONE).then_some(r))
                .collect();
        }
        for l in 0..left_count {
            if match_left[l] == NONE {
                augment(l, adjacency, &mut match_left, &mut match_right, &mut layer);
            }
        }
    }
}

/// Depth-first search along the layers, iterative so deep graphs cannot overflow the stack.
fn augment(
    root: usize,
    adjacency: &[Vec<usize>],
    match_left: &mut [usize],
    match_right: &mut [usize],
    layer: &mut [u32],
) -> bool {
    // Stack of (left vertex, index of the next edge to try).
    let mut stack = vec![(root, 0usize)];
    while let Some(&mut (l, ref mut next_edge)) = stack.last_mut() {
        if *next_edge == adjacency[l].len() {
            layer[l] = u32::MAX; // dead end: never try it again in this phase
            stack.pop();
            continue;
        }
        let r = adjacency[l][*next_edge];
        *next_edge += 1;
        let owner = match_right[r];
        if owner == NONE {
            // Flip the path: each left vertex on the stack takes the right vertex it
            // tried last, which the vertex above it on the stack just gave up.
            while let Some((l, edge)) = stack.pop() {
                let taken = adjacency[l][edge - 1];
                match_left[l] = taken;
                match_right[taken] = l;
            }
            return true;
        }
        if layer[owner] == layer[l] + 1 {
            stack.push((owner, 0));
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_force(adjacency: &[Vec<usize>], right_count: usize) -> usize {
        fn go(l: usize, adj: &[Vec<usize>], used: &mut Vec<bool>) -> usize {
            if l == adj.len() {
                return 0;
            }
            let mut best = go(l + 1, adj, used);
            for &r in &adj[l] {
                if !used[r] {
                    used[r] = true;
                    best = best.max(1 + go(l + 1, adj, used));
                    used[r] = false;
                }
            }
            best
        }
        go(0, adjacency, &mut vec![false; right_count])
    }

    #[test]
    fn matches_brute_force_on_small_graphs() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for _ in 0..300 {
            let left = rng.random_range(0..7);
            let right = rng.random_range(1..7);
            let adjacency: Vec<Vec<usize>> = (0..left)
                .map(|_| (0..right).filter(|_| rng.random_bool(0.35)).collect())
                .collect();
            assert_eq!(
                maximum_matching(&adjacency, right),
                brute_force(&adjacency, right),
                "{adjacency:?}"
            );
        }
    }
}
