//! The voxel world: which written coordinates lie inside it, and its obstacles,
//! which stand on the ground unless written `overhead`.

use super::bounds::PAD_REACH;
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

    /// The ground cell `[x, y]`, when it lies in the launch area: the world's
    /// footprint and [`PAD_REACH`] cells beside it, where pads and pad-layer
    /// obstacles may be.
    pub(super) fn launch_cell(&self, [x, y]: [i64; 2]) -> Option<[i32; 2]> {
        let reach = i64::from(PAD_REACH);
        let inside = |c: i64, d: u32| (-reach..i64::from(d) + reach).contains(&c);
        (inside(x, self.dimensions[0]) && inside(y, self.dimensions[1]))
            .then_some([x as i32, y as i32])
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

/// The pad-layer cells `[x, y]` that obstacles block: under every obstacle that
/// stands on the ground, and obstacles written in the pad layer itself.
pub(super) type GroundCells = std::collections::BTreeSet<[i32; 2]>;

/// Builds the voxel grid and blocks its obstacles, reporting those that are outside
/// the world (or its launch area) or inverted (such obstacles block nothing).
///
/// An obstacle stands on the ground: it blocks its voxels, every voxel below them
/// down to layer 0, and the pad-layer cell under its column (returned as ground
/// cells, since the pad layer is not part of the world's grid). An `overhead` box
/// blocks only its own voxels. A voxel at `z = -1` is in the pad layer, where it may
/// also lie beside the world, in the launch area.
pub(super) fn build(
    spec: &WorldSpec,
    bounds: &Bounds,
    report: &mut Report,
) -> (VoxelGrid, GroundCells) {
    let mut world = VoxelGrid::new(
        bounds.dimensions,
        spec.voxel_size_m,
        spec.origin_or_default_m(),
    );
    let mut ground = GroundCells::new();
    for (i, obstacle) in spec.obstacles.iter().enumerate() {
        let path = format!("world.obstacles[{i}]");
        let (min, max, overhead) = match obstacle {
            ObstacleSpec::Cell(raw) => match obstacle_voxel(bounds, *raw) {
                Ok(v) => (v, v, false),
                Err(why) => {
                    report.add(path, why);
                    continue;
                }
            },
            ObstacleSpec::Box(b) => match check_box(&path, b, bounds, report) {
                Some((min, max)) => (min, max, b.overhead),
                None => continue,
            },
        };
        let floor_z = if overhead { min.z } else { -1 };
        for y in min.y..=max.y {
            for x in min.x..=max.x {
                for z in floor_z.max(0)..=max.z {
                    world.block(Voxel::new(x, y, z));
                }
                if floor_z < 0 {
                    ground.insert([x, y]);
                }
            }
        }
    }
    (world, ground)
}

/// The voxel at `raw` where an obstacle may be: inside the world, or in the pad
/// layer (`z = -1`) under the world or beside it within the launch area; else why not.
fn obstacle_voxel(bounds: &Bounds, raw: RawVoxel) -> Result<Voxel, String> {
    if raw[2] == -1 {
        let reach = i64::from(PAD_REACH);
        let [dx, dy, _] = bounds.dimensions.map(i64::from);
        return match bounds.launch_cell([raw[0], raw[1]]) {
            Some([x, y]) => Ok(Voxel::new(x, y, -1)),
            None => Err(format!(
                "{raw:?} is in the pad layer (z = -1) but beyond the launch area: x from {} to {}, y from {} to {} ({PAD_REACH} cells beside the world)",
                -reach,
                dx + reach - 1,
                -reach,
                dy + reach - 1
            )),
        };
    }
    bounds.voxel(raw).ok_or_else(|| {
        format!(
            "{} (or z = -1 for an obstacle in the pad layer)",
            bounds.outside(raw)
        )
    })
}

/// The corners of an obstacle box, when both lie where obstacles may be, `min` is
/// nowhere above `max`, a box above the pad layer lies within the world's
/// footprint, and an overhead box does not reach into the pad layer.
fn check_box(
    path: &str,
    b: &BoxSpec,
    bounds: &Bounds,
    report: &mut Report,
) -> Option<(Voxel, Voxel)> {
    let (min, max) = match (obstacle_voxel(bounds, b.min), obstacle_voxel(bounds, b.max)) {
        (Ok(min), Ok(max)) => (min, max),
        (Err(why), _) => {
            // Only the first corner outside is reported.
            report.add(format!("{path}.min"), why);
            return None;
        }
        (_, Err(why)) => {
            report.add(format!("{path}.max"), why);
            return None;
        }
    };
    if min.x > max.x || min.y > max.y || min.z > max.z {
        report.add(path, format!("min {min} exceeds max {max} on some axis"));
        return None;
    }
    if max.z >= 0 && bounds.voxel([min.x, min.y, 0].map(i64::from)).is_none() {
        report.add(
            format!("{path}.min"),
            format!(
                "{min} is beside the world, where only the pad layer is (the box reaches up to layer {}): a box beside the world must lie in the pad layer, z = -1",
                max.z
            ),
        );
        return None;
    }
    if b.overhead && min.z < 0 {
        report.add(
            format!("{path}.overhead"),
            format!(
                "an overhead obstacle leaves the space below it free, but this one reaches down into the pad layer ({min}): start it at layer 0 or above, or drop `overhead`"
            ),
        );
        return None;
    }
    Some((min, max))
}
