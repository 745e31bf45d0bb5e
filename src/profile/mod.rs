//! Rest-to-rest straight-line motion with bounded speed, acceleration and jerk.
//!
//! Every motion the scheduler plans is a sequence of these: the drone speeds up from
//! rest, cruises at `max_speed_mps` if the run is long enough, and brakes back to
//! rest. Acceleration never jumps: it ramps at the jerk limit to at most
//! `max_accel_mps2`, holds, and ramps back (an S-curve, seven pieces of constant
//! jerk; fewer on short runs). Starting and ending each straight run at rest is what
//! makes turns safe for the acceleration limit: a 90° turn at speed would need an
//! unbounded acceleration on a polyline, so the drone stops at every corner instead.
//!
//! Why the jerk limit: a real autopilot cannot change its acceleration at once (it
//! must tilt first), and ArduCopter's position controller shapes every target with
//! its own jerk limit (`PSC_JERK_XY`, 5 m/s³ by default). Fed a trapezoid, whose
//! acceleration steps from 0 to 2 m/s², it falls behind by up to `a²/2j` in speed
//! and then overshoots to catch up; fed a motion it can follow exactly, it does.
//!
//! The scheduler times its runs with these profiles and the trajectories replay them,
//! so the module sits below both (it needs nothing from the rest of the crate).

mod brake;
mod pieces;
mod resume;

pub use brake::Brake;
pub use pieces::State;
pub use resume::Resume;

use pieces::Piece;
use serde::{Deserialize, Serialize};

/// The kinematic limits every commanded motion keeps.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Kinematics {
    /// Speed limit, m/s.
    pub max_speed_mps: f64,
    /// Acceleration limit, m/s².
    pub max_accel_mps2: f64,
    /// Jerk limit (how fast the acceleration may change), m/s³.
    pub max_jerk_mps3: f64,
}

/// A time-optimal rest-to-rest profile over `length_m` metres.
///
/// ```
/// use swarmctl::profile::{Kinematics, Profile};
/// let limits = Kinematics { max_speed_mps: 1.0, max_accel_mps2: 1.0, max_jerk_mps3: 2.0 };
/// // 4 m at up to 1 m/s, 1 m/s² and 2 m/s³: 0.5 s ramping the acceleration up,
/// // 0.5 s at 1 m/s², 0.5 s ramping it down (1.5 s, 0.75 m to full speed), 2.5 s
/// // cruising, and the same 1.5 s braking.
/// let p = Profile::new(4.0, limits);
/// assert!((p.duration_s() - 5.5).abs() < 1e-12);
/// assert!((p.distance_at_m(1.5) - 0.75).abs() < 1e-12);
/// assert!((p.time_at_distance_s(2.0) - 2.75).abs() < 1e-9);
/// assert!((p.speed_at_mps(2.75) - 1.0).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Profile {
    /// Distance covered, metres.
    pub length_m: f64,
    /// Highest speed reached (the speed limit, or less on a short run), m/s.
    pub peak_speed_mps: f64,
    /// Highest magnitude of the acceleration (the limit, or less on a short run), m/s².
    pub peak_accel_mps2: f64,
    /// Magnitude of the jerk while the acceleration ramps, m/s³.
    pub jerk_mps3: f64,
}

impl Profile {
    /// The fastest rest-to-rest motion over `length_m` under `limits`.
    /// Limits must be positive and finite (mission validation guarantees it).
    pub fn new(length_m: f64, limits: Kinematics) -> Self {
        let length_m = length_m.max(0.0);
        let (v, a, j) = (
            limits.max_speed_mps,
            limits.max_accel_mps2,
            limits.max_jerk_mps3,
        );
        let peak_speed_mps = if length_m >= 2.0 * ramp_length_m(v, a, j) {
            v
        } else {
            // Short run: no cruise, the two ramps meet. Full acceleration is reached
            // when v·j ≥ a²: then length = v²/a + v·a/j, else length = 2·v^1.5/√j.
            let with_full_accel =
                0.5 * a * (-a / j + (a * a / (j * j) + 4.0 * length_m / a).sqrt());
            if with_full_accel * j >= a * a {
                with_full_accel
            } else {
                (0.5 * length_m * j.sqrt()).powf(2.0 / 3.0)
            }
        };
        Self {
            length_m,
            peak_speed_mps,
            peak_accel_mps2: peak_accel(peak_speed_mps, a, j),
            jerk_mps3: j,
        }
    }

    /// Time spent speeding up from rest to the peak speed (equal to the braking time).
    pub fn ramp_s(&self) -> f64 {
        if self.peak_speed_mps <= 0.0 {
            return 0.0;
        }
        self.peak_speed_mps / self.peak_accel_mps2 + self.peak_accel_mps2 / self.jerk_mps3
    }

    /// The seven pieces: jerk up, hold, jerk down; cruise; and the mirror image.
    fn pieces(&self) -> [Piece; 7] {
        let (v, ap, j) = (self.peak_speed_mps, self.peak_accel_mps2, self.jerk_mps3);
        if v <= 0.0 {
            return [(0.0, 0.0); 7];
        }
        let jerk_s = ap / j;
        let hold_s = (v / ap - jerk_s).max(0.0);
        let ramp_m = 0.5 * v * self.ramp_s();
        let cruise_s = ((self.length_m - 2.0 * ramp_m) / v).max(0.0);
        [
            (jerk_s, j),
            (hold_s, 0.0),
            (jerk_s, -j),
            (cruise_s, 0.0),
            (jerk_s, -j),
            (hold_s, 0.0),
            (jerk_s, j),
        ]
    }

    /// Time from rest to rest.
    pub fn duration_s(&self) -> f64 {
        if self.length_m <= 0.0 {
            return 0.0;
        }
        pieces::duration_s(&self.pieces())
    }

    /// Position, speed and acceleration `time_s` after the start. Before the run
    /// the drone rests at 0, after it at `length_m` (exactly).
    pub fn state_at(&self, time_s: f64) -> State {
        if time_s <= 0.0 || self.length_m <= 0.0 {
            return State::rest(0.0);
        }
        let pieces = self.pieces();
        if time_s >= pieces::duration_s(&pieces) {
            return State::rest(self.length_m);
        }
        let mut s = pieces::state_at(State::rest(0.0), &pieces, time_s);
        s.x_m = s.x_m.clamp(0.0, self.length_m);
        s
    }

    /// When the drone passes `distance_m` along the run (clamped to the run), to
    /// below a nanosecond.
    pub fn time_at_distance_s(&self, distance_m: f64) -> f64 {
        let x = distance_m.clamp(0.0, self.length_m);
        let duration_s = self.duration_s();
        if x >= self.length_m {
            return duration_s;
        }
        // Distance only grows along the run.
        pieces::time_to_reach_s(State::rest(0.0), &self.pieces(), x, 1e-10)
            .map_or(duration_s, |t| t.min(duration_s))
    }

    /// Distance covered `time_s` after the start (clamped to the run).
    pub fn distance_at_m(&self, time_s: f64) -> f64 {
        self.state_at(time_s).x_m
    }

    /// Speed `time_s` after the start (zero outside the run).
    pub fn speed_at_mps(&self, time_s: f64) -> f64 {
        self.state_at(time_s).v_mps
    }
}

/// The highest acceleration on the way from rest to `v` (and back): the limit,
/// unless the jerk limit runs out of time to reach it first.
fn peak_accel(v_mps: f64, a_mps2: f64, j_mps3: f64) -> f64 {
    if v_mps * j_mps3 >= a_mps2 * a_mps2 {
        a_mps2
    } else {
        (v_mps * j_mps3).sqrt()
    }
}

/// Distance from rest to speed `v` (the ramp is point-symmetric about its middle,
/// so the mean speed is `v/2`).
fn ramp_length_m(v_mps: f64, a_mps2: f64, j_mps3: f64) -> f64 {
    let ap = peak_accel(v_mps, a_mps2, j_mps3);
    0.5 * v_mps * (v_mps / ap + ap / j_mps3)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits(v: f64, a: f64, j: f64) -> Kinematics {
        Kinematics {
            max_speed_mps: v,
            max_accel_mps2: a,
            max_jerk_mps3: j,
        }
    }

    /// Samples a profile finely and returns the largest |v|, |a| and |Δa/Δt| seen;
    /// the position must never go back.
    fn measured(p: &Profile) -> (f64, f64, f64) {
        let dt = 1e-4;
        let n = (p.duration_s() / dt).ceil() as usize + 2;
        let (mut v_max, mut a_max, mut j_max) = (0.0f64, 0.0f64, 0.0f64);
        let mut prev = p.state_at(-dt);
        for i in 0..=n {
            let s = p.state_at(i as f64 * dt);
            v_max = v_max.max(s.v_mps.abs());
            a_max = a_max.max(s.a_mps2.abs());
            j_max = j_max.max((s.a_mps2 - prev.a_mps2).abs() / dt);
            assert!(s.x_m >= prev.x_m - 1e-12, "position goes back");
            prev = s;
        }
        (v_max, a_max, j_max)
    }

    #[test]
    fn every_run_keeps_all_three_limits_and_ends_at_rest() {
        for &(l, v, a, j) in &[
            (4.0, 1.0, 2.0, 5.0),
            (1.0, 1.0, 2.0, 5.0),
            (0.3, 1.0, 2.0, 5.0),
            (0.01, 1.0, 2.0, 5.0),
            (10.0, 2.5, 0.7, 50.0),
            (2.0, 3.0, 4.0, 1.0),
        ] {
            let p = Profile::new(l, limits(v, a, j));
            let (v_max, a_max, j_max) = measured(&p);
            assert!(v_max <= v + 1e-9, "{l} {v} {a} {j}: speed {v_max}");
            assert!(a_max <= a + 1e-9, "{l} {v} {a} {j}: accel {a_max}");
            assert!(j_max <= j * 1.001 + 1e-6, "{l} {v} {a} {j}: jerk {j_max}");
            let end = p.state_at(p.duration_s() - 1e-9);
            assert!(
                (end.x_m - l).abs() < 1e-6 && end.v_mps.abs() < 1e-6,
                "{l}: {end:?}"
            );
            assert_eq!(p.state_at(p.duration_s() + 1.0), State::rest(l));
        }
    }

    #[test]
    fn short_run_reaches_neither_limit() {
        // 0.02 m: the ramps meet long before 1 m/s or 2 m/s² is reached.
        let p = Profile::new(0.02, limits(1.0, 2.0, 5.0));
        assert!(p.peak_speed_mps < 1.0 && p.peak_accel_mps2 < 2.0);
        // Four jerk pieces of ap/j: 0.02 = 2 · v^1.5 / √j.
        let v = (0.5 * 0.02 * 5f64.sqrt()).powf(2.0 / 3.0);
        assert!((p.peak_speed_mps - v).abs() < 1e-12);
        assert!((p.duration_s() - 4.0 * (v / 5.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_steep_jerk_limit_approaches_the_trapezoid() {
        // 2 m at 1 m/s, 1 m/s²: the trapezoid takes 3 s; at 10⁶ m/s³ the ramps add
        // a microsecond each.
        let p = Profile::new(2.0, limits(1.0, 1.0, 1e6));
        assert!((p.duration_s() - 3.0).abs() < 1e-5);
    }

    #[test]
    fn time_and_distance_are_inverse() {
        for &(l, v, a, j) in &[
            (3.0, 1.0, 2.0, 5.0),
            (0.2, 1.0, 0.5, 5.0),
            (10.0, 2.5, 0.7, 3.0),
        ] {
            let p = Profile::new(l, limits(v, a, j));
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
        let p = Profile::new(0.0, limits(1.0, 1.0, 5.0));
        assert_eq!(p.duration_s(), 0.0);
        assert_eq!(p.distance_at_m(1.0), 0.0);
    }
}
