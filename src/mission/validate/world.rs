//! The voxel world: which written coordinates lie inside it, and its obstacles.

use super::report::Report;
use crate::mission::schema::{BoxSpec, ObstacleSpec, RawVoxel, WorldSpec};
use crate::world::{Voxel, VoxelGrid};

/// The world's extent, to tell coordinates inside it from those outside.
pub(super) struct Bounds {
    /// Voxels along x, y and z; each at least 1.
    dimensions: [u32; 3],
}

impl Bounds {
    /// Bounds of a world of `dimensions` voxels along x, y and z, each at least 1.
    pub(super) fn new(dimensions: [u32; 3]) -> Self {
        Self { dimensions }
    }

    /// The voxel at `raw`, or `None` when any coordinate lies outside the world.
    pub(super) fn voxel(&self, raw: RawVoxel) -> Option<Voxel> {
        let coordinate = |axis: usize| {
            i32::try_from(raw[axis])
                .ok()
                .filter(|&c| c >= 0 && (c as u32) < self.dimensions[axis])
        };
        Some(Voxel::new(coordinate(0)?, coordinate(1)?, coordinate(2)?))
    }

    /// Voxels along x, y and z.
    pub(super) fn dimensions(&self) -> [u32; 3] {
        self.dimensions
    }

    /// Why `raw` is rejected, with the range the user may write.
    pub(super) fn outside(&self, raw: RawVoxel) -> String {
        format!(
            "{raw:?} is outside the world (dimensions {:?}, coordinates from 0 to {:?})",
            self.dimensions,
            self.dimensions.map(|d| d - 1)
        )
    }
}

/// The voxel at `raw` when it is inside the world and not an obstacle; otherwise
/// reports why at `path`.
pub(super) fn free_voxel(
    world: &VoxelGrid,
    bounds: &Bounds,
    path: &str,
    raw: RawVoxel,
    report: &mut Report,
) -> Option<Voxel> {
    match bounds.voxel(raw) {
        None => {
            report.add(path, bounds.outside(raw));
            None
        }
        Some(v) if world.is_blocked(v) => {
            report.add(path, format!("{v} is inside an obstacle"));
            None
        }
        Some(v) => Some(v),
    }
}

/// Builds the voxel grid and blocks its obstacles, reporting those that are outside
/// the world or inverted (such obstacles block nothing).
pub(super) fn build(spec: &WorldSpec, bounds: &Bounds, report: &mut Report) -> VoxelGrid {
    let mut world = VoxelGrid::new(bounds.dimensions, spec.voxel_size_m, spec.origin_m);
    for (i, obstacle) in spec.obstacles.iter().enumerate() {
        let path = format!("world.obstacles[{i}]");
        match obstacle {
            ObstacleSpec::Cell(raw) => match bounds.voxel(*raw) {
                Some(v) => world.block(v),
                None => report.add(path, bounds.outside(*raw)),
            },
            ObstacleSpec::Box(b) => {
                if let Some((min, max)) = check_box(&path, b, bounds, report) {
                    block_box(&mut world, min, max);
                }
            }
        }
    }
    world
}

/// The corners of an obstacle box, when both lie inside the world and `min` is
/// nowhere above `max`.
fn check_box(
    path: &str,
    b: &BoxSpec,
    bounds: &Bounds,
    report: &mut Report,
) -> Option<(Voxel, Voxel)> {
    let (min, max) = match (bounds.voxel(b.min), bounds.voxel(b.max)) {
        (Some(min), Some(max)) => (min, max),
        (min, _) => {
            // Only the first corner outside is reported.
            let (field, raw) = if min.is_none() {
                ("min", b.min)
            } else {
                ("max", b.max)
            };
            report.add(format!("{path}.{field}"), bounds.outside(raw));
            return None;
        }
    };
    if min.x > max.x || min.y > max.y || min.z > max.z {
        report.add(path, format!("min {min} exceeds max {max} on some axis"));
        return None;
    }
    Some((min, max))
}

/// Blocks every voxel of the inclusive box from `min` to `max`.
fn block_box(world: &mut VoxelGrid, min: Voxel, max: Voxel) {
    for z in min.z..=max.z {
        for y in min.y..=max.y {
            for x in min.x..=max.x {
                world.block(Voxel::new(x, y, z));
            }
        }
    }
}
