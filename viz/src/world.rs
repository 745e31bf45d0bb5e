//! The static world: axes, bounds and obstacle voxels.

use crate::error::log_err;
use crate::style::{self, f32x3};
use crate::{Scene, VizError, paths};

/// Logs what never moves: ENU axes, the world box and the obstacles.
pub fn log_world(rec: &rerun::RecordingStream, scene: &Scene) -> Result<(), VizError> {
    let log = |entity: rerun::EntityPath, result: rerun::RecordingStreamResult<()>| {
        result.map_err(log_err(&entity))
    };
    log(
        paths::WORLD.into(),
        rec.log_static(paths::WORLD, &rerun::ViewCoordinates::RIGHT_HAND_Z_UP()),
    )?;
    let b = scene.bounds;
    let center = [0, 1, 2].map(|i| 0.5 * (b.min_m[i] + b.max_m[i]));
    let size = [0, 1, 2].map(|i| b.max_m[i] - b.min_m[i]);
    let bounds = rerun::Boxes3D::from_centers_and_sizes([f32x3(center)], [f32x3(size)])
        .with_colors([style::color(style::BOUNDS_RGB)])
        .with_radii([style::line_radius_m(scene.voxel_size_m)]);
    log(
        paths::world_bounds(),
        rec.log_static(paths::world_bounds(), &bounds),
    )?;
    if !scene.obstacles.is_empty() {
        let obstacles = rerun::Boxes3D::from_centers_and_sizes(
            scene.obstacles.iter().map(|o| f32x3(o.center_m)),
            scene.obstacles.iter().map(|o| f32x3(o.size_m)),
        )
        .with_colors([style::color(style::OBSTACLE_RGB)])
        .with_fill_mode(rerun::FillMode::Solid);
        log(
            paths::obstacles(),
            rec.log_static(paths::obstacles(), &obstacles),
        )?;
    }
    Ok(())
}
