//! Rotations: drones that each move, in one step, into the voxel another one leaves,
//! closing a cycle.
//!
//! Discrete MAPF allows them, but no drone can enter a voxel before its predecessor
//! has left it by the safety distance, so a rotation cannot be flown: every drone of
//! the cycle waits for the next. The planner therefore removes them inside a group
//! (drones are interchangeable) and treats them as conflicts between groups.

/// Finds the cycles of movers between `t` and `t + 1`; each cycle lists drone indices
/// so that drone `k` moves into the voxel drone `k + 1` leaves (wrapping around).
/// `occupant[c]` must give the drone at cell `c` at `t` (or `u32::MAX`) and is left as found.
pub(crate) fn cycles_at(
    position: impl Fn(usize, usize) -> u32,
    drones: usize,
    t: usize,
    occupant: &[u32],
) -> Vec<Vec<usize>> {
    const UNSEEN: u8 = 0;
    const ON_CHAIN: u8 = 1;
    const DONE: u8 = 2;
    let mut state = vec![UNSEEN; drones];
    let mut cycles = Vec::new();
    let mut chain = Vec::new();
    for first in 0..drones {
        if state[first] != UNSEEN {
            continue;
        }
        chain.clear();
        let mut current = first;
        state[current] = ON_CHAIN;
        chain.push(current);
        loop {
            let (here, next) = (position(current, t), position(current, t + 1));
            if here == next {
                break;
            }
            let ahead = occupant[next as usize];
            if ahead == u32::MAX {
                break;
            }
            let ahead = ahead as usize;
            match state[ahead] {
                ON_CHAIN => {
                    if let Some(start) = chain.iter().position(|&d| d == ahead) {
                        cycles.push(chain[start..].to_vec());
                    }
                    break;
                }
                DONE => break,
                _ => {
                    state[ahead] = ON_CHAIN;
                    chain.push(ahead);
                    current = ahead;
                }
            }
        }
        for &d in &chain {
            state[d] = DONE;
        }
    }
    cycles
}

/// Replaces every cycle inside one group (swaps included) by waits: each drone of a
/// cycle keeps its voxel and continues with the remaining path of the drone that
/// was about to move into it. Same voxels at the same steps, no cycle, no more cost.
pub(crate) fn remove_cycles(paths: &mut [Vec<u32>], cells: usize) {
    let steps = paths.first().map_or(0, Vec::len);
    let mut occupant = vec![u32::MAX; cells];
    for t in 0..steps.saturating_sub(1) {
        for (i, p) in paths.iter().enumerate() {
            occupant[p[t] as usize] = i as u32;
        }
        let cycles = cycles_at(|d, s| paths[d][s], paths.len(), t, &occupant);
        for cycle in cycles {
            // Drone cycle[k - 1] moved into cycle[k]'s voxel; cycle[k] takes its suffix.
            let suffixes: Vec<Vec<u32>> =
                cycle.iter().map(|&d| paths[d][t + 1..].to_vec()).collect();
            for (k, &d) in cycle.iter().enumerate() {
                let from = (k + cycle.len() - 1) % cycle.len();
                paths[d][t + 1..].copy_from_slice(&suffixes[from]);
            }
        }
        for p in paths.iter() {
            occupant[p[t] as usize] = u32::MAX;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swaps_become_waits() {
        let mut paths = vec![vec![0, 1, 2], vec![1, 0, 3]];
        remove_cycles(&mut paths, 4);
        assert_eq!(paths, vec![vec![0, 0, 3], vec![1, 1, 2]]);
    }

    #[test]
    fn three_cycles_become_waits_and_followers_stay() {
        // 0 → 1 → 2 → 0 rotate at step 0; drone 3 follows into 4's voxel, no cycle.
        let mut paths = vec![
            vec![0, 1, 1],
            vec![1, 2, 2],
            vec![2, 0, 0],
            vec![3, 4, 4],
            vec![4, 5, 5],
        ];
        remove_cycles(&mut paths, 6);
        assert_eq!(&paths[..3], &[vec![0, 0, 0], vec![1, 1, 1], vec![2, 2, 2]]);
        assert_eq!(&paths[3..], &[vec![3, 4, 4], vec![4, 5, 5]]);
    }
}
