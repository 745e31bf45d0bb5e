//! The first collision between drones of different groups.

use super::rotation::cycles_at;

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
    /// Each `(group, from, to)` move between `step` and `step + 1` enters the voxel the next one leaves.
    Rotation {
        moves: Vec<(usize, u32, u32)>,
        step: u32,
    },
}

/// The earliest conflict and the total number of conflicts between groups, looking at
/// every path padded with waits to `makespan`.
pub(crate) fn first_conflict(
    routings: &[&[Vec<u32>]],
    cells: usize,
    makespan: u32,
) -> (Option<Conflict>, usize) {
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
    let mut first = None;
    let mut count = 0;
    for t in 0..=makespan as usize {
        for d in 0..drones.len() {
            let c = at(d, t) as usize;
            let other = occupant[c];
            if other == u32::MAX {
                occupant[c] = d as u32;
            } else if drones[other as usize].0 != drones[d].0 {
                count += 1;
                first.get_or_insert(Conflict::Vertex {
                    groups: [drones[other as usize].0, drones[d].0],
                    cell: c as u32,
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
                first.get_or_insert(match moves.as_slice() {
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
