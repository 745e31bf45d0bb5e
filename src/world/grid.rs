//! The voxel world: bounds, obstacles, metric placement and the 6-connected graph.

use super::Voxel;
use nalgebra::Point3;
use std::collections::VecDeque;

/// Dense index of a voxel inside a [`VoxelGrid`]; the planner works on these.
pub type Cell = usize;

/// Marks an unreachable cell in the result of [`VoxelGrid::distances_from`].
pub const UNREACHABLE: u32 = u32::MAX;

/// A box of voxels, each free or blocked, placed in ENU metres.
///
/// ```
/// use swarmctl::world::{Voxel, VoxelGrid};
/// let mut grid = VoxelGrid::new([3, 1, 1], 0.5, [0.0, 0.0, 1.0]);
/// grid.block(Voxel::new(1, 0, 0));
/// assert_eq!(grid.free_count(), 2);
/// assert_eq!(grid.center_m(Voxel::new(2, 0, 0)).x, 1.0);
/// let from = grid.cell(Voxel::new(0, 0, 0)).unwrap();
/// assert_eq!(grid.neighbours(from).count(), 0); // the only way on is blocked
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct VoxelGrid {
    dimensions: [u32; 3],
    /// The voxel with the smallest coordinates: `[0, 0, 0]` for a mission's world,
    /// below and beside it for the airspace (pad layer, launch areas).
    min: [i32; 3],
    voxel_size_m: f64,
    origin_m: [f64; 3],
    /// Centre height of the lowest layer when it is a pad layer, ENU metres: the pads'
    /// low hover height, which need not sit a whole voxel below layer 0.
    pad_layer_z_m: Option<f64>,
    blocked: Vec<bool>,
}

impl VoxelGrid {
    /// An empty world. Dimensions must have been validated (non-zero, bounded).
    pub fn new(dimensions: [u32; 3], voxel_size_m: f64, origin_m: [f64; 3]) -> Self {
        let len = dimensions.iter().map(|&d| d as usize).product();
        Self {
            dimensions,
            min: [0; 3],
            voxel_size_m,
            origin_m,
            pad_layer_z_m: None,
            blocked: vec![false; len],
        }
    }

    /// The airspace around `world`: the world itself, a pad layer below it (its
    /// centres at `pad_layer_z_m`) reaching sideways to cover `x_range` × `y_range`,
    /// and, outside the world's footprint above the pad layer, nothing (blocked):
    /// drones leave the pad layer only into the world's own voxels.
    pub fn airspace(
        world: &VoxelGrid,
        pad_layer_z_m: f64,
        x_range: std::ops::RangeInclusive<i32>,
        y_range: std::ops::RangeInclusive<i32>,
    ) -> VoxelGrid {
        let [wx, wy, wz] = world.dimensions;
        let lo = [
            (*x_range.start()).min(world.min[0]),
            (*y_range.start()).min(world.min[1]),
            world.min[2] - 1,
        ];
        let hi = [
            (*x_range.end()).max(world.min[0] + wx as i32 - 1),
            (*y_range.end()).max(world.min[1] + wy as i32 - 1),
            world.min[2] + wz as i32 - 1,
        ];
        let dimensions = std::array::from_fn(|i| (hi[i] - lo[i] + 1) as u32);
        let mut grid = VoxelGrid::new(dimensions, world.voxel_size_m, world.origin_m);
        grid.min = lo;
        grid.pad_layer_z_m = Some(pad_layer_z_m);
        for c in 0..grid.len() {
            let v = grid.voxel(c);
            let blocked = if v.z == lo[2] {
                false
            } else {
                !world.contains(v) || world.is_blocked(v)
            };
            grid.blocked[c] = blocked;
        }
        grid
    }

    /// This grid with every cell of its pad layer blocked (unchanged when it has
    /// none): the world's own voxels, where a leg that keeps out of the pad layer
    /// is planned and checked.
    pub fn without_pad_layer(&self) -> VoxelGrid {
        let mut grid = self.clone();
        if grid.pad_layer_z_m.is_some() {
            let plane = grid.dimensions[0] as usize * grid.dimensions[1] as usize;
            grid.blocked[..plane].fill(true);
        }
        grid
    }

    /// The voxel with the smallest coordinates (`[0, 0, 0]` for a mission's world).
    pub fn min_voxel(&self) -> Voxel {
        Voxel::from(self.min)
    }

    /// The pad layer's centre height, ENU metres, when this grid has one.
    pub fn pad_layer_z_m(&self) -> Option<f64> {
        self.pad_layer_z_m
    }

    /// World size in voxels along x (east), y (north), z (up).
    pub fn dimensions(&self) -> [u32; 3] {
        self.dimensions
    }

    /// Edge length of one voxel, metres.
    pub fn voxel_size_m(&self) -> f64 {
        self.voxel_size_m
    }

    /// The centre of voxel `[0, 0, 0]`, ENU metres: where the grid is placed.
    pub fn origin_m(&self) -> [f64; 3] {
        self.origin_m
    }

    /// Number of voxels, blocked or free.
    pub fn len(&self) -> usize {
        self.blocked.len()
    }

    /// True for a world of no voxels (validated missions never have one).
    pub fn is_empty(&self) -> bool {
        self.blocked.is_empty()
    }

    /// Number of voxels that are not obstacles.
    pub fn free_count(&self) -> usize {
        self.blocked.iter().filter(|&&b| !b).count()
    }

    /// True for a voxel inside the world's bounds, free or not.
    pub fn contains(&self, v: Voxel) -> bool {
        self.local(v).is_some()
    }

    /// `v` relative to the grid's lowest corner, when inside the grid.
    fn local(&self, v: Voxel) -> Option<[usize; 3]> {
        let rel = [v.x, v.y, v.z];
        let mut out = [0usize; 3];
        for i in 0..3 {
            let d = i64::from(rel[i]) - i64::from(self.min[i]);
            if d < 0 || d >= i64::from(self.dimensions[i]) {
                return None;
            }
            out[i] = d as usize;
        }
        Some(out)
    }

    /// The dense index of `v`, or `None` outside the world.
    pub fn cell(&self, v: Voxel) -> Option<Cell> {
        self.local(v).map(|[x, y, z]| {
            let [dx, dy, _] = self.dimensions.map(|d| d as usize);
            x + dx * (y + dy * z)
        })
    }

    /// The voxel at a dense index obtained from this grid.
    pub fn voxel(&self, cell: Cell) -> Voxel {
        let [dx, dy, _] = self.dimensions.map(|d| d as usize);
        Voxel::new(
            (cell % dx) as i32 + self.min[0],
            ((cell / dx) % dy) as i32 + self.min[1],
            (cell / (dx * dy)) as i32 + self.min[2],
        )
    }

    /// Makes `v` an obstacle; a voxel outside the world is ignored.
    pub fn block(&mut self, v: Voxel) {
        if let Some(c) = self.cell(v) {
            self.blocked[c] = true;
        }
    }

    /// True for an obstacle voxel (false outside the world).
    pub fn is_blocked(&self, v: Voxel) -> bool {
        self.cell(v).is_some_and(|c| self.blocked[c])
    }

    /// True for a voxel inside the world and not an obstacle.
    pub fn is_free(&self, v: Voxel) -> bool {
        self.cell(v).is_some_and(|c| !self.blocked[c])
    }

    /// [`is_free`](Self::is_free) for a dense index obtained from this grid.
    pub fn is_free_cell(&self, cell: Cell) -> bool {
        !self.blocked[cell]
    }

    /// All obstacle voxels, in cell order.
    pub fn obstacles(&self) -> impl Iterator<Item = Voxel> + '_ {
        (0..self.len())
            .filter(|&c| self.blocked[c])
            .map(|c| self.voxel(c))
    }

    /// Centre of voxel `v` in ENU metres: `origin_m + voxel_size_m * (x, y, z)`, except
    /// on a pad layer, whose centres sit at the pads' hover height.
    pub fn center_m(&self, v: Voxel) -> Point3<f64> {
        let s = self.voxel_size_m;
        let [ox, oy, oz] = self.origin_m;
        let z = match self.pad_layer_z_m {
            Some(z) if v.z == self.min[2] => z,
            _ => oz + s * f64::from(v.z),
        };
        Point3::new(ox + s * f64::from(v.x), oy + s * f64::from(v.y), z)
    }

    /// The free face neighbours of a cell (6-connectivity).
    pub fn neighbours(&self, cell: Cell) -> impl Iterator<Item = Cell> + '_ {
        let [dx, dy, dz] = self.dimensions.map(|d| d as usize);
        let (x, y, z) = (cell % dx, (cell / dx) % dy, cell / (dx * dy));
        let plane = dx * dy;
        let candidates = [
            (x > 0).then(|| cell - 1),
            (x + 1 < dx).then(|| cell + 1),
            (y > 0).then(|| cell - dx),
            (y + 1 < dy).then(|| cell + dx),
            (z > 0).then(|| cell - plane),
            (z + 1 < dz).then(|| cell + plane),
        ];
        candidates
            .into_iter()
            .flatten()
            .filter(move |&n| !self.blocked[n])
    }

    /// Breadth-first move counts from `from` to every cell ([`UNREACHABLE`] where none).
    pub fn distances_from(&self, from: Cell) -> Vec<u32> {
        self.distances_from_any(&[from])
    }

    /// Breadth-first move counts from the nearest of `sources` to every cell
    /// ([`UNREACHABLE`] where none; blocked sources are ignored).
    pub fn distances_from_any(&self, sources: &[Cell]) -> Vec<u32> {
        let mut dist = vec![UNREACHABLE; self.len()];
        let mut queue = VecDeque::with_capacity(sources.len());
        for &s in sources {
            if !self.blocked[s] && dist[s] == UNREACHABLE {
                dist[s] = 0;
                queue.push_back(s);
            }
        }
        while let Some(c) = queue.pop_front() {
            let next = dist[c] + 1;
            for n in self.neighbours(c) {
                if dist[n] == UNREACHABLE {
                    dist[n] = next;
                    queue.push_back(n);
                }
            }
        }
        dist
    }

    /// Connected-component label of every free cell (`u32::MAX` for obstacles).
    pub fn components(&self) -> Vec<u32> {
        let mut label = vec![u32::MAX; self.len()];
        let mut next_label = 0;
        let mut queue = VecDeque::new();
        for seed in 0..self.len() {
            if self.blocked[seed] || label[seed] != u32::MAX {
                continue;
            }
            label[seed] = next_label;
            queue.push_back(seed);
            while let Some(c) = queue.pop_front() {
                for n in self.neighbours(c) {
                    if label[n] == u32::MAX {
                        label[n] = next_label;
                        queue.push_back(n);
                    }
                }
            }
            next_label += 1;
        }
        label
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_and_voxel_round_trip() {
        let grid = VoxelGrid::new([4, 3, 2], 1.0, [0.0; 3]);
        for c in 0..grid.len() {
            assert_eq!(grid.cell(grid.voxel(c)), Some(c));
        }
        assert_eq!(grid.cell(Voxel::new(4, 0, 0)), None);
    }

    #[test]
    fn neighbours_respect_bounds_and_obstacles() {
        let mut grid = VoxelGrid::new([3, 3, 3], 1.0, [0.0; 3]);
        let centre = grid.cell(Voxel::new(1, 1, 1)).unwrap();
        assert_eq!(grid.neighbours(centre).count(), 6);
        grid.block(Voxel::new(1, 1, 2));
        assert_eq!(grid.neighbours(centre).count(), 5);
        let corner = grid.cell(Voxel::new(0, 0, 0)).unwrap();
        assert_eq!(grid.neighbours(corner).count(), 3);
    }

    #[test]
    fn distances_go_around_walls() {
        // A wall at x = 1 with a gap at the top: the way over costs two extra moves.
        let mut grid = VoxelGrid::new([3, 1, 2], 1.0, [0.0; 3]);
        grid.block(Voxel::new(1, 0, 0));
        let d = grid.distances_from(grid.cell(Voxel::new(0, 0, 0)).unwrap());
        assert_eq!(d[grid.cell(Voxel::new(2, 0, 0)).unwrap()], 4);
        assert_eq!(d[grid.cell(Voxel::new(1, 0, 0)).unwrap()], UNREACHABLE);
    }

    #[test]
    fn components_split_on_a_full_wall() {
        let mut grid = VoxelGrid::new([3, 1, 1], 1.0, [0.0; 3]);
        grid.block(Voxel::new(1, 0, 0));
        let labels = grid.components();
        assert_ne!(labels[0], labels[2]);
        assert_eq!(labels[1], u32::MAX);
    }
}
