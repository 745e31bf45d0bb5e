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

/// Reusable buffers for the swarm's minimum separation, computed often (every
/// series row of a flight): the n²/2 pairs run over coordinates laid out per axis
/// in `f32`, which the compiler vectorises. Coordinates differ from exact by
/// about 1e-7 of their magnitude, far below any safety distance.
#[derive(Debug, Default)]
pub struct Pairwise {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
}

impl Pairwise {
    /// Smallest pairwise distance among `positions` (`None` with fewer than two).
    pub fn min_m(&mut self, positions: impl IntoIterator<Item = [f64; 3]>) -> Option<f64> {
        self.x.clear();
        self.y.clear();
        self.z.clear();
        for p in positions {
            self.x.push(p[0] as f32);
            self.y.push(p[1] as f32);
            self.z.push(p[2] as f32);
        }
        if self.x.len() < 2 {
            return None;
        }
        // A squared distance is never negative, so its bits order like integers
        // (NaN sorts last): an integer minimum, which vectorises where a float
        // minimum (NaN-aware) does not.
        let mut best_bits = f32::INFINITY.to_bits();
        for i in 0..self.x.len() - 1 {
            let (xi, yi, zi) = (self.x[i], self.y[i], self.z[i]);
            let rest = self.x[i + 1..]
                .iter()
                .zip(&self.y[i + 1..])
                .zip(&self.z[i + 1..]);
            for ((x, y), z) in rest {
                let (dx, dy, dz) = (x - xi, y - yi, z - zi);
                best_bits = best_bits.min((dx * dx + dy * dy + dz * dz).to_bits());
            }
        }
        Some(f64::from(f32::from_bits(best_bits).sqrt()))
    }

    /// Smallest scaled separation `√((dx/rx)² + (dy/ry)² + (dz/rz)²)` among
    /// `positions` for an ellipsoid of `radii_m` (separated when at least 1):
    /// the plain distance once every coordinate is divided by its radius, so the
    /// same vectorised pass serves both.
    pub fn min_scaled(
        &mut self,
        positions: impl IntoIterator<Item = [f64; 3]>,
        radii_m: [f64; 3],
    ) -> Option<f64> {
        self.min_m(
            positions
                .into_iter()
                .map(|p| [0, 1, 2].map(|i| p[i] / radii_m[i])),
        )
    }
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
        let mut pairwise = Pairwise::default();
        let positions = [[0.0, 0.0, 0.0], [3.0, 4.0, 0.0], [0.0, 0.0, 2.0]];
        assert_eq!(pairwise.min_m(positions), Some(2.0));
        assert_eq!(pairwise.min_m([[1.0, 2.0, 3.0]]), None);
        let far = (0..50).map(|i| [f64::from(i) * 10.0, 0.0, 0.0]);
        let near = [[3.0, 0.5, 0.0], [3.0, 0.8, 0.0]];
        let d = pairwise.min_m(far.chain(near)).expect("pairs");
        assert!((d - 0.3).abs() < 1e-6, "{d}");
    }

    #[test]
    fn scaled_separation_divides_by_each_radius() {
        let mut pairwise = Pairwise::default();
        let radii = [0.25, 0.25, 0.75];
        // Side by side at H and stacked at V: both exactly on the ellipsoid.
        let side = pairwise.min_scaled([[0.0; 3], [0.25, 0.0, 0.0]], radii);
        let stacked = pairwise.min_scaled([[0.0; 3], [0.0, 0.0, 0.75]], radii);
        for scaled in [side, stacked] {
            assert!((scaled.expect("pair") - 1.0).abs() < 1e-6, "{scaled:?}");
        }
        // 0.5 m apart: twice H beside, but two thirds of V below.
        let below = pairwise.min_scaled([[0.0; 3], [0.5, 0.0, 0.0], [0.0, 0.0, -0.5]], radii);
        assert!(
            (below.expect("pairs") - 2.0 / 3.0).abs() < 1e-6,
            "{below:?}"
        );
    }
}
