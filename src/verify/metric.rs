//! How two drones' relative position is measured: Euclidean distance for a
//! spherical separation, the scaled distance of a bounding cylinder for an
//! ellipsoidal one; the value on a chord, and the slack a deviation from it costs.

/// How two drones' relative position is measured.
#[derive(Debug, Clone, Copy)]
pub(super) enum Metric {
    /// Distance, metres.
    Euclid,
    /// `max(ρ / h, |dz| / v)`: at least 1 outside the cylinder of radius `h` and
    /// half height `v`.
    Cylinder { h: f64, v: f64 },
}

impl Metric {
    pub(super) fn of(self, r: [f64; 3]) -> f64 {
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
    pub(super) fn min_on_chord(self, r0: [f64; 3], dr: [f64; 3]) -> (f64, f64) {
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
    pub(super) fn floor(self, radius_m: f64) -> f64 {
        match self {
            Metric::Euclid => radius_m,
            // ρ² + dz² ≥ r² puts ρ or |dz| at r/√2 or more.
            Metric::Cylinder { h, v } => radius_m / (std::f64::consts::SQRT_2 * h.max(v)),
        }
    }

    /// How much the value may drop when each drone strays `deviation_m` in all from
    /// its chord.
    pub(super) fn slack(self, deviation_m: f64) -> f64 {
        match self {
            Metric::Euclid => deviation_m,
            Metric::Cylinder { h, v } => deviation_m / h.min(v),
        }
    }
}
