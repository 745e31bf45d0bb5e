//! Rest-to-rest straight-line motion with bounded speed and acceleration.
//!
//! Every motion the scheduler plans is a sequence of these: the drone accelerates at
//! `accel_mps2` from rest, cruises at `max_speed_mps` if the run is long enough, and
//! decelerates at `accel_mps2` back to rest (a trapezoid, or a triangle on short runs).
//! Starting and ending each straight run at rest is what makes turns safe for the
//! acceleration limit: a 90° turn at speed would need an unbounded acceleration on a
//! polyline, so the drone stops at every corner instead.
//!
//! The scheduler times its runs with these profiles and the trajectories replay them,
//! so the module sits below both (it needs nothing from the rest of the crate).

use serde::{Deserialize, Serialize};

/// A time-optimal rest-to-rest profile over `length_m` metres.
///
/// ```
/// use swarmctl::profile::Profile;
/// // 4 m at up to 1 m/s and 1 m/s²: 1 s to accelerate, 3 s cruising, 1 s braking.
/// let p = Profile::new(4.0, 1.0, 1.0);
/// assert!((p.duration_s() - 5.0).abs() < 1e-12);
/// assert!((p.time_at_distance_s(0.5) - 1.0).abs() < 1e-12);
/// assert!((p.distance_at_m(2.5) - 2.0).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Profile {
    /// Distance covered, metres.
    pub length_m: f64,
    /// Highest speed reached (the speed limit, or less on a short run), m/s.
    pub peak_speed_mps: f64,
    /// Magnitude of the acceleration while speeding up and braking, m/s².
    pub accel_mps2: f64,
}

impl Profile {
    /// The fastest rest-to-rest motion over `length_m` under the given limits.
    /// Limits must be positive (mission validation guarantees it).
    pub fn new(length_m: f64, max_speed_mps: f64, max_accel_mps2: f64) -> Self {
        let length_m = length_m.max(0.0);
        // Distance needed to reach full speed and brake again.
        let full_speed_length_m = max_speed_mps * max_speed_mps / max_accel_mps2;
        let peak_speed_mps = if length_m >= full_speed_length_m {
            max_speed_mps
        } else {
            (length_m * max_accel_mps2).sqrt()
        };
        Self {
            length_m,
            peak_speed_mps,
            accel_mps2: max_accel_mps2,
        }
    }

    /// Time spent accelerating (equal to the time spent braking).
    pub fn ramp_s(&self) -> f64 {
        self.peak_speed_mps / self.accel_mps2
    }

    /// Distance covered while accelerating (equal to the braking distance).
    fn ramp_m(&self) -> f64 {
        0.5 * self.peak_speed_mps * self.ramp_s()
    }

    /// Time from rest to rest.
    pub fn duration_s(&self) -> f64 {
        if self.length_m <= 0.0 {
            return 0.0;
        }
        2.0 * self.ramp_s() + (self.length_m - 2.0 * self.ramp_m()).max(0.0) / self.peak_speed_mps
    }

    /// When the drone passes `distance_m` along the run (clamped to the run).
    pub fn time_at_distance_s(&self, distance_m: f64) -> f64 {
        let x = distance_m.clamp(0.0, self.length_m);
        let ramp_m = self.ramp_m();
        let a = self.accel_mps2;
        if x <= ramp_m {
            (2.0 * x / a).sqrt()
        } else if x <= self.length_m - ramp_m {
            self.ramp_s() + (x - ramp_m) / self.peak_speed_mps
        } else {
            self.duration_s() - (2.0 * (self.length_m - x) / a).sqrt()
        }
    }

    /// Distance covered `time_s` after the start (clamped to the run).
    pub fn distance_at_m(&self, time_s: f64) -> f64 {
        let d = self.duration_s();
        let t = time_s.clamp(0.0, d);
        let ramp_s = self.ramp_s();
        let a = self.accel_mps2;
        if t <= ramp_s {
            0.5 * a * t * t
        } else if t <= d - ramp_s {
            self.ramp_m() + self.peak_speed_mps * (t - ramp_s)
        } else {
            let left_s = d - t;
            self.length_m - 0.5 * a * left_s * left_s
        }
    }

    /// Signed acceleration along the run `time_s` after the start: `+a` speeding
    /// up, `−a` braking, zero cruising and outside the run.
    pub fn accel_at_mps2(&self, time_s: f64) -> f64 {
        let d = self.duration_s();
        if time_s <= 0.0 || time_s >= d {
            return 0.0;
        }
        let ramp_s = self.ramp_s();
        if time_s < ramp_s {
            self.accel_mps2
        } else if time_s > d - ramp_s {
            -self.accel_mps2
        } else {
            0.0
        }
    }

    /// Speed `time_s` after the start (zero outside the run).
    pub fn speed_at_mps(&self, time_s: f64) -> f64 {
        let d = self.duration_s();
        if time_s <= 0.0 || time_s >= d {
            return 0.0;
        }
        let ramp_s = self.ramp_s();
        let a = self.accel_mps2;
        if time_s <= ramp_s {
            a * time_s
        } else if time_s <= d - ramp_s {
            self.peak_speed_mps
        } else {
            a * (d - time_s)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_run_is_a_triangle() {
        // 0.5 m at 1 m/s², speed limit 2 m/s is never reached: peak sqrt(0.5).
        let p = Profile::new(0.5, 2.0, 1.0);
        assert!((p.peak_speed_mps - 0.5f64.sqrt()).abs() < 1e-12);
        assert!((p.duration_s() - 2.0 * 0.5f64.sqrt()).abs() < 1e-12);
        assert!((p.distance_at_m(p.duration_s() / 2.0) - 0.25).abs() < 1e-12);
    }

    #[test]
    fn time_and_distance_are_inverse() {
        for &(l, v, a) in &[(3.0, 1.0, 2.0), (0.2, 1.0, 0.5), (10.0, 2.5, 0.7)] {
            let p = Profile::new(l, v, a);
            for i in 0..=50 {
                let x = l * f64::from(i) / 50.0;
                let t = p.time_at_distance_s(x);
                assert!((p.distance_at_m(t) - x).abs() < 1e-9, "{l} {v} {a} at {x}");
            }
            assert!(p.peak_speed_mps <= v + 1e-12);
        }
    }

    #[test]
    fn zero_length_takes_no_time() {
        let p = Profile::new(0.0, 1.0, 1.0);
        assert_eq!(p.duration_s(), 0.0);
        assert_eq!(p.distance_at_m(1.0), 0.0);
    }
}
