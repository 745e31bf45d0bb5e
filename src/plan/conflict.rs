//! The first collision between drones of different groups, and between drones of
//! any groups in cells stacked within an ellipsoid's vertical reach.

use super::rotation::cycles_at;
use super::space::Space;

/// Two groups in one voxel at one step, trading voxels along an edge, or closing a
/// rotation (see [`super::rotation`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Conflict {
    Vertex {
        groups: [usize; 2],
        cell: u32,
        step: u32,
    },
    /// `groups[0]` moves `from → to` while `groups[1]` moves `to → from`, between `step` and `step + 1`.
    Edge {
        groups: [usize; 2],
        from: u32,
        to: u32,
        step: u32,
    },
    /// Two drones (of different groups or of one: `groups` may repeat) in cells of
    /// one column within the vertical reach at `step`.
    Stacked {
        groups: [usize; 2],
        cells: [u32; 2],
        step: u32,
    },
    /// Each `(group, from, to)` move between `step` and `step + 1` enters the voxel the
    /// next one leaves, or one stacked with it.
    Rotation {
        moves: Vec<(usize, u32, u32)>,
        step: u32,
    },
}

/// The earliest conflict and the total number of conflicts between groups, looking at
/// every path padded with waits to `makespan`.
pub(crate) fn first_conflict(
    routings: &[&[Vec<u32>]],
    space: &Space,
    makespan: u32,
) -> (Option<Conflict>, usize) {
    let (found, count) = conflicts(routings, space, makespan, 1);
    (found.into_iter().next(), count)
}

/// The first `keep` conflicts between groups, earliest first, and the total
/// number of them, looking at every path padded with waits to `makespan`.
pub(crate) fn conflicts(
    routings: &[&[Vec<u32>]],
    space: &Space,
    makespan: u32,
    keep: usize,
) -> (Vec<Conflict>, usize) {
    let cells = space.len();
    // Drones flattened across groups: (group, path).
    let drones: Vec<(usize, &Vec<u32>)> = routings
        .iter()
        .enumerate()
        .flat_map(|(g, paths)| paths.iter().map(move |p| (g, p)))
        .collect();
    let at = |d: usize, t: usize| {
        let p = drones[d].1;
        p[t.min(p.len() - 1)]
    };
    let mut occupant = vec![u32::MAX; cells];
    let mut first = Vec::new();
    let mut note = |conflict: Conflict| {
        if first.len() < keep {
            first.push(conflict);
        }
    };
    let mut count = 0;
    for t in 0..=makespan as usize {
        for d in 0..drones.len() {
            let c = at(d, t) as usize;
            let other = occupant[c];
            if other == u32::MAX {
                occupant[c] = d as u32;
            } else if drones[other as usize].0 != drones[d].0 {
                count += 1;
                note(Conflict::Vertex {
                    groups: [drones[other as usize].0, drones[d].0],
                    cell: c as u32,
                    step: t as u32,
                });
            }
        }
        if space.has_stacking() {
            let found = stacked_at(space, &at, drones.len(), t, &occupant);
            count += found.len();
            for (a, b) in found {
                note(Conflict::Stacked {
                    groups: [drones[a].0, drones[b].0],
                    cells: [at(a, t), at(b, t)],
                    step: t as u32,
                });
            }
            if t < makespan as usize
                && let Some(cycle) = stacked_cycle_at(space, &at, drones.len(), t, &occupant)
            {
                count += 1;
                note(Conflict::Rotation {
                    moves: cycle
                        .iter()
                        .map(|&d| (drones[d].0, at(d, t), at(d, t + 1)))
                        .collect(),
                    step: t as u32,
                });
            }
        }
        if t < makespan as usize {
            for cycle in cycles_at(at, drones.len(), t, &occupant) {
                let moves: Vec<(usize, u32, u32)> = cycle
                    .iter()
                    .map(|&d| (drones[d].0, at(d, t), at(d, t + 1)))
                    .collect();
                if moves.iter().all(|m| m.0 == moves[0].0) {
                    continue; // inside one group: the low level removes those
                }
                count += 1;
                note(match moves.as_slice() {
                    &[(a, from, to), (b, ..)] => Conflict::Edge {
                        groups: [a, b],
                        from,
                        to,
                        step: t as u32,
                    },
                    _ => Conflict::Rotation {
                        moves,
                        step: t as u32,
                    },
                });
            }
        }
        for d in 0..drones.len() {
            occupant[at(d, t) as usize] = u32::MAX;
        }
    }
    (first, count)
}

/// Pairs of drones in stacked cells at `t` (each pair once). `occupant` gives the
/// drone in every cell at `t`.
fn stacked_at(
    space: &Space,
    at: &impl Fn(usize, usize) -> u32,
    drones: usize,
    t: usize,
    occupant: &[u32],
) -> Vec<(usize, usize)> {
    let mut pairs = Vec::new();
    for d in 0..drones {
        let c = at(d, t);
        for &other_cell in space.stacked(c) {
            let other = occupant[other_cell as usize];
            // Each pair once: from the drone in the lower-numbered cell.
            if other != u32::MAX && other_cell > c {
                pairs.push((d, other as usize));
            }
        }
    }
    pairs
}

/// A cycle of moves between `t` and `t + 1` in which every drone enters a cell the
/// next one leaves or a cell stacked with it: no schedule can fly it (every drone
/// waits for the next to be out of reach). Drone indices in cycle order; `None`
/// when there is none. Cycles through shared cells only are also found here.
pub(crate) fn stacked_cycle_at(
    space: &Space,
    at: &impl Fn(usize, usize) -> u32,
    drones: usize,
    t: usize,
    occupant: &[u32],
) -> Option<Vec<usize>> {
    // Drone `d` waits for every other drone at `t` in the cell `d` enters or in one
    // stacked with it (if that one stayed, it would be a stacked or vertex conflict).
    let waits_for = |d: usize| -> Vec<usize> {
        let next = at(d, t + 1);
        if next == at(d, t) {
            return Vec::new();
        }
        std::iter::once(next)
            .chain(space.stacked(next).iter().copied())
            .map(|c| occupant[c as usize])
            .filter(|&o| o != u32::MAX && o as usize != d)
            .map(|o| o as usize)
            .collect()
    };
    const UNSEEN: u8 = 0;
    const ON_STACK: u8 = 1;
    const DONE: u8 = 2;
    let mut state = vec![UNSEEN; drones];
    for root in 0..drones {
        if state[root] != UNSEEN {
            continue;
        }
        // Iterative depth-first search; `path` is the current chain.
        let mut path: Vec<(usize, Vec<usize>)> = vec![(root, waits_for(root))];
        state[root] = ON_STACK;
        while let Some((d, pending)) = path.last_mut() {
            let d = *d;
            match pending.pop() {
                Some(next) if state[next] == ON_STACK => {
                    let start = path.iter().position(|(x, _)| *x == next)?;
                    return Some(path[start..].iter().map(|(x, _)| *x).collect());
                }
                Some(next) if state[next] == UNSEEN => {
                    state[next] = ON_STACK;
                    let waits = waits_for(next);
                    path.push((next, waits));
                }
                Some(_) => {}
                None => {
                    state[d] = DONE;
                    path.pop();
                }
            }
        }
    }
    None
}
