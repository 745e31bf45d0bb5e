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
//! **Scale.** Drones are sorted into cubes of the search radius (plus the motion within one
//! interval) at each sample time and only drones in neighbouring cubes are compared: about
//! `O(drones · log drones · samples)`, not `O(drones² · samples)`.

mod differences;
mod metric;
mod report;
mod samples;
mod separation;
mod violations;

pub use report::{ClosestPair, DroneReport, ScaledSeparation, SeparationReport};
pub use samples::CheckError;

use crate::mission::Limits;
use differences::drone_report;
use metric::Metric;
use samples::validate_times;
use separation::separation;
use violations::violations;

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
