//! Per-drone speed, acceleration and jerk as finite differences of the samples
//! (see the module docs of [`verify`](super) for why they never exceed the truth).

use super::report::DroneReport;

fn dist(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    ((a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2) + (a[3] - b[3]).powi(2)).sqrt()
}

/// Speed, acceleration and jerk of one drone as first, second and third finite
/// differences of its samples.
pub(super) fn drone_report(s: &[[f64; 4]], period_s: f64) -> DroneReport {
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
