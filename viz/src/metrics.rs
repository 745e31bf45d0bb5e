//! Derived time series: speed along a sampled track, and the swarm's minimum separation.
//!
//! Kept free of rerun so the arithmetic is unit-tested on its own.

/// Speeds `(t_s, speed_mps)` by finite differences of consecutive samples
/// `[t_s, x, y, z]`, stamped at the later sample. Pairs with no elapsed time are skipped.
pub fn speeds(track: &[[f64; 4]]) -> Vec<(f64, f64)> {
    track
        .windows(2)
        .filter_map(|w| {
            let dt_s = w[1][0] - w[0][0];
            (dt_s > 0.0).then(|| (w[1][0], distance(&w[0], &w[1]) / dt_s))
        })
        .collect()
}

/// Position on a time-sorted track at `t_s`, linear between samples and held
/// at both ends. `None` for an empty track.
pub fn position_at(track: &[[f64; 4]], t_s: f64) -> Option<[f64; 3]> {
    let first = track.first()?;
    let last = track.last()?;
    if t_s <= first[0] {
        return Some([first[1], first[2], first[3]]);
    }
    if t_s >= last[0] {
        return Some([last[1], last[2], last[3]]);
    }
    let i = track.partition_point(|s| s[0] <= t_s);
    let (a, b) = (&track[i - 1], &track[i]);
    let f = if b[0] > a[0] {
        (t_s - a[0]) / (b[0] - a[0])
    } else {
        0.0
    };
    Some([1, 2, 3].map(|k| a[k] + f * (b[k] - a[k])))
}

/// Smallest pairwise distance among `positions` (`None` with fewer than two).
pub fn min_pairwise_m(positions: &[[f64; 3]]) -> Option<f64> {
    let mut best: Option<f64> = None;
    for (i, a) in positions.iter().enumerate() {
        for b in &positions[i + 1..] {
            let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
            best = Some(best.map_or(d, |m| m.min(d)));
        }
    }
    best
}

/// Minimum separation of the swarm sampled every `period_s` from the earliest to
/// the latest sample of any track: `(t_s, min_distance_m)`.
pub fn min_separation_series(tracks: &[&[[f64; 4]]], period_s: f64) -> Vec<(f64, f64)> {
    let t0 = tracks
        .iter()
        .filter_map(|t| t.first())
        .map(|s| s[0])
        .fold(f64::INFINITY, f64::min);
    let t1 = tracks
        .iter()
        .filter_map(|t| t.last())
        .map(|s| s[0])
        .fold(f64::NEG_INFINITY, f64::max);
    if !(t0.is_finite() && t1.is_finite()) || period_s <= 0.0 {
        return Vec::new();
    }
    let steps = ((t1 - t0) / period_s).ceil() as usize;
    let mut positions = Vec::with_capacity(tracks.len());
    (0..=steps)
        .filter_map(|k| {
            let t_s = (t0 + k as f64 * period_s).min(t1);
            positions.clear();
            positions.extend(tracks.iter().filter_map(|t| position_at(t, t_s)));
            min_pairwise_m(&positions).map(|d| (t_s, d))
        })
        .collect()
}

fn distance(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    ((b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2) + (b[3] - a[3]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speed_of_a_straight_line() {
        let track = [
            [0.0, 0.0, 0.0, 0.0],
            [0.5, 1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0, 0.0],
            [1.0, 1.0, 2.0, 0.0],
        ];
        assert_eq!(speeds(&track), vec![(0.5, 2.0), (1.0, 4.0)]);
    }

    #[test]
    fn position_interpolates_and_holds() {
        let track = [[1.0, 0.0, 0.0, 0.0], [3.0, 2.0, 0.0, 0.0]];
        assert_eq!(position_at(&track, 0.0), Some([0.0, 0.0, 0.0]));
        assert_eq!(position_at(&track, 2.0), Some([1.0, 0.0, 0.0]));
        assert_eq!(position_at(&track, 9.0), Some([2.0, 0.0, 0.0]));
        assert_eq!(position_at(&[], 0.0), None);
    }

    #[test]
    fn separation_of_two_approaching_drones() {
        let a = [[0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 0.0, 0.0]];
        let b = [[0.0, 4.0, 0.0, 0.0], [1.0, 2.0, 0.0, 0.0]];
        let series = min_separation_series(&[&a, &b], 0.5);
        assert_eq!(series, vec![(0.0, 4.0), (0.5, 2.5), (1.0, 1.0)]);
    }
}
