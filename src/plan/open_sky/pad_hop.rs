//! Pads beside the world: the airspace above a launch area is closed (drones
//! leave the pad layer only into the world's own voxels), so a line to or from
//! a pad there would cut through it. Such a drone hops along the pad layer
//! between its pad and the nearest cell it can rise from, and flies its line
//! from there.

use super::assignment::Point;
use crate::world::{Voxel, VoxelGrid};

/// Hops longer than this are not open sky: pads that far out are better left
/// to the search, which sees the traffic along the pad layer.
const MAX_HOP: usize = 32;

/// A drone's way from its start to its goal: along the pad layer out from under
/// closed airspace (`out`, from the start, without the line's first cell), the
/// `line`, then along the pad layer to the goal (`into`, without the line's last
/// cell, ending at the goal). Where both ends have open airspace above, both
/// hops are empty and the way is the line.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Way {
    pub out: Vec<Point>,
    pub line: (Point, Point),
    pub into: Vec<Point>,
}

impl Way {
    /// The way from `from` to `to` in `grid`, or `None` when an end lies more
    /// than [`MAX_HOP`] cells from open airspace, or under closed airspace with
    /// nowhere nearer the other end to go.
    pub(super) fn between(grid: &VoxelGrid, from: Point, to: Point) -> Option<Way> {
        if from == to {
            // A drone that stays waits where it is, open airspace or not.
            return Some(Way {
                out: Vec::new(),
                line: (from, to),
                into: Vec::new(),
            });
        }
        let mut out = hop(grid, from, to)?;
        let mut into = hop(grid, to, from)?;
        // Each hop ends at the line's end it reaches (its last cell); the way
        // keeps those cells on the line.
        let exit = out.pop()?;
        let entry = into.pop()?;
        into.reverse();
        Some(Way {
            out,
            line: (exit, entry),
            into,
        })
    }

    /// Whether a drone on this way, flown over `makespan` steps, is on its line
    /// (not on a hop) at `step`: only there does another staircase of its line
    /// put it elsewhere.
    pub(super) fn on_line_at(&self, step: u32, makespan: u32) -> bool {
        let step = step as usize;
        step >= self.out.len() && step + self.into.len() <= makespan as usize
    }

    /// Moves the way takes at the least: its hops and the line's Manhattan length.
    pub(super) fn moves(&self) -> u32 {
        let (a, b) = self.line;
        let line: u32 = (0..3).map(|k| a[k].abs_diff(b[k])).sum();
        line + (self.out.len() + self.into.len()) as u32
    }
}

/// The cells from `at` along the pad layer towards `toward`'s column until one
/// is not closed in (`at` alone when it is not), each step along the axis with
/// farther to go; `None` past [`MAX_HOP`] or when `at` is below `toward`'s
/// column and still closed in.
fn hop(grid: &VoxelGrid, at: Point, toward: Point) -> Option<Vec<Point>> {
    let mut cells = vec![at];
    let mut here = at;
    while closed_in(grid, here) {
        if cells.len() > MAX_HOP {
            return None;
        }
        let gap = [0, 1].map(|k| toward[k] - here[k]);
        let k = if gap[0].abs() >= gap[1].abs() { 0 } else { 1 };
        if gap[k] == 0 {
            return None;
        }
        here[k] += gap[k].signum();
        cells.push(here);
    }
    Some(cells)
}

/// Whether `p` is a cell of `grid`'s pad layer with no free cell above it: a
/// launch area beside the world, or under an obstacle standing on the ground.
/// A cell of the world itself never is (the top layer has nothing above it,
/// and needs nothing).
fn closed_in(grid: &VoxelGrid, p: Point) -> bool {
    grid.pad_layer_z_m().is_some()
        && p[2] == grid.min_voxel().z
        && !grid.is_free(Voxel::new(p[0], p[1], p[2] + 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4×4×3 world over a pad layer reaching two cells west of it.
    fn airspace() -> VoxelGrid {
        let world = VoxelGrid::new([4, 4, 3], 1.0, [0.0; 3]);
        VoxelGrid::airspace(&world, -0.5, -2..=3, 0..=3)
    }

    #[test]
    fn a_pad_under_the_world_is_reached_on_the_line() {
        let way = Way::between(&airspace(), [3, 3, 2], [1, 1, -1]).unwrap();
        assert_eq!(way.line, ([3, 3, 2], [1, 1, -1]));
        assert!(way.out.is_empty() && way.into.is_empty());
        assert_eq!(way.moves(), 7);
    }

    #[test]
    fn a_pad_beside_the_world_is_reached_along_the_pad_layer() {
        // The pad two cells west of the world: the line ends under the world's
        // edge, and the last two moves are along the pad layer.
        let way = Way::between(&airspace(), [3, 1, 2], [-2, 1, -1]).unwrap();
        assert_eq!(way.line, ([3, 1, 2], [0, 1, -1]));
        assert_eq!(way.into, vec![[-1, 1, -1], [-2, 1, -1]]);
        // As many moves as the Manhattan distance: nothing is lost on the hop.
        assert_eq!(way.moves(), 5 + 3);
        // Taking off from it: the same cells the other way round.
        let back = Way::between(&airspace(), [-2, 1, -1], [3, 1, 2]).unwrap();
        assert_eq!(back.out, vec![[-2, 1, -1], [-1, 1, -1]]);
        assert_eq!(back.line, ([0, 1, -1], [3, 1, 2]));
        assert!(back.into.is_empty());
    }

    #[test]
    fn a_closed_end_with_nowhere_to_go_is_no_way() {
        // Two pads in one row of the launch area: no move towards the other
        // brings either nearer open airspace (the search plans that).
        assert!(Way::between(&airspace(), [-2, 1, -1], [-2, 2, -1]).is_none());
        // A drone staying on its pad there just waits.
        let stay = Way::between(&airspace(), [-2, 1, -1], [-2, 1, -1]).unwrap();
        assert_eq!(stay.moves(), 0);
    }

    #[test]
    fn the_top_of_the_world_is_open() {
        let way = Way::between(&airspace(), [0, 0, 2], [3, 0, 2]).unwrap();
        assert!(way.out.is_empty() && way.into.is_empty());
    }
}
