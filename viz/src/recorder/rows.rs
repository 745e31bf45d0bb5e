//! Samples into rows: every drone's newest position on a fixed time grid, and
//! on a coarser grid the speeds, separation shapes and the swarm's minimum
//! separation (and scaled separation, under an ellipsoid). Pure arithmetic on the recorder thread, no rerun: the worker
//! sends what accumulates here at each flush.

use super::options::RecorderOptions;
use super::samples::FlightSample;
use crate::style::f32x3;
use crate::{Scene, metrics};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// Per-drone state on the recorder thread.
#[derive(Default)]
pub(super) struct Track {
    /// Newest sample `(t_s, position)`.
    latest: Option<(f64, [f64; 3])>,
    /// The sample the last speed was measured from.
    anchor: Option<(f64, [f64; 3])>,
    speed_mps: f64,
    /// The flown path so far, thinned to steps of `path_step_m`.
    pub(super) path: Vec<[f32; 3]>,
}

/// The rows built so far and what is needed to build the next ones.
pub(super) struct FlightRows {
    /// Spacing of position rows, flight seconds (at least 1 ms).
    row_period_s: f64,
    /// See [`RecorderOptions::path_step_m`].
    path_step_m: f64,
    /// See [`RecorderOptions::first_row_wait_s`].
    first_row_wait_s: f64,
    /// Where each drone is shown until it reports: its start.
    starts_m: Vec<[f64; 3]>,
    /// One per scene drone, in instance order.
    pub(super) tracks: Vec<Track>,
    /// Drones that have reported at least once.
    reporting: usize,
    /// Index of the next row to close (its time is `index × row_period_s`), once
    /// the first sample has arrived.
    next_row: Option<u64>,
    /// Flight time of the first sample.
    pub(super) first_t_s: Option<f64>,
    /// Flight time of the newest sample.
    pub(super) last_t_s: f64,
    rows_since_series: usize,
    rows_per_series: usize,
    /// Times of the rows not yet sent.
    pub(super) row_times_s: Vec<f64>,
    /// Every drone's position per unsent row, row after row.
    pub(super) row_positions: Vec<[f32; 3]>,
    /// Times of the series rows not yet sent.
    pub(super) series_times_s: Vec<f64>,
    /// Safety-sphere centres at the series times: every drone per row.
    pub(super) series_positions: Vec<[f32; 3]>,
    /// Every drone's speed per series row, m/s.
    pub(super) series_speeds: Vec<f64>,
    /// The swarm's minimum separation `(t_s, metres)` per series row.
    pub(super) separation: Vec<(f64, f64)>,
    /// The ellipsoid's radii, when drones are separated by one (see [`Scene::scaled_radii_m`]).
    scaled_radii_m: Option<[f64; 3]>,
    /// The swarm's minimum scaled separation `(t_s, scaled)` per series row, under an ellipsoid.
    pub(super) scaled: Vec<(f64, f64)>,
    pairwise: metrics::Pairwise,
    /// Samples dropped (shared with the handles).
    dropped: Arc<AtomicU64>,
    /// Samples placed.
    pub(super) logged: u64,
    /// Position rows closed.
    pub(super) rows_logged: u64,
}

impl FlightRows {
    /// No rows yet, for the drones of `scene`; unknown samples are counted in `dropped`.
    pub(super) fn new(scene: &Scene, options: &RecorderOptions, dropped: Arc<AtomicU64>) -> Self {
        let row_period_s = options.row_period_s.max(1e-3);
        Self {
            row_period_s,
            path_step_m: options.path_step_m,
            first_row_wait_s: options.first_row_wait_s,
            starts_m: scene.drones.iter().map(|d| d.start_m).collect(),
            tracks: scene.drones.iter().map(|_| Track::default()).collect(),
            reporting: 0,
            next_row: None,
            first_t_s: None,
            last_t_s: 0.0,
            rows_since_series: 0,
            rows_per_series: ((options.series_period_s / row_period_s).round() as usize).max(1),
            row_times_s: Vec::new(),
            row_positions: Vec::new(),
            series_times_s: Vec::new(),
            series_positions: Vec::new(),
            series_speeds: Vec::new(),
            separation: Vec::new(),
            scaled_radii_m: scene.scaled_radii_m(),
            scaled: Vec::new(),
            pairwise: metrics::Pairwise::default(),
            dropped,
            logged: 0,
            rows_logged: 0,
        }
    }

    /// Places one sample, closing the rows before it first.
    pub(super) fn sample(&mut self, s: FlightSample) {
        if s.drone >= self.tracks.len() || !s.t_s.is_finite() {
            self.dropped.fetch_add(1, Ordering::Relaxed);
            return;
        }
        // Rows up to this sample's time are complete: telemetry arrives in time order
        // up to the executor's tick, which is shorter than a row.
        if self.next_row.is_none() {
            self.next_row = Some((s.t_s / self.row_period_s).ceil().max(0.0) as u64);
            self.first_t_s = Some(s.t_s);
        }
        self.close_rows(s.t_s);
        let step_m = self.path_step_m;
        let track = &mut self.tracks[s.drone];
        if track.latest.is_none() {
            self.reporting += 1;
            track.anchor = Some((s.t_s, s.position_m));
        }
        track.latest = Some((s.t_s, s.position_m));
        let p = f32x3(s.position_m);
        let moved = track.path.last().is_none_or(|q| {
            let d2: f32 = (0..3).map(|i| (p[i] - q[i]).powi(2)).sum();
            f64::from(d2.sqrt()) >= step_m
        });
        if moved {
            track.path.push(p);
        }
        self.logged += 1;
        self.last_t_s = self.last_t_s.max(s.t_s);
    }

    /// Closes every row whose time is before `t_s` (all of them for infinity).
    pub(super) fn close_rows(&mut self, t_s: f64) {
        let (Some(first_t_s), Some(mut next)) = (self.first_t_s, self.next_row) else {
            return;
        };
        let period = self.row_period_s;
        // At the end, one more row so that the last samples are shown.
        let end = if t_s.is_finite() {
            t_s
        } else {
            self.last_t_s + period
        };
        // Until every drone has reported (or a while has passed), hold rows back.
        let waiting = self.reporting < self.tracks.len()
            && t_s.is_finite()
            && t_s - first_t_s < self.first_row_wait_s;
        if waiting {
            return;
        }
        while (next as f64) * period < end {
            self.close_row(next as f64 * period);
            next += 1;
        }
        self.next_row = Some(next);
    }

    fn close_row(&mut self, t_s: f64) {
        self.row_times_s.push(t_s);
        self.rows_logged += 1;
        let row_start = self.row_positions.len();
        for (track, start_m) in self.tracks.iter().zip(&self.starts_m) {
            let p = track.latest.map_or(*start_m, |(_, p)| p);
            self.row_positions.push(f32x3(p));
        }
        self.rows_since_series += 1;
        if self.rows_since_series < self.rows_per_series {
            return;
        }
        self.rows_since_series = 0;
        self.series_times_s.push(t_s);
        self.series_positions
            .extend_from_slice(&self.row_positions[row_start..]);
        for track in &mut self.tracks {
            if let (Some((t1, p1)), Some((t0, p0))) = (track.latest, track.anchor)
                && t1 > t0
            {
                let d2: f64 = (0..3).map(|i| (p1[i] - p0[i]).powi(2)).sum();
                track.speed_mps = d2.sqrt() / (t1 - t0);
                track.anchor = track.latest;
            }
            self.series_speeds.push(track.speed_mps);
        }
        let reported = || self.tracks.iter().filter_map(|t| t.latest.map(|(_, p)| p));
        if let Some(d) = self.pairwise.min_m(reported()) {
            self.separation.push((t_s, d));
        }
        if let Some(radii) = self.scaled_radii_m
            && let Some(scaled) = self.pairwise.min_scaled(reported(), radii)
        {
            self.scaled.push((t_s, scaled));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Drone;

    fn scene(n: usize) -> Scene {
        Scene {
            name: "test".into(),
            voxel_size_m: 1.0,
            safety_distance_m: 0.25,
            drones: (0..n)
                .map(|i| Drone {
                    id: format!("d{i}"),
                    start_m: [i as f64, 0.0, 0.0],
                    ..Drone::default()
                })
                .collect(),
            ..Scene::default()
        }
    }

    fn rows(n: usize) -> FlightRows {
        let options = RecorderOptions {
            row_period_s: 0.1,
            series_period_s: 0.2,
            ..RecorderOptions::default()
        };
        FlightRows::new(&scene(n), &options, Arc::new(AtomicU64::new(0)))
    }

    fn sample(drone: usize, t_s: f64, x: f64) -> FlightSample {
        FlightSample {
            drone,
            t_s,
            position_m: [x, 0.0, 0.0],
        }
    }

    #[test]
    fn rows_hold_every_drones_newest_position() {
        let mut w = rows(2);
        w.sample(sample(0, 0.01, 0.0));
        w.sample(sample(1, 0.02, 5.0));
        w.sample(sample(0, 0.11, 1.0));
        w.sample(sample(1, 0.12, 5.0));
        w.sample(sample(0, 0.21, 2.0));
        w.sample(sample(1, 0.22, 5.0));
        // Rows at 0.1 and 0.2 closed; the one at 0.3 waits for later samples.
        assert_eq!(w.row_times_s.len(), 2);
        assert!((w.row_times_s[0] - 0.1).abs() < 1e-12);
        assert_eq!(w.row_positions[..2], [[0.0, 0.0, 0.0], [5.0, 0.0, 0.0]]);
        assert_eq!(w.row_positions[2..], [[1.0, 0.0, 0.0], [5.0, 0.0, 0.0]]);
        // One series row (every second row): drone 0 moved 1 m in 0.1 s.
        assert_eq!(w.series_times_s.len(), 1);
        assert!((w.series_speeds[0] - 10.0).abs() < 1e-9);
        assert_eq!(w.series_speeds[1], 0.0);
        assert_eq!(w.separation.len(), 1);
        assert!((w.separation[0].1 - 4.0).abs() < 1e-12);
        w.close_rows(f64::INFINITY);
        assert_eq!(*w.row_positions.last().expect("rows"), [5.0, 0.0, 0.0]);
        assert_eq!(w.logged, 6);
    }

    #[test]
    fn an_ellipsoid_adds_the_scaled_separation_per_series_row() {
        let scene = Scene {
            vertical_separation_m: Some(0.75),
            ..scene(2)
        };
        let options = RecorderOptions {
            row_period_s: 0.1,
            series_period_s: 0.1,
            ..RecorderOptions::default()
        };
        let mut w = FlightRows::new(&scene, &options, Arc::new(AtomicU64::new(0)));
        w.sample(sample(0, 0.01, 0.0));
        w.sample(FlightSample {
            drone: 1,
            t_s: 0.02,
            position_m: [0.0, 0.0, 1.5],
        });
        w.close_rows(f64::INFINITY);
        assert!(!w.scaled.is_empty());
        // 1.5 m straight above: twice V.
        assert!((w.scaled[0].1 - 2.0).abs() < 1e-6, "{:?}", w.scaled);
        assert!((w.separation[0].1 - 1.5).abs() < 1e-6);
    }

    #[test]
    fn rows_wait_for_every_drone_then_show_the_silent_one_at_its_start() {
        let mut w = rows(2);
        w.sample(sample(0, 0.0, 0.0));
        w.sample(sample(0, 0.5, 0.0));
        assert!(w.row_times_s.is_empty());
        w.sample(sample(0, 1.05, 0.0));
        assert_eq!(w.row_times_s.len(), 11);
        assert_eq!(w.row_positions[1], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn unknown_drones_are_dropped_and_counted() {
        let mut w = rows(1);
        w.sample(sample(3, 0.0, 0.0));
        assert_eq!(w.dropped.load(Ordering::Relaxed), 1);
        assert_eq!(w.logged, 0);
    }
}
