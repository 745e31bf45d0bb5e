//! Logging a [`Scene`]: the world, the plan's static geometry and its schedule.
//!
//! The schedule is known in full before logging starts, so it goes in as columns
//! (`send_columns`): every drone's trajectory resampled onto one shared time grid,
//! one chunk per entity and timeline, and no reliance on the stream's per-thread
//! current time.

use crate::error::{log_err, ser_err};
use crate::style::{self, f32x3};
use crate::swarm::Column;
use crate::{PlanEvent, Scene, TimeAxis, VizError, metrics, paths, swarm};
use rerun::{RecordingStream, TimeColumn};

/// Grid period used when the drones' trajectories are not sampled alike, seconds.
const FALLBACK_PERIOD_S: f64 = 0.05;
/// Never resample a plan onto more rows than this (a bound on memory, not a limit in practice).
const MAX_ROWS: usize = 200_000;

/// Writes (or streams) a recording of `scene`: static geometry once, the
/// schedule on every axis in `axes`; returns once everything is flushed.
pub fn write_scene(scene: &Scene, sink: &crate::Sink, axes: &[TimeAxis]) -> Result<(), VizError> {
    let timeline = axes.first().map_or(crate::PLAN_TIMELINE, |a| a.timeline);
    let rec = crate::sink::open(scene, sink, timeline)?;
    log_scene(&rec, scene, axes)?;
    rec.flush_blocking()
        .map_err(|e| VizError::Flush(e.to_string()))
}

/// The plan's drones on one time grid, ready to be logged on any axis.
#[derive(Debug, Clone, Default)]
pub(crate) struct PlanRows {
    /// Number of drones per row (the scene's drones that have a trajectory).
    drones: usize,
    times_s: Vec<f64>,
    /// `times_s.len()` rows of `drones` positions.
    positions: Vec<[f32; 3]>,
    /// Same layout: speed since the previous row.
    speeds_mps: Vec<f64>,
    /// The swarm's minimum separation at each row.
    separation: Vec<(f64, f64)>,
    /// The swarm's minimum scaled separation at each row, under an ellipsoid.
    scaled: Vec<(f64, f64)>,
    safety_distance_m: f64,
    events: Vec<PlanEvent>,
}

impl PlanRows {
    /// Resamples every drone's trajectory onto one grid: the trajectories' own
    /// sample times when they share them (a compiled plan does), else a fine
    /// uniform grid. Drones hold their last position once their trajectory ends.
    pub(crate) fn new(scene: &Scene) -> Self {
        let tracks: Vec<&[[f64; 4]]> = scene
            .drones
            .iter()
            .map(|d| d.trajectory.as_slice())
            .filter(|t| !t.is_empty())
            .collect();
        let times_s = grid(&tracks);
        let n = tracks.len();
        let mut rows = Self {
            drones: n,
            positions: Vec::with_capacity(times_s.len() * n),
            speeds_mps: Vec::with_capacity(times_s.len() * n),
            separation: Vec::with_capacity(times_s.len()),
            scaled: Vec::new(),
            safety_distance_m: scene.safety_distance_m,
            events: scene.events.clone(),
            times_s: Vec::new(),
        };
        let mut previous: Vec<[f64; 3]> = Vec::new();
        let mut current: Vec<[f64; 3]> = Vec::with_capacity(n);
        let mut previous_t_s = f64::NAN;
        let mut pairwise = metrics::Pairwise::default();
        for &t_s in &times_s {
            current.clear();
            current.extend(tracks.iter().filter_map(|t| metrics::position_at(t, t_s)));
            for (i, p) in current.iter().enumerate() {
                let speed = match previous.get(i) {
                    Some(q) if t_s > previous_t_s => distance(p, q) / (t_s - previous_t_s),
                    _ => 0.0,
                };
                rows.speeds_mps.push(speed);
                rows.positions.push(f32x3(*p));
            }
            if let Some(d) = pairwise.min_m(current.iter().copied()) {
                rows.separation.push((t_s, d));
            }
            if let Some(radii) = scene.scaled_radii_m()
                && let Some(scaled) = pairwise.min_scaled(current.iter().copied(), radii)
            {
                rows.scaled.push((t_s, scaled));
            }
            std::mem::swap(&mut previous, &mut current);
            previous_t_s = t_s;
        }
        rows.times_s = times_s;
        rows
    }

    /// Scene indices of the drones in the rows, in instance order.
    pub(crate) fn members(scene: &Scene) -> Vec<usize> {
        (0..scene.drones.len())
            .filter(|&i| !scene.drones[i].trajectory.is_empty())
            .collect()
    }
}

/// The sample times shared by every track if they share them (each a prefix of
/// the longest), else a uniform grid over all of them.
fn grid(tracks: &[&[[f64; 4]]]) -> Vec<f64> {
    let Some(longest) = tracks.iter().max_by_key(|t| t.len()) else {
        return Vec::new();
    };
    let shared = tracks
        .iter()
        .all(|t| t.iter().zip(longest.iter()).all(|(a, b)| a[0] == b[0]));
    if shared {
        return longest.iter().map(|s| s[0]).collect();
    }
    let t0 = tracks.iter().map(|t| t[0][0]).fold(f64::INFINITY, f64::min);
    let t1 = tracks
        .iter()
        .map(|t| t[t.len() - 1][0])
        .fold(f64::NEG_INFINITY, f64::max);
    let period_s = tracks
        .iter()
        .filter_map(|t| t.get(1).map(|s| s[0] - t[0][0]))
        .filter(|dt| *dt > 0.0)
        .fold(FALLBACK_PERIOD_S, f64::min)
        .max((t1 - t0) / MAX_ROWS as f64);
    let steps = ((t1 - t0) / period_s).ceil() as usize;
    (0..=steps)
        .map(|k| (t0 + k as f64 * period_s).min(t1))
        .collect()
}

fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Logs `scene` into `rec`: static geometry and styles once, the schedule on
/// every axis in `axes`. Returns the plan's rows so they can be logged on
/// another axis later (a live flight learns when the plan starts only then).
pub(crate) fn log_scene(
    rec: &RecordingStream,
    scene: &Scene,
    axes: &[TimeAxis],
) -> Result<PlanRows, VizError> {
    crate::world::log_world(rec, scene)?;
    log_markers(rec, scene)?;
    let members = PlanRows::members(scene);
    swarm::log_styles(rec, scene, "plan", &members)?;
    swarm::log_series_styles(rec, scene, "plan")?;
    let rows = PlanRows::new(scene);
    for axis in axes {
        log_plan_axis(rec, &rows, axis)?;
    }
    Ok(rows)
}

/// The schedule on one axis: drones, separation shapes, speeds, separation (and
/// scaled separation under an ellipsoid), waits.
pub(crate) fn log_plan_axis(
    rec: &RecordingStream,
    rows: &PlanRows,
    axis: &TimeAxis,
) -> Result<(), VizError> {
    let n = rows.drones;
    let times_s = &rows.times_s;
    let positions = &rows.positions;
    swarm::send_column(rec, "plan", axis, times_s, n, Column::Points(positions))?;
    swarm::send_column(rec, "plan", axis, times_s, n, Column::Spheres(positions))?;
    let speeds = Column::Speeds(rows.speeds_mps.clone());
    swarm::send_column(rec, "plan", axis, times_s, n, speeds)?;
    swarm::send_series(rec, &paths::min_separation("plan"), axis, &rows.separation)?;
    let (separation, distance_m) = (&rows.separation, rows.safety_distance_m);
    swarm::send_limit_line(
        rec,
        &paths::safety_distance("plan"),
        axis,
        separation,
        distance_m,
    )?;
    swarm::send_series(
        rec,
        &paths::min_scaled_separation("plan"),
        axis,
        &rows.scaled,
    )?;
    swarm::send_limit_line(rec, &paths::scaled_limit("plan"), axis, &rows.scaled, 1.0)?;
    log_events(rec, &rows.events, axis)
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
    let strips: Vec<(usize, Vec<[f32; 3]>)> = scene
        .drones
        .iter()
        .enumerate()
        .filter(|(_, d)| !d.path_m.is_empty())
        .map(|(i, d)| (i, d.path_m.iter().map(|p| f32x3(*p)).collect()))
        .collect();
    swarm::log_paths(rec, scene, "plan", &strips)
}

/// TPG waits and other scheduled events as text, in time order.
fn log_events(
    rec: &RecordingStream,
    events: &[PlanEvent],
    axis: &TimeAxis,
) -> Result<(), VizError> {
    if events.is_empty() {
        return Ok(());
    }
    let entity = paths::events("plan");
    let times =
        TimeColumn::new_duration_secs(axis.timeline, events.iter().map(|e| e.t_s + axis.offset_s));
    let texts: Vec<String> = events
        .iter()
        .map(|e| match &e.drone {
            Some(d) => format!("{d}: {}", e.text),
            None => e.text.clone(),
        })
        .collect();
    let columns = rerun::TextLog::update_fields()
        .with_many_text(texts)
        .with_many_level(std::iter::repeat_n(rerun::TextLogLevel::INFO, events.len()))
        .columns_of_unit_batches()
        .map_err(ser_err(&entity))?;
    rec.send_columns(entity.clone(), [times], columns)
        .map_err(log_err(&entity))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Drone;

    fn drone(id: &str, trajectory: Vec<[f64; 4]>) -> Drone {
        Drone {
            id: id.into(),
            trajectory,
            ..Drone::default()
        }
    }

    #[test]
    fn shared_sample_times_become_the_grid_and_short_tracks_hold() {
        let scene = Scene {
            drones: vec![
                drone("a", vec![[0.0, 0.0, 0.0, 0.0], [0.5, 1.0, 0.0, 0.0]]),
                drone("b", vec![[0.0, 0.0, 3.0, 0.0]]),
                drone("no-plan", vec![]),
            ],
            ..Scene::default()
        };
        let rows = PlanRows::new(&scene);
        assert_eq!(PlanRows::members(&scene), vec![0, 1]);
        assert_eq!(rows.drones, 2);
        assert_eq!(rows.times_s, vec![0.0, 0.5]);
        assert_eq!(
            rows.positions,
            vec![
                [0.0, 0.0, 0.0],
                [0.0, 3.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 3.0, 0.0]
            ]
        );
        assert_eq!(rows.speeds_mps, vec![0.0, 0.0, 2.0, 0.0]);
        assert_eq!(rows.separation.len(), 2);
        assert!((rows.separation[1].1 - 10f64.sqrt()).abs() < 1e-6);
    }

    #[test]
    fn an_ellipsoid_adds_the_scaled_separation_and_a_sphere_does_not() {
        // One drone 0.5 m above another: twice H beside, two thirds of V below.
        let mut scene = Scene {
            safety_distance_m: 0.25,
            drones: vec![
                drone("low", vec![[0.0, 0.0, 0.0, 1.0]]),
                drone("high", vec![[0.0, 0.0, 0.0, 1.5]]),
            ],
            ..Scene::default()
        };
        assert!(PlanRows::new(&scene).scaled.is_empty());
        scene.vertical_separation_m = Some(0.75);
        let rows = PlanRows::new(&scene);
        assert_eq!(rows.scaled.len(), 1);
        assert!(
            (rows.scaled[0].1 - 2.0 / 3.0).abs() < 1e-6,
            "{:?}",
            rows.scaled
        );
        assert_eq!(
            swarm::separation_half_sizes(&scene),
            [0.125, 0.125, 0.375],
            "half the ellipsoid's radii, so touching shapes mean a breach"
        );
    }

    #[test]
    fn different_sample_times_are_resampled() {
        let tracks: [&[[f64; 4]]; 2] = [
            &[[0.0, 0.0, 0.0, 0.0], [0.1, 0.0, 0.0, 0.0]],
            &[[0.05, 0.0, 0.0, 0.0], [0.2, 0.0, 0.0, 0.0]],
        ];
        let times = grid(&tracks);
        assert_eq!(times.len(), 5);
        assert_eq!(times[0], 0.0);
        assert_eq!(times[4], 0.2);
    }
}
