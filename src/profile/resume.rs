//! Motion from a moving state to rest a given distance ahead, within the limits.

use super::brake::Brake;
use super::pieces::{self, Piece, State};
use super::{Kinematics, Profile};

/// From a moving state (typically mid-brake) on to rest `length_m` further, as fast
/// as this S-curve family allows: the jerk takes the speed to a peak (up, or down
/// if already faster), the drone cruises there, and it stops with the shortest
/// [`Brake`] from the peak. The highest peak whose motion still fits in `length_m`
/// is chosen. A drone braking so hard, so slowly, that easing the braking off
/// would stop it and send it backwards first finishes its brake instead and
/// goes on at once with the rest-to-rest [`Profile`](super::Profile).
///
/// This is what lets a drone that began braking for a gate pick up again the
/// moment the gate opens, keeping the speed it still has, instead of stopping and
/// starting over from rest (which costs its own stop, the vehicle settling, and a
/// fresh speed-up). Rest-to-rest motion is the special case the scheduler plans
/// with, [`Profile`](super::Profile).
///
/// ```
/// use swarmctl::profile::{Kinematics, Resume, State};
/// let limits = Kinematics { max_speed_mps: 1.0, max_accel_mps2: 1.0, max_jerk_mps3: 2.5 };
/// // Half-way through a brake at 0.6 m/s: on to rest 3 m further.
/// let from = State { x_m: 0.0, v_mps: 0.6, a_mps2: -1.0 };
/// let r = Resume::new(from, 3.0, limits).expect("0.6 m/s stops well within 3 m");
/// assert_eq!(r.state_at(0.0), from);
/// assert_eq!(r.state_at(r.duration_s()), State::rest(3.0));
/// // Never slower than stopping and starting over from rest.
/// assert!(r.peak_speed_mps() > 0.6);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resume {
    start: State,
    length_m: f64,
    peak_speed_mps: f64,
    /// Speed change to the peak (3), cruise (1), brake (3), three unused; or the
    /// rest of the brake (3) and a rest-to-rest profile (7).
    pieces: [Piece; 10],
}

impl Resume {
    /// The motion from `start` (at `x_m = 0`, speed ≥ 0 along the line) to rest at
    /// `length_m` under `limits`; `None` when the shortest stop from `start`
    /// already ends beyond `length_m`, or `start` breaks the limits.
    pub fn new(start: State, length_m: f64, limits: Kinematics) -> Option<Self> {
        let (v_max, a_max, j) = (
            limits.max_speed_mps,
            limits.max_accel_mps2,
            limits.max_jerk_mps3,
        );
        let (v0, a0) = (start.v_mps, start.a_mps2);
        if !(v0 >= 0.0 && v0 <= v_max + 1e-9 && a0.abs() <= a_max + 1e-9) {
            return None;
        }
        let start = State { x_m: 0.0, ..start };
        // Easing a deceleration off at the jerk limit loses a0²/2j more speed.
        if a0 < 0.0 && v0 < a0 * a0 / (2.0 * j) {
            return Self::brake_then_go(start, length_m, limits);
        }
        let fits = |peak_mps: f64| Self::build(start, peak_mps, 0.0, limits).1 <= length_m + 1e-9;
        if !fits(0.0) {
            return None;
        }
        let peak_speed_mps = if fits(v_max) {
            v_max
        } else {
            // The distance grows with the peak: bisect to a micrometre per second.
            let (mut lo, mut hi) = (0.0, v_max);
            while hi - lo > 1e-6 {
                let mid = 0.5 * (lo + hi);
                if fits(mid) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo
        };
        let reach_m = Self::build(start, peak_speed_mps, 0.0, limits).1;
        let cruise_s = if peak_speed_mps > 1e-9 {
            (length_m - reach_m) / peak_speed_mps
        } else {
            0.0
        };
        let (pieces, _) = Self::build(start, peak_speed_mps, cruise_s, limits);
        Some(Self {
            start,
            length_m,
            peak_speed_mps,
            pieces,
        })
    }

    /// The rest of the shortest stop from `start`, then at once the rest-to-rest
    /// profile over what is left (the brake ends, and the profile begins, at rest
    /// with the jerk pushing forward, so nothing jumps).
    fn brake_then_go(start: State, length_m: f64, limits: Kinematics) -> Option<Self> {
        let brake = Brake::new(start, limits);
        let left_m = length_m - brake.stop_m();
        if left_m < -1e-9 {
            return None;
        }
        let profile = Profile::new(left_m.max(0.0), limits);
        let [b0, b1, b2] = brake.pieces();
        let [p0, p1, p2, p3, p4, p5, p6] = if profile.duration_s() > 0.0 {
            profile.pieces()
        } else {
            [(0.0, 0.0); 7]
        };
        Some(Self {
            start,
            length_m,
            peak_speed_mps: profile.peak_speed_mps.max(start.v_mps),
            pieces: [b0, b1, b2, p0, p1, p2, p3, p4, p5, p6],
        })
    }

    /// The pieces that take `start` to `peak_mps`, cruise `cruise_s` there and
    /// brake, and where that ends.
    fn build(start: State, peak_mps: f64, cruise_s: f64, limits: Kinematics) -> ([Piece; 10], f64) {
        let change = speed_change(start.v_mps, start.a_mps2, peak_mps, limits);
        let at_peak = pieces::state_at(start, &change, pieces::duration_s(&change));
        let brake = Brake::new(
            State {
                x_m: at_peak.x_m + peak_mps * cruise_s,
                v_mps: peak_mps,
                a_mps2: 0.0,
            },
            limits,
        );
        let [b0, b1, b2] = brake.pieces();
        (
            [
                change[0],
                change[1],
                change[2],
                (cruise_s, 0.0),
                b0,
                b1,
                b2,
                (0.0, 0.0),
                (0.0, 0.0),
                (0.0, 0.0),
            ],
            brake.stop_m(),
        )
    }

    /// The speed it cruises at, m/s.
    pub fn peak_speed_mps(&self) -> f64 {
        self.peak_speed_mps
    }

    /// Distance from the start to the rest point, metres.
    pub fn length_m(&self) -> f64 {
        self.length_m
    }

    /// How long it takes to come to rest, seconds.
    pub fn duration_s(&self) -> f64 {
        pieces::duration_s(&self.pieces)
    }

    /// The state `time_s` after the start; at rest at [`Resume::length_m`] after.
    pub fn state_at(&self, time_s: f64) -> State {
        if time_s >= self.duration_s() {
            return State::rest(self.length_m);
        }
        let mut s = pieces::state_at(self.start, &self.pieces, time_s);
        s.x_m = s.x_m.min(self.length_m);
        s
    }

    /// When it passes `distance_m` from the start (clamped to the motion).
    pub fn time_at_distance_s(&self, distance_m: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, self.duration_s());
        if distance_m >= self.length_m {
            return hi;
        }
        // Position only grows along the motion: bisect to below a nanosecond.
        while hi - lo > 1e-10 {
            let mid = 0.5 * (lo + hi);
            if self.state_at(mid).x_m < distance_m {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    }
}

/// The quickest change from speed `v0` and acceleration `a0` to speed `v1` at zero
/// acceleration: the acceleration ramps at the jerk limit to a peak (at most the
/// limit), holds, and ramps back to zero.
fn speed_change(v0: f64, a0: f64, v1: f64, limits: Kinematics) -> [Piece; 3] {
    let (a_max, j) = (limits.max_accel_mps2, limits.max_jerk_mps3);
    // The speed reached by only ramping a0 back to zero.
    let v_ramp = v0 + a0 * a0.abs() / (2.0 * j);
    // Work with speeding up; slowing down is its mirror image.
    let (sign, a0, dv) = if v1 >= v_ramp {
        (1.0, a0, v1 - v0)
    } else {
        (-1.0, -a0, v0 - v1)
    };
    // Ramping a0 → ap → 0 gains (2ap² − a0²)/2j; a hold at ap gains ap per second.
    let ap_unheld = ((2.0 * j * dv + a0 * a0) / 2.0).max(0.0).sqrt().max(a0);
    let (ap, hold_s) = if ap_unheld <= a_max {
        (ap_unheld, 0.0)
    } else {
        (
            a_max,
            ((dv - (2.0 * a_max * a_max - a0 * a0) / (2.0 * j)) / a_max).max(0.0),
        )
    };
    [
        ((ap - a0) / j, sign * j),
        (hold_s, 0.0),
        (ap / j, -sign * j),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: Kinematics = Kinematics {
        max_speed_mps: 1.0,
        max_accel_mps2: 1.0,
        max_jerk_mps3: 2.5,
    };

    /// Samples finely: the limits hold, position never goes back, acceleration
    /// changes no faster than the jerk limit, and it ends at rest at the length.
    fn assert_within_limits(r: &Resume, what: &str) {
        let dt = 1e-4;
        let mut prev = r.state_at(0.0);
        for k in 1..=((r.duration_s() / dt) as usize + 2) {
            let s = r.state_at(k as f64 * dt);
            assert!(s.v_mps >= -1e-9 && s.v_mps <= 1.0 + 1e-9, "{what}: {s:?}");
            assert!(s.a_mps2.abs() <= 1.0 + 1e-9, "{what}: {s:?}");
            assert!(s.x_m >= prev.x_m - 1e-12, "{what}: goes back at {s:?}");
            assert!(
                (s.a_mps2 - prev.a_mps2).abs() <= 2.5 * dt + 1e-9,
                "{what}: jerk at {s:?}"
            );
            prev = s;
        }
        let end = pieces::state_at(r.start, &r.pieces, r.duration_s());
        assert!(
            (end.x_m - r.length_m).abs() < 1e-5
                && end.v_mps.abs() < 1e-9
                && end.a_mps2.abs() < 1e-9,
            "{what}: ends at {end:?}"
        );
    }

    /// From every point of every brake along a profile, resuming to the run's end
    /// keeps all three limits, ends there at rest, and is never slower than
    /// finishing the brake and starting over from rest.
    #[test]
    fn resuming_from_any_point_of_a_brake_keeps_the_limits_and_saves_time() {
        let p = Profile::new(4.0, LIMITS);
        let mut resumed = 0;
        for i in 1..20 {
            let t_brake = p.duration_s() * 0.5 * f64::from(i) / 20.0;
            let brake = Brake::new(p.state_at(t_brake), LIMITS);
            for k in 0..10 {
                let into_s = brake.duration_s() * f64::from(k) / 10.0;
                let now = brake.state_at(into_s);
                let left_m = 4.0 - now.x_m;
                let from = State { x_m: 0.0, ..now };
                let what = format!("brake at {t_brake:.2} s, {into_s:.2} s in: {now:?}");
                match Resume::new(from, left_m, LIMITS) {
                    Some(r) => {
                        resumed += 1;
                        assert_within_limits(&r, &what);
                        let over_s = brake.duration_s() - into_s
                            + Profile::new(4.0 - brake.stop_m(), LIMITS).duration_s();
                        assert!(r.duration_s() <= over_s + 1e-6, "{what}: slower");
                    }
                    None => panic!("{what}: refused"),
                }
            }
        }
        assert_eq!(resumed, 190);
    }

    /// From rest it is the scheduler's own rest-to-rest profile.
    #[test]
    fn from_rest_it_is_the_rest_to_rest_profile() {
        for &length_m in &[0.05, 0.4, 1.0, 4.0] {
            let r = Resume::new(State::rest(0.0), length_m, LIMITS).expect("from rest");
            let p = Profile::new(length_m, LIMITS);
            assert!((r.duration_s() - p.duration_s()).abs() < 1e-4, "{length_m}");
            assert_within_limits(&r, &format!("{length_m} m from rest"));
        }
    }

    /// Nothing stops shorter than the brake, so a rest point before it is refused;
    /// one at the brake's own stop is the brake.
    #[test]
    fn a_rest_point_short_of_the_brake_is_refused() {
        let cruising = State {
            x_m: 0.0,
            v_mps: 1.0,
            a_mps2: 0.0,
        };
        let brake = Brake::new(cruising, LIMITS);
        assert!(Resume::new(cruising, brake.stop_m() - 0.01, LIMITS).is_none());
        let r = Resume::new(cruising, brake.stop_m(), LIMITS).expect("the brake itself");
        assert!((r.duration_s() - brake.duration_s()).abs() < 1e-3);
        // Time at distance inverts the motion.
        for i in 0..=20 {
            let x = brake.stop_m() * f64::from(i) / 20.0;
            assert!((r.state_at(r.time_at_distance_s(x)).x_m - x).abs() < 1e-6);
        }
    }
}
