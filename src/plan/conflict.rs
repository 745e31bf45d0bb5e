//! The first collision between drones of different groups.

/// Two groups in one voxel at one step, or trading voxels along an edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
}

/// The earliest conflict and the total number of conflicts between groups, looking at
/// every path padded with waits to `makespan`.
pub(crate) fn first_conflict(
    routings: &[&[Vec<u32>]],
    cells: usize,
    makespan: u32,
) -> (Option<Conflict>, usize) {
    let at = |path: &Vec<u32>, t: usize| path[t.min(path.len() - 1)];
    // owner[cell] = (group, drone index) of a drone there at the current step.
    let mut owner = vec![(usize::MAX, 0usize); cells];
    let mut first = None;
    let mut count = 0;
    for t in 0..=makespan as usize {
        for (g, paths) in routings.iter().enumerate() {
            for (d, p) in paths.iter().enumerate() {
                let c = at(p, t) as usize;
                let (other, _) = owner[c];
                if other != usize::MAX && other != g {
                    count += 1;
                    first.get_or_insert(Conflict::Vertex {
                        groups: [other, g],
                        cell: c as u32,
                        step: t as u32,
                    });
                } else {
                    owner[c] = (g, d);
                }
            }
        }
        if t < makespan as usize {
            for (g, paths) in routings.iter().enumerate() {
                for p in paths.iter() {
                    let (a, b) = (at(p, t), at(p, t + 1));
                    if a == b {
                        continue;
                    }
                    let (other, od) = owner[b as usize];
                    // Each swap is seen from both sides; count it once, from the lower group.
                    if other != usize::MAX && g < other && at(&routings[other][od], t + 1) == a {
                        count += 1;
                        first.get_or_insert(Conflict::Edge {
                            groups: [g, other],
                            from: a,
                            to: b,
                            step: t as u32,
                        });
                    }
                }
            }
        }
        for paths in routings {
            for p in paths.iter() {
                owner[at(p, t) as usize] = (usize::MAX, 0);
            }
        }
    }
    (first, count)
}
