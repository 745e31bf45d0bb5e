//! An independent check of sampled trajectories: separation, speed, acceleration,
//! jerk, start and goal at rest.
//!
//! Speed, acceleration and jerk are the first, second and third finite differences of
//! the samples; each is a weighted mean of the true quantity over its samples' span,
//! so none can exceed the true maximum: a motion within the limits passes.
//!
//! Samples are setpoints, so separation is checked against the setpoint separation
//! the schedule promises ([`Limits::setpoint_separation_m`]: the safety distance
//! plus twice the tracking error the vehicles are trusted to keep); with a zero
//! tracking error that is the safety distance itself.
//!
//! It reads nothing but the samples `[t_s, x_m, y_m, z_m]` and the limits, and shares no
//! code with the scheduler or the trajectory generator it checks.
//!
//! **Between samples.** Within a sample interval of length `Δt` each drone is compared
//! with the straight line between its two samples; the minimum distance of two such
//! lines is exact (relative motion is linear). A motion whose acceleration stays within
//! `a` deviates from that chord by at most `a·Δt²/8`, so the true minimum distance is at
//! least the chord minimum minus `a·Δt²/4` ([`SeparationReport::min_separation_bound_m`]),
//! a rigorous bound tighter than the speed-only `v·Δt`. One assumption: a drone whose
//! samples are identical from one sample before the interval to one after it is holding
//! still (its streamed setpoint does not change), so no margin is charged for it; this
//! lets drones parked exactly the safety distance apart pass.
//!
//! **Ellipsoids.** Under an ellipsoidal separation the schedule promises more than
//! a distance: setpoints stay outside the *bounding cylinder* of the ellipsoid grown by
//! both drones' tracking error — horizontal distance `ρ ≥ H' = H + 2e` or vertical
//! distance `|dz| ≥ V' = V + 2e` — which keeps vehicles within `e` of their
//! setpoints outside the ellipsoid itself (the grown ellipsoid alone would not: it is
//! smaller than the ellipsoid plus a ball of `2e`). The checker measures that:
//! the scaled distance `max(ρ / H', |dz| / V')`, separated when at least 1, at the
//! samples, exactly on the chords (the scaled distance of a linear relative motion
//! is convex in time), and as a bound that charges each drone's chord deviation
//! over `min(H', V')` ([`ScaledSeparation`]).
//!
//! **Scale.** Drones are hashed into cubes of the search radius (plus the motion within one
//! interval) at each sample time and only drones in neighbouring cubes are compared: about
//! `O(drones · samples)`, not `O(drones² · samples)`.

use crate::mission::Limits;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Float slack for comparisons with limits, so that exact profiles pass.
const TOLERANCE: f64 = 1e-6;

/// Per-drone figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DroneReport {
    /// Highest finite-difference speed between consecutive samples, m/s.
    pub max_speed_mps: f64,
    /// Highest second-difference acceleration over three consecutive samples, m/s².
    pub max_accel_mps2: f64,
    /// Highest third-difference jerk over four consecutive samples, m/s³.
    #[serde(default)]
    pub max_jerk_mps3: f64,
    /// Speed over the first sample interval, m/s (a drone starting at rest under the
    /// acceleration limit covers at most `a·Δt²/2` there).
    pub start_speed_mps: f64,
    /// Speed over the last sample interval, m/s (likewise for coming to rest).
    pub end_speed_mps: f64,
}

/// The closest approach found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClosestPair {
    /// One drone, by index in the samples.
    pub first: usize,
    /// The other, by index in the samples.
    pub second: usize,
    /// Time of the closest approach of the interpolated motion, seconds.
    pub time_s: f64,
}

/// What the checker found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeparationReport {
    /// Pairs farther apart than this were not examined; separations are reported as at
    /// least this when no pair came closer.
    pub search_radius_m: f64,
    /// Smallest distance between two drones at a common sample time.
    pub min_separation_samples_m: f64,
    /// Smallest distance between the linearly interpolated motions.
    pub min_separation_interpolated_m: f64,
    /// Guaranteed lower bound on the true continuous separation, assuming the
    /// acceleration limit holds between samples.
    pub min_separation_bound_m: f64,
    /// The pair behind the interpolated minimum, if any pair came within the radius.
    pub closest: Option<ClosestPair>,
    /// Per-drone figures, in sample order.
    pub drones: Vec<DroneReport>,
    /// Highest speed of any drone, m/s.
    pub max_speed_mps: f64,
    /// Highest acceleration of any drone, m/s².
    pub max_accel_mps2: f64,
    /// Highest jerk of any drone, m/s³.
    #[serde(default)]
    pub max_jerk_mps3: f64,
    /// Under an ellipsoidal separation, the scaled distances the schedule
    /// promises (see the module docs); `None` for a sphere.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scaled: Option<ScaledSeparation>,
    /// Human-readable violations; empty means every limit holds.
    pub violations: Vec<String>,
}

/// Scaled distances of the setpoints' bounding cylinders: `max(ρ / H', |dz| / V')`,
/// separated when at least 1.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScaledSeparation {
    /// The cylinder's radius, metres: the horizontal separation plus twice the
    /// tracking error.
    pub horizontal_m: f64,
    /// The cylinder's half height, metres: the vertical separation plus twice the
    /// tracking error.
    pub vertical_m: f64,
    /// Smallest scaled distance at a common sample time.
    pub min_samples: f64,
    /// Smallest scaled distance of the linearly interpolated motions.
    pub min_interpolated: f64,
    /// Guaranteed lower bound on the true continuous scaled distance.
    pub min_bound: f64,
    /// The pair behind the bound, if any pair came within the search radius.
    pub closest: Option<ClosestPair>,
}

impl SeparationReport {
    /// True when separation, speed, acceleration, jerk and rest at both ends all hold.
    pub fn ok(&self) -> bool {
        self.violations.is_empty()
    }
}

/// Why the samples could not be checked at all.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CheckError {
    /// Drones sampled a different number of times.
    #[error(
        "drone {drone} has {found} samples, drone 0 has {expected}: all must share sample times"
    )]
    SampleCount {
        /// The drone, by index in the samples.
        drone: usize,
        /// Drone 0's sample count.
        expected: usize,
        /// This drone's.
        found: usize,
    },
    /// Drones sampled at different times.
    #[error("drone {drone}, sample {index}: time {found} s differs from drone 0's {expected} s")]
    SampleTime {
        /// The drone, by index in the samples.
        drone: usize,
        /// The sample, by index.
        index: usize,
        /// Drone 0's time there, seconds.
        expected: f64,
        /// This drone's, seconds.
        found: f64,
    },
    /// The sample times do not step by one constant period (the margin between
    /// samples depends on it).
    #[error("sample times must increase at a constant period (sample {index})")]
    Period {
        /// The first sample off the period.
        index: usize,
    },
}

/// Checks sampled trajectories (all drones sampled at the same times, constant period)
/// against `limits`.
///
/// ```
/// use swarmctl::mission::Limits;
/// let limits = Limits { max_speed_mps: 1.0, max_accel_mps2: 1.0, max_jerk_mps3: 5.0, safety_distance_m: 0.5, vertical_separation_m: None, tracking_error_m: 0.0 };
/// let still = |x: f64| (0..5).map(|k| [k as f64 * 0.1, x, 0.0, 0.0]).collect::<Vec<_>>();
/// let report = swarmctl::verify::check(&[still(0.0), still(0.4)], &limits).unwrap();
/// assert!((report.min_separation_samples_m - 0.4).abs() < 1e-12);
/// assert!(!report.ok()); // 0.4 m < 0.5 m
/// ```
pub fn check(samples: &[Vec<[f64; 4]>], limits: &Limits) -> Result<SeparationReport, CheckError> {
    let times = validate_times(samples)?;
    let period_s = if times.len() > 1 {
        times[1] - times[0]
    } else {
        0.0
    };
    let drones: Vec<DroneReport> = samples.iter().map(|s| drone_report(s, period_s)).collect();
    let max_speed_mps = drones.iter().map(|d| d.max_speed_mps).fold(0.0, f64::max);
    let max_accel_mps2 = drones.iter().map(|d| d.max_accel_mps2).fold(0.0, f64::max);
    let max_jerk_mps3 = drones.iter().map(|d| d.max_jerk_mps3).fold(0.0, f64::max);
    let search_radius_m = 2.0 * limits.setpoint_separation_m();
    let margin_m = limits.max_accel_mps2 * period_s * period_s / 8.0;
    let sep = separation(
        samples,
        &times,
        search_radius_m,
        max_speed_mps,
        margin_m,
        Metric::Euclid,
    );
    let scaled = limits.is_ellipsoid().then(|| {
        let grown = limits.setpoint_separation();
        let (h, v) = (grown.horizontal_m, grown.vertical_m);
        let metric = Metric::Cylinder { h, v };
        let radius_m = 2.0 * h.max(v);
        let s = separation(samples, &times, radius_m, max_speed_mps, margin_m, metric);
        ScaledSeparation {
            horizontal_m: h,
            vertical_m: v,
            min_samples: s.samples_m,
            min_interpolated: s.interpolated_m,
            min_bound: s.bound_m,
            closest: s.closest,
        }
    });
    let mut report = SeparationReport {
        search_radius_m,
        min_separation_samples_m: sep.samples_m,
        min_separation_interpolated_m: sep.interpolated_m,
        min_separation_bound_m: sep.bound_m,
        closest: sep.closest,
        drones,
        max_speed_mps,
        max_accel_mps2,
        max_jerk_mps3,
        scaled,
        violations: Vec::new(),
    };
    report.violations = violations(&report, limits, period_s);
    Ok(report)
}

fn validate_times(samples: &[Vec<[f64; 4]>]) -> Result<Vec<f64>, CheckError> {
    let Some(first) = samples.first() else {
        return Ok(Vec::new());
    };
    let times: Vec<f64> = first.iter().map(|s| s[0]).collect();
    if times.len() > 1 {
        let period = times[1] - times[0];
        for (index, w) in times.windows(2).enumerate() {
            if period.is_nan()
                || period <= 0.0
                || ((w[1] - w[0]) - period).abs() > 1e-6 * period.max(1.0)
            {
                return Err(CheckError::Period { index: index + 1 });
            }
        }
    }
    for (drone, s) in samples.iter().enumerate() {
        if s.len() != times.len() {
            return Err(CheckError::SampleCount {
                drone,
                expected: times.len(),
                found: s.len(),
            });
        }
        for (index, (sample, &t)) in s.iter().zip(&times).enumerate() {
            if (sample[0] - t).abs() > 1e-9 {
                return Err(CheckError::SampleTime {
                    drone,
                    index,
                    expected: t,
                    found: sample[0],
                });
            }
        }
    }
    Ok(times)
}

fn dist(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    ((a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2) + (a[3] - b[3]).powi(2)).sqrt()
}

fn drone_report(s: &[[f64; 4]], period_s: f64) -> DroneReport {
    if s.len() < 2 || period_s <= 0.0 {
        return DroneReport {
            max_speed_mps: 0.0,
            max_accel_mps2: 0.0,
            max_jerk_mps3: 0.0,
            start_speed_mps: 0.0,
            end_speed_mps: 0.0,
        };
    }
    let speed = |k: usize| dist(&s[k], &s[k + 1]) / period_s;
    let max_speed_mps = (0..s.len() - 1).map(speed).fold(0.0, f64::max);
    let max_accel_mps2 = s
        .windows(3)
        .map(|w| {
            let a: [f64; 3] =
                std::array::from_fn(|i| w[2][i + 1] - 2.0 * w[1][i + 1] + w[0][i + 1]);
            (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt() / (period_s * period_s)
        })
        .fold(0.0, f64::max);
    let max_jerk_mps3 = s
        .windows(4)
        .map(|w| {
            let j: [f64; 3] = std::array::from_fn(|i| {
                w[3][i + 1] - 3.0 * w[2][i + 1] + 3.0 * w[1][i + 1] - w[0][i + 1]
            });
            (j[0] * j[0] + j[1] * j[1] + j[2] * j[2]).sqrt() / period_s.powi(3)
        })
        .fold(0.0, f64::max);
    DroneReport {
        max_speed_mps,
        max_accel_mps2,
        max_jerk_mps3,
        start_speed_mps: speed(0),
        end_speed_mps: speed(s.len() - 2),
    }
}

/// How two drones' relative position is measured.
#[derive(Debug, Clone, Copy)]
enum Metric {
    /// Distance, metres.
    Euclid,
    /// `max(ρ / h, |dz| / v)`: at least 1 outside the cylinder of radius `h` and
    /// half height `v`.
    Cylinder { h: f64, v: f64 },
}

impl Metric {
    fn of(self, r: [f64; 3]) -> f64 {
        match self {
            Metric::Euclid => (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt(),
            Metric::Cylinder { h, v } => {
                ((r[0] * r[0] + r[1] * r[1]).sqrt() / h).max(r[2].abs() / v)
            }
        }
    }

    /// The least value on the chord `r0 + u·dr`, `u` in `[0, 1]`, and where. Both
    /// metrics are convex along a line, so a golden-section search converges on the
    /// minimum of the cylinder's; the Euclidean one is solved in closed form.
    fn min_on_chord(self, r0: [f64; 3], dr: [f64; 3]) -> (f64, f64) {
        let at = |u: f64| -> [f64; 3] { std::array::from_fn(|c| r0[c] + u * dr[c]) };
        match self {
            Metric::Euclid => {
                let dd = dr[0] * dr[0] + dr[1] * dr[1] + dr[2] * dr[2];
                let u = if dd > 0.0 {
                    (-(r0[0] * dr[0] + r0[1] * dr[1] + r0[2] * dr[2]) / dd).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (self.of(at(u)), u)
            }
            Metric::Cylinder { .. } => {
                const INVERSE_PHI: f64 = 0.618_033_988_749_894_8;
                let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
                // 60 golden-section steps shrink the bracket below 1e-12.
                for _ in 0..60 {
                    let a = hi - INVERSE_PHI * (hi - lo);
                    let b = lo + INVERSE_PHI * (hi - lo);
                    if self.of(at(a)) <= self.of(at(b)) {
                        hi = b;
                    } else {
                        lo = a;
                    }
                }
                let u = 0.5 * (lo + hi);
                [
                    (self.of(at(0.0)), 0.0),
                    (self.of(at(1.0)), 1.0),
                    (self.of(at(u)), u),
                ]
                .into_iter()
                .fold(
                    (f64::INFINITY, 0.0),
                    |best, x| if x.0 < best.0 { x } else { best },
                )
            }
        }
    }

    /// The least value of two drones at least `radius_m` apart: what pairs the
    /// search does not examine are reported as.
    fn floor(self, radius_m: f64) -> f64 {
        match self {
            Metric::Euclid => radius_m,
            // ρ² + dz² ≥ r² puts ρ or |dz| at r/√2 or more.
            Metric::Cylinder { h, v } => radius_m / (std::f64::consts::SQRT_2 * h.max(v)),
        }
    }

    /// How much the value may drop when each drone strays `deviation_m` in all from
    /// its chord.
    fn slack(self, deviation_m: f64) -> f64 {
        match self {
            Metric::Euclid => deviation_m,
            Metric::Cylinder { h, v } => deviation_m / h.min(v),
        }
    }
}

struct Separation {
    metric: Metric,
    samples_m: f64,
    interpolated_m: f64,
    bound_m: f64,
    /// Largest deviation of one drone from its chord within an interval.
    margin_m: f64,
    closest: Option<ClosestPair>,
}

/// Closest approach over all pairs and sample intervals, by spatial hashing.
fn separation(
    samples: &[Vec<[f64; 4]>],
    times: &[f64],
    radius_m: f64,
    speed_mps: f64,
    margin_m: f64,
    metric: Metric,
) -> Separation {
    let mut out = Separation {
        metric,
        samples_m: metric.floor(radius_m),
        interpolated_m: metric.floor(radius_m),
        bound_m: metric.floor(radius_m),
        margin_m,
        closest: None,
    };
    if samples.len() < 2 || times.is_empty() {
        return out;
    }
    let period_s = if times.len() > 1 {
        times[1] - times[0]
    } else {
        0.0
    };
    // Two drones that come within `radius_m` during an interval start it within this.
    let cell_m = (radius_m + 2.0 * speed_mps * period_s).max(1e-9);
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for k in 0..times.len() {
        for cell in grid.values_mut() {
            cell.clear();
        }
        for (i, s) in samples.iter().enumerate() {
            grid.entry(key(&s[k], cell_m)).or_default().push(i as u32);
        }
        for (i, s) in samples.iter().enumerate() {
            let c = key(&s[k], cell_m);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let Some(others) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                            continue;
                        };
                        for &j in others {
                            let j = j as usize;
                            if j <= i {
                                continue;
                            }
                            pair(samples, i, j, k, &mut out);
                        }
                    }
                }
            }
        }
        grid.retain(|_, v| !v.is_empty());
    }
    out
}

fn key(s: &[f64; 4], cell_m: f64) -> [i64; 3] {
    [
        (s[1] / cell_m).floor() as i64,
        (s[2] / cell_m).floor() as i64,
        (s[3] / cell_m).floor() as i64,
    ]
}

/// Distance of drones `i` and `j` at sample `k` and over the interval `[k, k + 1]`.
fn pair(samples: &[Vec<[f64; 4]>], i: usize, j: usize, k: usize, out: &mut Separation) {
    let (a0, b0) = (&samples[i][k], &samples[j][k]);
    let r0: [f64; 3] = std::array::from_fn(|c| a0[c + 1] - b0[c + 1]);
    let d0 = out.metric.of(r0);
    if d0 < out.samples_m {
        out.samples_m = d0;
    }
    let (mut best, mut best_t) = (d0, a0[0]);
    if let (Some(a1), Some(b1)) = (samples[i].get(k + 1), samples[j].get(k + 1)) {
        // Relative position r(u) = r0 + u (r1 - r0), u in [0, 1].
        let r1: [f64; 3] = std::array::from_fn(|c| a1[c + 1] - b1[c + 1]);
        let dr: [f64; 3] = std::array::from_fn(|c| r1[c] - r0[c]);
        let (d, u) = out.metric.min_on_chord(r0, dr);
        if d < best {
            best = d;
            best_t = a0[0] + u * (a1[0] - a0[0]);
        }
    }
    out.interpolated_m = out.interpolated_m.min(best);
    let deviation_m = margin(&samples[i], k, out.margin_m) + margin(&samples[j], k, out.margin_m);
    let bound = best - out.metric.slack(deviation_m);
    if bound < out.bound_m {
        out.bound_m = bound;
        out.closest = Some(ClosestPair {
            first: i,
            second: j,
            time_s: best_t,
        });
    }
}

/// How far a drone may stray from its chord over `[k, k + 1]`: nothing if it holds still
/// from sample `k − 1` to `k + 2`, else `a·Δt²/8`.
fn margin(s: &[[f64; 4]], k: usize, margin_m: f64) -> f64 {
    if k + 1 >= s.len() {
        return 0.0; // no interval after the last sample
    }
    let window = &s[k.saturating_sub(1)..(k + 3).min(s.len())];
    let still = window.iter().all(|p| p[1..] == window[0][1..]);
    if still { 0.0 } else { margin_m }
}

/// Which pair came closest and when, for a violation message.
fn closest_text(closest: Option<&ClosestPair>) -> String {
    closest
        .map(|c| {
            format!(
                " (drones #{} and #{} near t = {:.3} s)",
                c.first, c.second, c.time_s
            )
        })
        .unwrap_or_default()
}

fn violations(report: &SeparationReport, limits: &Limits, period_s: f64) -> Vec<String> {
    let mut v = Vec::new();
    let separation_m = limits.setpoint_separation_m();
    if let Some(scaled) = &report.scaled {
        if scaled.min_bound < 1.0 - TOLERANCE {
            let who = closest_text(scaled.closest.as_ref());
            v.push(format!(
                "scaled separation may drop to {:.4}, below 1: setpoints inside each other's cylinder of radius {:.3} m and half height {:.3} m (the separation ellipsoid {} × {} m grown by twice the tracking error {} m){who}",
                scaled.min_bound,
                scaled.horizontal_m,
                scaled.vertical_m,
                limits.safety_distance_m,
                limits.vertical_separation_m.unwrap_or(limits.safety_distance_m),
                limits.tracking_error_m
            ));
        }
    } else if report.min_separation_bound_m < separation_m - TOLERANCE {
        let who = closest_text(report.closest.as_ref());
        v.push(format!(
            "separation may drop to {:.4} m, below the setpoint separation {} m (safety distance {} m plus twice the tracking error {} m){who}",
            report.min_separation_bound_m,
            separation_m,
            limits.safety_distance_m,
            limits.tracking_error_m
        ));
    }
    let rest_speed = 0.5 * limits.max_accel_mps2 * period_s + TOLERANCE;
    for (i, d) in report.drones.iter().enumerate() {
        if d.max_speed_mps > limits.max_speed_mps + TOLERANCE {
            v.push(format!(
                "drone #{i} reaches {:.4} m/s, above the limit {} m/s",
                d.max_speed_mps, limits.max_speed_mps
            ));
        }
        if d.max_accel_mps2 > limits.max_accel_mps2 + TOLERANCE {
            v.push(format!(
                "drone #{i} accelerates at {:.4} m/s², above the limit {} m/s²",
                d.max_accel_mps2, limits.max_accel_mps2
            ));
        }
        // Third differences of positions in metres amplify rounding by 8/Δt³: allow it.
        if d.max_jerk_mps3 > limits.max_jerk_mps3 * (1.0 + 1e-6) + 1e-9 / period_s.powi(3) {
            v.push(format!(
                "drone #{i} changes its acceleration at {:.4} m/s³, above the limit {} m/s³",
                d.max_jerk_mps3, limits.max_jerk_mps3
            ));
        }
        if d.start_speed_mps > rest_speed {
            v.push(format!(
                "drone #{i} does not start at rest ({:.4} m/s)",
                d.start_speed_mps
            ));
        }
        if d.end_speed_mps > rest_speed {
            v.push(format!(
                "drone #{i} does not end at rest ({:.4} m/s)",
                d.end_speed_mps
            ));
        }
    }
    v
}
