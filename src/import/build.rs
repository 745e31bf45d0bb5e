//! The mission every imported instance becomes: a 1 m voxel world and the default
//! limits, since community formats carry neither.

use crate::mission::schema::{GroupSpec, LimitsSpec, LinkSpec, ObstacleSpec, WorldSpec};
use crate::mission::{FenceSpec, MissionFile};
use std::path::Path;

/// Limits given to imported instances, which carry none of their own: 1 m voxels,
/// 1 m/s, 2 m/s², 0.3 m safety distance.
pub fn default_limits() -> LimitsSpec {
    LimitsSpec {
        max_speed_mps: 1.0,
        max_accel_mps2: 2.0,
        max_jerk_mps3: None,
        safety_distance_m: Some(0.3),
        separation: None,
        tracking_error_m: None,
    }
}

/// A mission file around an imported world and groups.
pub(crate) fn mission_file(
    name: String,
    source: &Path,
    world: WorldSpec,
    groups: Vec<GroupSpec>,
) -> MissionFile {
    MissionFile {
        name,
        description: Some(format!("Imported from {}", source.display())),
        world,
        limits: default_limits(),
        link: LinkSpec::default(),
        groups,
        stages: Vec::new(),
        landing: None,
        fence: FenceSpec::default(),
    }
}

/// A 1 m voxel world lifted 1 m off the ground, its formations kept in the world's
/// own voxels: an imported instance is planned as exactly that instance (a 2D map is
/// one layer), so its makespan compares with the published solvers'. The pads below
/// and the takeoff and landing legs through them are swarmctl's own, reported apart.
pub(crate) fn world_spec(dimensions: [i64; 3], obstacles: Vec<ObstacleSpec>) -> WorldSpec {
    WorldSpec {
        dimensions,
        voxel_size_m: 1.0,
        origin_m: Some([0.0, 0.0, 1.0]),
        pad_height_m: None,
        geo_origin: None,
        obstacles,
        formations_use_pad_layer: false,
    }
}
