//! The report held against the limits: separation, speed, acceleration, jerk and
//! rest at both ends, each breach a human-readable line.

use super::report::{ClosestPair, SeparationReport};
use crate::mission::Limits;

/// Float slack for comparisons with limits, so that exact profiles pass.
const TOLERANCE: f64 = 1e-6;

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

/// Every limit the report breaks, as a human-readable line each.
pub(super) fn violations(report: &SeparationReport, limits: &Limits, period_s: f64) -> Vec<String> {
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
