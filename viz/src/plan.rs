//! Logging a [`Scene`]: the world, the plan's static geometry and its schedule.
//!
//! The schedule is known in full before logging starts, so it goes in as columns
//! (`send_columns`): one chunk per drone and timeline instead of one row per
//! sample, and no reliance on the stream's per-thread current time.

use crate::style::{self, f32x3};
use crate::{Scene, TimeAxis, VizError, metrics, paths};
use rerun::{RecordingStream, TimeColumn};

/// How often the plan's minimum separation is evaluated, seconds.
const SEPARATION_PERIOD_S: f64 = 0.05;

/// Writes (or streams) a recording of `scene`: static geometry once, the
/// schedule on every axis in `axes`; returns once everything is flushed.
pub fn write_scene(scene: &Scene, sink: &crate::Sink, axes: &[TimeAxis]) -> Result<(), VizError> {
    let timeline = axes.first().map_or(crate::PLAN_TIMELINE, |a| a.timeline);
    let rec = crate::sink::open(&scene.name, sink, timeline)?;
    log_scene(&rec, scene, axes)?;
    rec.flush_blocking()
        .map_err(|e| VizError::Flush(e.to_string()))
}

/// Logs `scene` into `rec`: static geometry once, the schedule on every axis in `axes`.
pub(crate) fn log_scene(
    rec: &RecordingStream,
    scene: &Scene,
    axes: &[TimeAxis],
) -> Result<(), VizError> {
    crate::world::log_world(rec, scene)?;
    log_markers(rec, scene)?;
    log_drone_styles(rec, scene, "plan")?;
    let separation = {
        let tracks: Vec<&[[f64; 4]]> = scene
            .drones
            .iter()
            .map(|d| d.trajectory.as_slice())
            .collect();
        metrics::min_separation_series(&tracks, SEPARATION_PERIOD_S)
    };
    for axis in axes {
        for drone in &scene.drones {
            log_trajectory(rec, drone, axis)?;
        }
        log_series(rec, &paths::min_separation("plan"), axis, &separation)?;
        if let (Some(first), Some(last)) = (separation.first(), separation.last()) {
            let line = [
                (first.0, scene.safety_distance_m),
                (last.0, scene.safety_distance_m),
            ];
            log_series(rec, &paths::safety_distance("plan"), axis, &line)?;
        }
        log_events(rec, scene, axis)?;
    }
    log_series_styles(rec, scene, "plan")?;
    Ok(())
}

pub(crate) fn log_err(
    entity: &rerun::EntityPath,
) -> impl FnOnce(rerun::RecordingStreamError) -> VizError + '_ {
    move |source| VizError::Log {
        entity: entity.to_string(),
        source,
    }
}

pub(crate) fn ser_err(
    entity: &rerun::EntityPath,
) -> impl FnOnce(rerun::SerializationError) -> VizError + '_ {
    move |source| VizError::Serialize {
        entity: entity.to_string(),
        source,
    }
}

/// Start and goal markers per group, and every drone's voxel path as a line strip.
fn log_markers(rec: &RecordingStream, scene: &Scene) -> Result<(), VizError> {
    let radius = style::drone_radius_m(scene.voxel_size_m);
    for (g, group) in scene.groups.iter().enumerate() {
        let members: Vec<_> = scene.drones.iter().filter(|d| d.group == g).collect();
        let color = style::color(group.color_rgb);
        let starts = paths::starts(&group.name);
        rec.log_static(
            starts.clone(),
            &rerun::Points3D::new(members.iter().map(|d| f32x3(d.start_m)))
                .with_radii([radius * 0.6])
                .with_colors([color]),
        )
        .map_err(log_err(&starts))?;
        let goals = paths::goals(&group.name);
        rec.log_static(
            goals.clone(),
            &rerun::Boxes3D::from_centers_and_half_sizes(
                members.iter().map(|d| f32x3(d.goal_m)),
                [[radius; 3]],
            )
            .with_colors([color]),
        )
        .map_err(log_err(&goals))?;
    }
    for drone in &scene.drones {
        let entity = paths::plan_path(&drone.id);
        let strip: Vec<[f32; 3]> = drone.path_m.iter().map(|p| f32x3(*p)).collect();
        rec.log_static(
            entity.clone(),
            &rerun::LineStrips3D::new([strip])
                .with_colors([style::color(scene.drone_color(drone))])
                .with_radii([style::line_radius_m(scene.voxel_size_m)]),
        )
        .map_err(log_err(&entity))?;
    }
    Ok(())
}

/// What does not change over time for each drone marker: label, colour, size,
/// and the safety sphere's radius (half the safety distance, so two spheres
/// overlap exactly when two drones are closer than the safety distance).
pub(crate) fn log_drone_styles(
    rec: &RecordingStream,
    scene: &Scene,
    kind: &str,
) -> Result<(), VizError> {
    let radius = style::drone_radius_m(scene.voxel_size_m);
    let half = (scene.safety_distance_m / 2.0) as f32;
    for drone in &scene.drones {
        let rgb = match kind {
            "flight" => style::flown(scene.drone_color(drone)),
            _ => scene.drone_color(drone),
        };
        let entity = paths::drone(kind, &drone.id);
        rec.log_static(
            entity.clone(),
            &rerun::Points3D::update_fields()
                .with_labels([drone.id.as_str()])
                .with_colors([style::color(rgb)])
                .with_radii([radius]),
        )
        .map_err(log_err(&entity))?;
        let entity = paths::safety(kind, &drone.id);
        rec.log_static(
            entity.clone(),
            &rerun::Ellipsoids3D::update_fields()
                .with_half_sizes([[half; 3]])
                .with_colors([style::color(rgb)])
                .with_fill_mode(rerun::FillMode::MajorWireframe),
        )
        .map_err(log_err(&entity))?;
    }
    Ok(())
}

/// One drone's scheduled positions, safety sphere centres and speed as columns.
fn log_trajectory(
    rec: &RecordingStream,
    drone: &crate::Drone,
    axis: &TimeAxis,
) -> Result<(), VizError> {
    if drone.trajectory.is_empty() {
        return Ok(());
    }
    let times = || {
        TimeColumn::new_duration_secs(
            axis.timeline,
            drone.trajectory.iter().map(|s| s[0] + axis.offset_s),
        )
    };
    let positions: Vec<[f32; 3]> = drone
        .trajectory
        .iter()
        .map(|s| f32x3([s[1], s[2], s[3]]))
        .collect();
    let entity = paths::drone("plan", &drone.id);
    let columns = rerun::Points3D::update_fields()
        .with_positions(positions.iter().copied())
        .columns_of_unit_batches()
        .map_err(ser_err(&entity))?;
    rec.send_columns(entity.clone(), [times()], columns)
        .map_err(log_err(&entity))?;
    let entity = paths::safety("plan", &drone.id);
    let columns = rerun::Ellipsoids3D::update_fields()
        .with_centers(positions)
        .columns_of_unit_batches()
        .map_err(ser_err(&entity))?;
    rec.send_columns(entity.clone(), [times()], columns)
        .map_err(log_err(&entity))?;
    log_series(
        rec,
        &paths::speed("plan", &drone.id),
        axis,
        &metrics::speeds(&drone.trajectory),
    )
}

/// A scalar time series `(t_s, value)` as one column.
pub(crate) fn log_series(
    rec: &RecordingStream,
    entity: &rerun::EntityPath,
    axis: &TimeAxis,
    series: &[(f64, f64)],
) -> Result<(), VizError> {
    if series.is_empty() {
        return Ok(());
    }
    let times =
        TimeColumn::new_duration_secs(axis.timeline, series.iter().map(|s| s.0 + axis.offset_s));
    let columns = rerun::Scalars::new(series.iter().map(|s| s.1))
        .columns_of_unit_batches()
        .map_err(ser_err(entity))?;
    rec.send_columns(entity.clone(), [times], columns)
        .map_err(log_err(entity))
}

/// Series names and colours: each drone's speed in its group colour, the
/// safety distance in red.
pub(crate) fn log_series_styles(
    rec: &RecordingStream,
    scene: &Scene,
    kind: &str,
) -> Result<(), VizError> {
    for drone in &scene.drones {
        let entity = paths::speed(kind, &drone.id);
        rec.log_static(
            entity.clone(),
            &rerun::SeriesLines::new()
                .with_names([drone.id.as_str()])
                .with_colors([style::color(scene.drone_color(drone))]),
        )
        .map_err(log_err(&entity))?;
    }
    let entity = paths::safety_distance(kind);
    rec.log_static(
        entity.clone(),
        &rerun::SeriesLines::new()
            .with_names(["safety distance"])
            .with_colors([style::color(style::SAFETY_RGB)]),
    )
    .map_err(log_err(&entity))?;
    let entity = paths::min_separation(kind);
    rec.log_static(
        entity.clone(),
        &rerun::SeriesLines::new().with_names([format!("{kind} min separation")]),
    )
    .map_err(log_err(&entity))
}

/// TPG waits and other scheduled events as text, in time order.
fn log_events(rec: &RecordingStream, scene: &Scene, axis: &TimeAxis) -> Result<(), VizError> {
    if scene.events.is_empty() {
        return Ok(());
    }
    let entity = paths::events("plan");
    let times = TimeColumn::new_duration_secs(
        axis.timeline,
        scene.events.iter().map(|e| e.t_s + axis.offset_s),
    );
    let texts: Vec<String> = scene
        .events
        .iter()
        .map(|e| match &e.drone {
            Some(d) => format!("{d}: {}", e.text),
            None => e.text.clone(),
        })
        .collect();
    let columns = rerun::TextLog::update_fields()
        .with_many_text(texts)
        .with_many_level(std::iter::repeat_n(
            rerun::TextLogLevel::INFO,
            scene.events.len(),
        ))
        .columns_of_unit_batches()
        .map_err(ser_err(&entity))?;
    rec.send_columns(entity.clone(), [times], columns)
        .map_err(log_err(&entity))
}
