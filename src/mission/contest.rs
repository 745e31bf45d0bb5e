//! Whether every drone of a leg can end it on a voxel of its own: groups whose
//! targets overlap may need more of the shared voxels than there are.
//!
//! Each group (or single drone) of a leg may end on any of its targets, and no two
//! drones on one voxel. Within a group that always fits (a group has at least as many
//! targets as drones), but a goal of one group may be where another group must be at
//! the same time: its start, a spare's hold, or where a group not named by a stage
//! stays. Under an ellipsoid, two voxels that must both be taken may also be stacked
//! within its vertical reach. No path search can place them then, however long it
//! runs, so validation refuses such a mission and the planner answers at once
//! instead of searching until its deadline. Read by both; it knows nothing of how
//! either goes on.

use crate::world::Voxel;
use std::collections::{BTreeMap, HashMap};

/// Demands that cannot all be placed, and the voxels they compete for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Contest {
    /// Indices of the demands that need shared voxels, in input order.
    pub demands: Vec<usize>,
    /// The voxels they compete for, sorted: more than one of them may take each, or
    /// (`stacked`) two they must both take.
    pub voxels: Vec<Voxel>,
    /// The two voxels are stacked within the separation's vertical reach: no two
    /// drones may hold both at once.
    pub stacked: bool,
}

/// `None` when each demand `(drones, targets)` can have `drones` distinct voxels of
/// its `targets` with no voxel given twice overall and no two voxels it must take
/// `stacked` (related by an ellipsoid's vertical reach; never, for a sphere);
/// otherwise who competes for what. The stacking test is sound, not complete: it
/// looks only at demands with no more targets than drones, which take them all.
pub fn contested(
    demands: &[(usize, &[Voxel])],
    stacked: &dyn Fn(Voxel, Voxel) -> bool,
) -> Option<Contest> {
    too_few(demands).or_else(|| stacked_musts(demands, stacked))
}

/// Two voxels that demands with no more targets than drones must take, stacked.
fn stacked_musts(
    demands: &[(usize, &[Voxel])],
    stacked: &dyn Fn(Voxel, Voxel) -> bool,
) -> Option<Contest> {
    let mut columns: BTreeMap<(i32, i32), Vec<(Voxel, usize)>> = BTreeMap::new();
    for (i, &(drones, targets)) in demands.iter().enumerate() {
        let mut all = targets.to_vec();
        all.sort_unstable();
        all.dedup();
        if all.len() <= drones {
            for v in all {
                columns.entry((v.x, v.y)).or_default().push((v, i));
            }
        }
    }
    for cells in columns.values() {
        for (k, &(a, i)) in cells.iter().enumerate() {
            if let Some(&(b, j)) = cells[k + 1..]
                .iter()
                .find(|&&(b, _)| a != b && stacked(a, b))
            {
                let mut demands = vec![i, j];
                demands.sort_unstable();
                demands.dedup();
                let mut voxels = vec![a, b];
                voxels.sort_unstable();
                return Some(Contest {
                    demands,
                    voxels,
                    stacked: true,
                });
            }
        }
    }
    None
}

/// Whether the demands need more of their shared voxels than there are.
///
/// A demand with at least as many voxels of its own (no other demand lists them) as
/// drones never needs a shared one, so it is left out; each of the rest needs the
/// difference from the shared voxels: first greedily, then by augmenting paths,
/// stopping at the first drone no path places (it never will be). Shared voxels
/// are few in any real leg, so this is quick even for thousands of drones.
fn too_few(demands: &[(usize, &[Voxel])]) -> Option<Contest> {
    let mut listed_by: HashMap<Voxel, Vec<usize>> = HashMap::new();
    for (i, (_, targets)) in demands.iter().enumerate() {
        for &v in targets.iter() {
            let by = listed_by.entry(v).or_default();
            if by.last() != Some(&i) {
                by.push(i);
            }
        }
    }
    let mut shared: Vec<Voxel> = listed_by
        .iter()
        .filter(|(_, by)| by.len() > 1)
        .map(|(&v, _)| v)
        .collect();
    shared.sort_unstable();
    let index: HashMap<Voxel, usize> = shared.iter().enumerate().map(|(k, &v)| (v, k)).collect();
    // Per demand still short of voxels of its own: which one, and the shared voxels
    // it lists; one slot per shared voxel it needs.
    let mut short: Vec<(usize, Vec<usize>)> = Vec::new();
    let mut slots: Vec<usize> = Vec::new();
    for (i, &(drones, targets)) in demands.iter().enumerate() {
        let mut own: Vec<Voxel> = targets
            .iter()
            .copied()
            .filter(|v| !index.contains_key(v))
            .collect();
        own.sort_unstable();
        own.dedup();
        if own.len() < drones {
            let mut options: Vec<usize> = targets
                .iter()
                .filter_map(|v| index.get(v).copied())
                .collect();
            options.sort_unstable();
            options.dedup();
            slots.extend(std::iter::repeat_n(short.len(), drones - own.len()));
            short.push((i, options));
        }
    }
    let options: Vec<&[usize]> = slots.iter().map(|&d| &short[d].1[..]).collect();
    let mut taken_by: Vec<Option<usize>> = vec![None; shared.len()];
    let mut waiting = Vec::new();
    for (slot, opts) in options.iter().enumerate() {
        match opts.iter().find(|&&v| taken_by[v].is_none()) {
            Some(&v) => taken_by[v] = Some(slot),
            None => waiting.push(slot),
        }
    }
    let fits = waiting.into_iter().all(|slot| {
        let mut seen = vec![false; shared.len()];
        augment(slot, &options, &mut taken_by, &mut seen)
    });
    if fits {
        return None;
    }
    let competing: Vec<usize> = short.iter().map(|(i, _)| *i).collect();
    let voxels = shared
        .into_iter()
        .filter(|v| {
            listed_by
                .get(v)
                .is_some_and(|by| by.iter().any(|i| competing.contains(i)))
        })
        .collect();
    Some(Contest {
        demands: competing,
        voxels,
        stacked: false,
    })
}

/// Kuhn's augmenting path from `slot`: true if it (and every slot it displaces) found
/// a shared voxel.
fn augment(
    slot: usize,
    options: &[&[usize]],
    taken_by: &mut [Option<usize>],
    seen: &mut [bool],
) -> bool {
    for &v in options[slot] {
        if seen[v] {
            continue;
        }
        seen[v] = true;
        let free = match taken_by[v] {
            None => true,
            Some(other) => augment(other, options, taken_by, seen),
        };
        if free {
            taken_by[v] = Some(slot);
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: i32, y: i32, z: i32) -> Voxel {
        Voxel::new(x, y, z)
    }

    /// A sphere: no two cells related.
    fn sphere(_: Voxel, _: Voxel) -> bool {
        false
    }

    fn contested_in_sphere(demands: &[(usize, &[Voxel])]) -> Option<Contest> {
        contested(demands, &sphere)
    }

    #[test]
    fn a_goal_where_another_group_must_be_is_contested() {
        // Group 0: one drone, its only goal is group 1's start.
        let a = [v(1, 2, 1)];
        let b = [v(1, 2, 0), v(1, 2, 1)];
        let c = contested_in_sphere(&[(1, &a), (2, &b)]).expect("contested");
        assert_eq!(c.demands, [0, 1]);
        assert_eq!(c.voxels, [v(1, 2, 1)]);
    }

    #[test]
    fn shared_voxels_are_fine_while_there_are_enough() {
        // Both list [0,0,0]; one has a voxel of its own to spare.
        let a = [v(0, 0, 0), v(1, 0, 0)];
        let b = [v(0, 0, 0), v(2, 0, 0)];
        assert_eq!(contested_in_sphere(&[(1, &a), (1, &b)]), None);
        // Three drones over three voxels, two shared: an assignment exists.
        let c = [v(0, 0, 0), v(5, 0, 0)];
        assert_eq!(contested_in_sphere(&[(2, &c), (1, &a)]), None);
        // Disjoint targets never contest.
        assert_eq!(
            contested_in_sphere(&[(2, &[v(0, 0, 1), v(0, 0, 2)]), (1, &[v(3, 3, 3)])]),
            None
        );
    }

    #[test]
    fn a_drone_displaced_along_a_chain_still_fits() {
        // d0 may take s0 or s1, d1 only s0, d2 s1 or s2: fits only by displacing d0.
        let s = [v(0, 0, 0), v(1, 0, 0), v(2, 0, 0)];
        let d0 = [s[0], s[1]];
        let d1 = [s[0]];
        let d2 = [s[1], s[2]];
        let d3 = [s[2], s[1]];
        assert_eq!(contested_in_sphere(&[(1, &d0), (1, &d1), (1, &d2)]), None);
        let c =
            contested_in_sphere(&[(1, &d0), (1, &d1), (1, &d2), (1, &d3)]).expect("four for three");
        assert_eq!(c.demands, [0, 1, 2, 3]);
        assert_eq!(c.voxels, s);
    }

    #[test]
    fn voxels_that_must_both_be_taken_may_not_be_stacked() {
        // Adjacent layers of one column are related (a tall ellipsoid).
        let tall = |a: Voxel, b: Voxel| a.x == b.x && a.y == b.y && (a.z - b.z).abs() == 1;
        let start = [v(1, 2, 0), v(2, 3, 1)];
        let spare_hold = [v(1, 2, -1), v(0, 0, 0)];
        let c = contested(&[(2, &start), (2, &spare_hold)], &tall).expect("stacked");
        assert!(c.stacked);
        assert_eq!(c.demands, [0, 1]);
        assert_eq!(c.voxels, [v(1, 2, -1), v(1, 2, 0)]);
        // With a third target the group may leave the stacked one empty: not refused.
        let roomy = [v(1, 2, -1), v(0, 0, 0), v(4, 4, 4)];
        assert_eq!(contested(&[(2, &start), (2, &roomy)], &tall), None);
        // A sphere relates nothing.
        assert_eq!(contested(&[(2, &start), (2, &spare_hold)], &sphere), None);
    }
}
