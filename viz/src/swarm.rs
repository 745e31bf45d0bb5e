//! A swarm as columns: each row holds every drone's value at one time.
//!
//! Plans and flights log their drones the same way: one entity for all positions
//! (drone `i` is instance `i`), one for the separation spheres (ellipsoids under
//! an ellipsoidal separation) and one for the speeds, sent with `send_columns` so
//! a whole stretch of time is one chunk per entity.
//! Nothing here uses the stream's per-thread current time.

use crate::error::{log_err, ser_err};
use crate::style;
use crate::{Scene, TimeAxis, VizError, paths};
use rerun::{RecordingStream, TimeColumn};

fn times(axis: &TimeAxis, times_s: &[f64]) -> TimeColumn {
    TimeColumn::new_duration_secs(axis.timeline, times_s.iter().map(|t| t + axis.offset_s))
}

/// One entity's values over time: `times_s.len()` rows of `drones` entries
/// each, row after row. What differs between the entities is only their path and
/// the archetype the values fill; the chunk is sent the same way for all.
pub(crate) enum Column<'a> {
    /// Positions, drawn as points.
    Points(&'a [[f32; 3]]),
    /// Positions as the centres of the separation spheres or ellipsoids, which
    /// thus move with the drones.
    Spheres(&'a [[f32; 3]]),
    /// Speeds: one series per drone.
    Speeds(Vec<f64>),
}

/// Sends `column` at `times_s` as one chunk on its entity for `kind`.
pub(crate) fn send_column(
    rec: &RecordingStream,
    kind: &str,
    axis: &TimeAxis,
    times_s: &[f64],
    drones: usize,
    column: Column<'_>,
) -> Result<(), VizError> {
    if times_s.is_empty() || drones == 0 {
        return Ok(());
    }
    let lengths = std::iter::repeat_n(drones, times_s.len());
    let (entity, values, columns) = match column {
        Column::Points(positions) => (
            paths::drones(kind),
            positions.len(),
            rerun::Points3D::update_fields()
                .with_positions(positions.iter().copied())
                .columns(lengths)
                .map(Vec::from_iter),
        ),
        Column::Spheres(positions) => (
            paths::safety(kind),
            positions.len(),
            rerun::Ellipsoids3D::update_fields()
                .with_centers(positions.iter().copied())
                .columns(lengths)
                .map(Vec::from_iter),
        ),
        Column::Speeds(speeds_mps) => (
            paths::speeds(kind),
            speeds_mps.len(),
            rerun::Scalars::new(speeds_mps)
                .columns(lengths)
                .map(Vec::from_iter),
        ),
    };
    debug_assert_eq!(values, times_s.len() * drones);
    let columns = columns.map_err(ser_err(&entity))?;
    rec.send_columns(entity.clone(), [times(axis, times_s)], columns)
        .map_err(log_err(&entity))
}

/// A scalar time series `(t_s, value)` as one column.
pub(crate) fn send_series(
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

/// A flat line at `value` over the span of `series` (its first to its last time):
/// a limit drawn beside the series it bounds. Nothing for an empty series.
pub(crate) fn send_limit_line(
    rec: &RecordingStream,
    entity: &rerun::EntityPath,
    axis: &TimeAxis,
    series: &[(f64, f64)],
    value: f64,
) -> Result<(), VizError> {
    match (series.first(), series.last()) {
        (Some(first), Some(last)) => {
            send_series(rec, entity, axis, &[(first.0, value), (last.0, value)])
        }
        _ => Ok(()),
    }
}

/// Half sizes of the separation shape drawn around each drone: half the
/// separation's radii (`H/2, H/2, V/2` for an ellipsoid, `d/2` for a sphere).
/// Two identical shapes overlap exactly when their centres are inside the full
/// separation of each other, so touching shapes read as a breach.
pub(crate) fn separation_half_sizes(scene: &Scene) -> [f32; 3] {
    scene.separation_radii_m().map(|r| (r / 2.0) as f32)
}

/// What does not change over time for the drones `members` (scene indices, in
/// instance order): labels, colours and size of the points, the separation
/// shapes' half sizes ([`separation_half_sizes`]), and the speed series' names
/// and colours. Flown drones are drawn lighter than planned ones.
pub(crate) fn log_styles(
    rec: &RecordingStream,
    scene: &Scene,
    kind: &str,
    members: &[usize],
) -> Result<(), VizError> {
    if members.is_empty() {
        return Ok(());
    }
    let drones: Vec<&crate::Drone> = members.iter().map(|&i| &scene.drones[i]).collect();
    let colors: Vec<rerun::Color> = drones
        .iter()
        .map(|d| {
            let rgb = scene.drone_color(d);
            style::color(if kind == "flight" {
                style::flown(rgb)
            } else {
                rgb
            })
        })
        .collect();
    let labels: Vec<&str> = drones.iter().map(|d| d.id.as_str()).collect();
    let half = separation_half_sizes(scene);
    let entity = paths::drones(kind);
    rec.log_static(
        entity.clone(),
        &rerun::Points3D::update_fields()
            .with_labels(labels.iter().copied())
            .with_colors(colors.iter().copied())
            .with_radii([style::drone_radius_m(scene.voxel_size_m)]),
    )
    .map_err(log_err(&entity))?;
    let entity = paths::safety(kind);
    rec.log_static(
        entity.clone(),
        &rerun::Ellipsoids3D::update_fields()
            .with_half_sizes(std::iter::repeat_n(half, drones.len()))
            .with_colors(colors.iter().copied())
            .with_fill_mode(rerun::FillMode::MajorWireframe),
    )
    .map_err(log_err(&entity))?;
    let entity = paths::speeds(kind);
    rec.log_static(
        entity.clone(),
        &rerun::SeriesLines::new()
            .with_names(labels.iter().copied())
            .with_colors(colors),
    )
    .map_err(log_err(&entity))
}

/// Names and colours of the separation plot: the swarm's minimum separation and
/// the safety distance in red; under an ellipsoid also the scaled plot (the
/// minimum scaled separation and its limit 1 in red).
pub(crate) fn log_series_styles(
    rec: &RecordingStream,
    scene: &Scene,
    kind: &str,
) -> Result<(), VizError> {
    if scene.scaled_radii_m().is_some() {
        log_scaled_styles(rec, kind)?;
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

/// Names and colours of the scaled separation plot.
fn log_scaled_styles(rec: &RecordingStream, kind: &str) -> Result<(), VizError> {
    let entity = paths::scaled_limit(kind);
    rec.log_static(
        entity.clone(),
        &rerun::SeriesLines::new()
            .with_names(["separated (1)"])
            .with_colors([style::color(style::SAFETY_RGB)]),
    )
    .map_err(log_err(&entity))?;
    let entity = paths::min_scaled_separation(kind);
    rec.log_static(
        entity.clone(),
        &rerun::SeriesLines::new().with_names([format!("{kind} min scaled separation")]),
    )
    .map_err(log_err(&entity))
}

/// One line strip per drone in `strips` (scene index, points), in their colours.
pub(crate) fn log_paths(
    rec: &RecordingStream,
    scene: &Scene,
    kind: &str,
    strips: &[(usize, Vec<[f32; 3]>)],
) -> Result<(), VizError> {
    if strips.is_empty() {
        return Ok(());
    }
    let colors = strips.iter().map(|(i, _)| {
        let rgb = scene.drone_color(&scene.drones[*i]);
        style::color(if kind == "flight" {
            style::flown(rgb)
        } else {
            rgb
        })
    });
    let entity = paths::paths(kind);
    rec.log_static(
        entity.clone(),
        &rerun::LineStrips3D::new(strips.iter().map(|(_, s)| s.clone()))
            .with_colors(colors)
            .with_radii([style::line_radius_m(scene.voxel_size_m)]),
    )
    .map_err(log_err(&entity))
}
