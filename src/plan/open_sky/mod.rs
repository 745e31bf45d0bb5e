//! Open sky: where nothing stands between two formations, every drone flies
//! straight to its goal, all of them at once, and no search is needed. Drone
//! shows are mostly open sky.
//!
//! Why straight lines are safe (CAPT: Turpin, Michael & Kumar, IJRR 2014). Let
//! drones `i` and `j` of one group start `Δs = sᵢ − sⱼ` apart and end `Δg = gᵢ − gⱼ`
//! apart, and fly their lines in step: at the fraction `α` of the way they are
//! `(1 − α)Δs + αΔg` apart, whose square is
//! `(1 − α)²|Δs|² + α²|Δg|² + 2α(1 − α) Δs·Δg`. Exchanging their goals changes
//! the summed squared distances by `2 Δs·Δg`, so in an assignment that no
//! exchange improves (`assignment`) every pair has `Δs·Δg ≥ 0`, and then they
//! are at least `|Δs||Δg| / √(|Δs|² + |Δg|²) ≥ min(|Δs|, |Δg|) / √2` apart
//! all the way: formations spaced `2√2` drone radii apart cannot collide.
//!
//! Two things keep that from being the whole proof here, so the paths are checked
//! (every pair of drones, vertex, edge, rotation and stacking conflicts): drones
//! of different groups may not exchange goals, so the argument holds within a
//! group only; and on the voxel grid each drone flies a staircase less than two
//! voxels off its line (`staircase`), not the line, so two drones whose lines pass
//! a voxel or two apart can still meet (formations two voxels apart do). Where
//! two meet, one of them flies another staircase of its line (rounded the other
//! way, or its axes in another order), a bounded number of times; a conflict
//! left means no open-sky plan. The validator and the trajectory checker then
//! prove the plan as any other.
//!
//! Pads beside the world have no airspace above them: a drone landing there
//! flies its line to the pad layer under the world's edge and hops along it to
//! its pad (`pad_hop`; taking off, the other way round), in as many moves as the
//! line straight to the pad would take.
//!
//! The makespan is the longest staircase, which may exceed the least possible
//! makespan (the assignment minimises squared distances, not the longest): the
//! caller states the gap to its lower bound, and may search for better.

mod assignment;
mod pad_hop;
mod staircase;

use super::conflict::{Conflict, conflicts};
use super::first_plan::regroup;
use super::space::{NONE, Space};
use crate::world::{Voxel, VoxelGrid};
use assignment::Point;
pub(super) use assignment::pairwise_stable;
use pad_hop::Way;
use staircase::{VARIANTS, staircase};
use std::time::Instant;

/// A leg flown on straight lines: per group, per drone (in start order), its
/// compact cell at every step `0..=makespan`, and a lower bound on any plan's
/// makespan.
#[derive(Debug, Clone)]
pub(super) struct StraightLines {
    pub paths: Vec<Vec<Vec<u32>>>,
    pub makespan: u32,
    /// The farthest any drone is from its group's nearest goal and, where a group
    /// has as many goals as drones, the farthest any goal is from the group's
    /// nearest drone: every plan takes at least that many steps (a move changes
    /// one coordinate by one, so no path is shorter than the Manhattan distance).
    pub lower_bound: u32,
}

/// The leg from `groups` (per group, its drones' starts and its free goals) on
/// straight lines (with a hop along the pad layer to or from a pad beside the
/// world, see `pad_hop`), or `None` when it is not open sky: a line leaves the free
/// cells of `space` whichever way it is flown, lines still meet after a bounded
/// number of repairs (a drone flying another staircase of its line), or `until`
/// passes first. `None` too, before any staircase is flown, when `wanted` says
/// lines of that makespan (the longest assigned line) against that lower bound
/// would not be used, so that their staircases and conflict checks are spared.
pub(super) fn straight_lines(
    grid: &VoxelGrid,
    space: &Space,
    groups: &[(&[Voxel], &[Voxel])],
    until: Instant,
    wanted: impl Fn(u32, u32) -> bool,
) -> Option<StraightLines> {
    // Every drone's way, flattened across groups in order.
    let mut ways: Vec<Way> = Vec::new();
    for &(starts, goals) in groups {
        let points =
            |voxels: &[Voxel]| -> Vec<Point> { voxels.iter().map(|&v| v.into()).collect() };
        let (starts, goals) = (points(starts), points(goals));
        let goal_of = pairwise_stable(&starts, &goals, until)?;
        for (&s, g) in starts.iter().zip(goal_of) {
            ways.push(Way::between(grid, s, goals[g])?);
        }
    }
    let makespan = ways.iter().map(Way::moves).max().unwrap_or(0);
    let lower_bound = groups
        .iter()
        .map(|(starts, goals)| nearest_bound(starts, goals))
        .max()
        .unwrap_or(0);
    if !wanted(makespan, lower_bound) {
        return None;
    }
    let compact = |p: Point| {
        let c = space.compact(grid.cell(p.into())?);
        (c != NONE).then_some(c)
    };
    let fly = |way: &Way, variant: u8| -> Option<Vec<u32>> {
        let ((from, to), hops) = (way.line, way.out.len() + way.into.len());
        let steps = makespan - hops as u32;
        let line = staircase(from, to, steps, variant);
        let cells = way
            .out
            .iter()
            .copied()
            .chain(line)
            .chain(way.into.iter().copied());
        cells.map(compact).collect()
    };
    let mut variant = vec![0u8; ways.len()];
    let mut paths = Vec::with_capacity(ways.len());
    for way in &ways {
        paths.push(fly(way, 0)?);
    }
    // Where two staircases meet, one of the two drones flies another staircase
    // of its line: every meeting found in a round at once, as each round checks
    // the whole leg again.
    for _ in 0..=REPAIR_ROUNDS {
        if Instant::now() >= until {
            return None;
        }
        // Each drone on its own, so that drones of one group are checked too.
        let per_drone: Vec<&[Vec<u32>]> = paths.iter().map(std::slice::from_ref).collect();
        let (meetings, _) = conflicts(&per_drone, space, makespan, ways.len());
        if meetings.is_empty() {
            return Some(StraightLines {
                paths: regroup(groups.iter().map(|(starts, _)| starts.len()), paths),
                makespan,
                lower_bound,
            });
        }
        let mut moved = vec![false; ways.len()];
        for meeting in &meetings {
            let ([a, b], step) = drones_of(meeting)?;
            if moved[a] || moved[b] {
                continue; // one of them flies otherwise already
            }
            // A drone on a hop at that step flies it whatever its staircase, so
            // the other one moves where it can.
            let can = |d: usize| variant[d] + 1 < VARIANTS;
            let on_line = |d: usize| ways[d].on_line_at(step, makespan);
            let d = [b, a]
                .into_iter()
                .filter(|&d| can(d))
                .find(|&d| on_line(d))
                .or_else(|| [b, a].into_iter().find(|&d| can(d)))?;
            // A variant that leaves the free space is skipped.
            loop {
                variant[d] += 1;
                if let Some(path) = fly(&ways[d], variant[d]) {
                    paths[d] = path;
                    break;
                }
                if variant[d] + 1 >= VARIANTS {
                    return None;
                }
            }
            moved[d] = true;
        }
    }
    None
}

/// Rounds of repairs before a leg is given up as not open sky: each costs a
/// check of the whole leg (about 50 ms at 5,000 drones over 66 steps) and
/// repairs every meeting it finds. Carpets two voxels apart rising into a ball
/// meet about 200 times at 5,000 drones.
const REPAIR_ROUNDS: usize = 24;

/// Two drones (as flattened indices) of a conflict between drones, and its step.
fn drones_of(conflict: &Conflict) -> Option<([usize; 2], u32)> {
    match conflict {
        Conflict::Vertex { groups, step, .. }
        | Conflict::Edge { groups, step, .. }
        | Conflict::Stacked { groups, step, .. } => Some((*groups, *step)),
        Conflict::Rotation { moves, step } => match moves.as_slice() {
            [(a, ..), (b, ..), ..] => Some(([*a, *b], *step)),
            _ => None,
        },
    }
}

/// See [`StraightLines::lower_bound`]: one group's.
fn nearest_bound(starts: &[Voxel], goals: &[Voxel]) -> u32 {
    let farthest_to_nearest = |from: &[Voxel], to: &[Voxel]| {
        from.iter()
            .filter_map(|&a| to.iter().map(|&b| a.manhattan(b)).min())
            .max()
            .unwrap_or(0)
    };
    let drones = farthest_to_nearest(starts, goals);
    if goals.len() == starts.len() {
        drones.max(farthest_to_nearest(goals, starts))
    } else {
        drones
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn far() -> Instant {
        Instant::now() + Duration::from_secs(60)
    }

    /// Lines of any makespan are wanted.
    fn any() -> impl Fn(u32, u32) -> bool {
        |_, _| true
    }

    fn voxels(points: &[[i32; 3]]) -> Vec<Voxel> {
        points
            .iter()
            .map(|p| Voxel::new(p[0], p[1], p[2]))
            .collect()
    }

    #[test]
    fn a_line_rises_into_a_square_on_straight_lines() {
        let grid = VoxelGrid::new([8, 8, 6], 1.0, [0.0; 3]);
        let space = Space::new(&grid, 0);
        let starts = voxels(&(0..4).map(|i| [2 * i, 0, 0]).collect::<Vec<_>>());
        let goals = voxels(&[[2, 4, 4], [4, 4, 4], [2, 6, 4], [4, 6, 4]]);
        let lines = straight_lines(&grid, &space, &[(&starts, &goals)], far(), any()).unwrap();
        // The farthest drone (6, 0, 0) is 2 + 4 + 4 = 10 moves from its nearest
        // goal (4, 4, 4), as the goals (2, 6, 4) and (4, 6, 4) are from theirs.
        assert_eq!(lines.lower_bound, 10);
        assert!(lines.makespan >= lines.lower_bound);
        let cell = |v: Voxel| space.compact(grid.cell(v).unwrap());
        for (path, start) in lines.paths[0].iter().zip(&starts) {
            assert_eq!(path.len(), lines.makespan as usize + 1);
            assert_eq!(path[0], cell(*start));
            assert!(goals.iter().any(|&g| cell(g) == path[path.len() - 1]));
            for pair in path.windows(2) {
                assert!(space.moves(pair[0]).contains(&pair[1]), "a jump");
            }
        }
        let ends: Vec<u32> = lines.paths[0].iter().map(|p| p[p.len() - 1]).collect();
        let mut distinct = ends.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), ends.len(), "two drones on one goal");
    }

    #[test]
    fn drones_land_on_pads_beside_the_world_along_the_pad_layer() {
        // A 6×6×4 world over a pad layer reaching two cells beyond its west
        // edge; four drones land from a square in its middle on a row of pads
        // under its west edge and beside it.
        let world = VoxelGrid::new([6, 6, 4], 1.0, [0.0; 3]);
        let grid = VoxelGrid::airspace(&world, -0.5, -2..=5, 0..=5);
        let space = Space::new(&grid, 0);
        let starts = voxels(&[[2, 2, 3], [4, 2, 3], [2, 4, 3], [4, 4, 3]]);
        let pads = voxels(&[[-2, 1, -1], [-2, 4, -1], [0, 1, -1], [0, 4, -1]]);
        let lines = straight_lines(&grid, &space, &[(&starts, &pads)], far(), any()).unwrap();
        let mut ends = Vec::new();
        for path in &lines.paths[0] {
            assert_eq!(path.len(), lines.makespan as usize + 1);
            for pair in path.windows(2) {
                assert!(space.moves(pair[0]).contains(&pair[1]), "a jump");
            }
            ends.push(grid.voxel(space.world_cell(path[path.len() - 1])));
        }
        ends.sort_by_key(|v| (v.x, v.y));
        assert_eq!(ends, pads, "every pad taken once");
        // (4, 2, 3) is 4 + 1 + 4 moves from its nearest pad (0, 1, -1); the hops
        // cost no more than that: the lines meet the bound.
        assert_eq!(lines.lower_bound, 9);
        assert_eq!(lines.makespan, 9);
    }

    #[test]
    fn a_wall_between_the_formations_is_not_open_sky() {
        // A wall across the world with a door at its east end: the way is round
        // by the door, not straight.
        let mut grid = VoxelGrid::new([8, 8, 6], 1.0, [0.0; 3]);
        for x in 0..7 {
            for z in 0..6 {
                grid.block(Voxel::new(x, 3, z));
            }
        }
        let space = Space::new(&grid, 0);
        let starts = voxels(&[[0, 0, 0], [6, 0, 0]]);
        let goals = voxels(&[[0, 6, 4], [6, 6, 4]]);
        assert!(straight_lines(&grid, &space, &[(&starts, &goals)], far(), any()).is_none());
    }

    #[test]
    fn groups_that_must_cross_head_on_are_not_open_sky() {
        // Two groups of one drone each trade ends along a row: they would swap
        // voxels mid-way, and drones of different groups cannot exchange goals.
        let grid = VoxelGrid::new([5, 1, 1], 1.0, [0.0; 3]);
        let space = Space::new(&grid, 0);
        let (west, east) = (voxels(&[[0, 0, 0]]), voxels(&[[4, 0, 0]]));
        let groups = [(&west[..], &east[..]), (&east[..], &west[..])];
        assert!(straight_lines(&grid, &space, &groups, far(), any()).is_none());
        // One group of both: they keep their ends and wait.
        let both = voxels(&[[0, 0, 0], [4, 0, 0]]);
        let lines = straight_lines(&grid, &space, &[(&both, &both)], far(), any()).unwrap();
        assert_eq!(lines.makespan, 0);
    }
}
