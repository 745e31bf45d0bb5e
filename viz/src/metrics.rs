//! Derived quantities: a position on a sampled track, the swarm's minimum separation.
//!
//! Kept free of rerun so the arithmetic is unit-tested on its own.

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
    // Squared distances in the loop (it runs n²/2 times per call), one root at the end.
    let mut best_squared = f64::INFINITY;
    for (i, a) in positions.iter().enumerate() {
        for b in &positions[i + 1..] {
            let d2 = (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2);
            best_squared = best_squared.min(d2);
        }
    }
    (positions.len() >= 2).then(|| best_squared.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn position_interpolates_and_holds() {
        let track = [[1.0, 0.0, 0.0, 0.0], [3.0, 2.0, 0.0, 0.0]];
        assert_eq!(position_at(&track, 0.0), Some([0.0, 0.0, 0.0]));
        assert_eq!(position_at(&track, 2.0), Some([1.0, 0.0, 0.0]));
        assert_eq!(position_at(&track, 9.0), Some([2.0, 0.0, 0.0]));
        assert_eq!(position_at(&[], 0.0), None);
    }

    #[test]
    fn closest_pair_distance() {
        let positions = [[0.0, 0.0, 0.0], [3.0, 4.0, 0.0], [0.0, 0.0, 2.0]];
        assert_eq!(min_pairwise_m(&positions), Some(2.0));
        assert_eq!(min_pairwise_m(&positions[..1]), None);
    }
}
