//! The closest approach of every pair of drones, at the samples and between them,
//! found by spatial hashing (see the module docs of [`verify`](super) for the
//! bound between samples and the scale).

use super::metric::Metric;
use super::report::ClosestPair;
use std::collections::HashMap;

/// The closest approach under one metric.
pub(super) struct Separation {
    metric: Metric,
    /// Smallest value at a common sample time.
    pub(super) samples_m: f64,
    /// Smallest value of the linearly interpolated motions.
    pub(super) interpolated_m: f64,
    /// Guaranteed lower bound on the true continuous value.
    pub(super) bound_m: f64,
    /// Largest deviation of one drone from its chord within an interval.
    margin_m: f64,
    /// The pair behind the bound, if any pair came within the search radius.
    pub(super) closest: Option<ClosestPair>,
}

/// Closest approach over all pairs and sample intervals, by spatial hashing.
pub(super) fn separation(
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
