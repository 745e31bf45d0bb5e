//! The shortest stop from a moving state within the acceleration and jerk limits.

use super::Kinematics;
use super::pieces::{self, Piece, State};

/// Braking to rest along the line from `start`: the jerk takes the acceleration down
/// to full deceleration as fast as allowed, holds it, and ramps it back to zero just
/// as the speed reaches zero (fewer pieces when there is less speed to lose).
///
/// Decelerating as hard as the limits allow, as early as they allow, is the stop
/// that covers the least distance, so no motion from `start` can stop short of
/// [`Brake::stop_m`]. The follower's gate check relies on that: braking later along
/// a profile never stops earlier.
///
/// ```
/// use swarmctl::profile::{Brake, Kinematics, State};
/// let limits = Kinematics { max_speed_mps: 1.0, max_accel_mps2: 2.0, max_jerk_mps3: 5.0 };
/// // Cruising at 1 m/s from x = 3 m: 0.4 s ramping to −2 m/s², 0.1 s at it, 0.4 s back.
/// let b = Brake::new(State { x_m: 3.0, v_mps: 1.0, a_mps2: 0.0 }, limits);
/// assert!((b.duration_s() - 0.9).abs() < 1e-12);
/// assert!((b.stop_m() - 3.45).abs() < 1e-12);
/// assert_eq!(b.state_at(5.0), State::rest(b.stop_m()));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Brake {
    start: State,
    pieces: [Piece; 3],
}

impl Brake {
    /// The shortest stop from `start` (speed ≥ 0 along the line) under `limits`.
    pub fn new(start: State, limits: Kinematics) -> Self {
        let (a, j) = (limits.max_accel_mps2, limits.max_jerk_mps3);
        let v0 = start.v_mps.max(0.0);
        let a0 = start.a_mps2.clamp(-a, a);
        // Ramping from a0 to −a_b, holding for hold_s and ramping back to zero loses
        // (a0² − a_b²)/2j + a_b·hold_s + a_b²/2j of speed, which must be v0.
        let speed_to_lose = v0 + a0 * a0 / (2.0 * j);
        let (decel, hold_s) = if speed_to_lose * j >= a * a {
            (a, (speed_to_lose - a * a / j) / a)
        } else {
            // Never less than already applied: the acceleration only falls from a0.
            ((j * speed_to_lose).sqrt().max(-a0), 0.0)
        };
        Self {
            start: State {
                v_mps: v0,
                a_mps2: a0,
                ..start
            },
            pieces: [((a0 + decel) / j, -j), (hold_s, 0.0), (decel / j, j)],
        }
    }

    /// Its pieces of constant jerk (for motions that end with this stop).
    pub(super) fn pieces(&self) -> [Piece; 3] {
        self.pieces
    }

    /// How long the stop takes, seconds.
    pub fn duration_s(&self) -> f64 {
        pieces::duration_s(&self.pieces)
    }

    /// The state `time_s` after braking began; at rest at [`Brake::stop_m`] after.
    pub fn state_at(&self, time_s: f64) -> State {
        if time_s >= self.duration_s() {
            return State::rest(self.stop_m());
        }
        pieces::state_at(self.start, &self.pieces, time_s)
    }

    /// Where the stop ends, metres along the line.
    pub fn stop_m(&self) -> f64 {
        pieces::state_at(self.start, &self.pieces, self.duration_s()).x_m
    }

    /// How long after braking began it passes `x_m`, to a microsecond (0 if it
    /// starts there or beyond); `None` if it stops short. The follower's
    /// commitments and the schedule's decision lead both ask this.
    pub fn time_to_pass_s(&self, x_m: f64) -> Option<f64> {
        if x_m > self.stop_m() {
            return None;
        }
        if self.start.x_m >= x_m {
            return Some(0.0);
        }
        // Position only grows along a brake: bisect.
        let (mut lo, mut hi) = (0.0, self.duration_s());
        while hi - lo > 1e-6 {
            let mid = 0.5 * (lo + hi);
            if self.state_at(mid).x_m < x_m {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(hi)
    }
}

#[cfg(test)]
mod tests {
    use super::super::Profile;
    use super::*;

    const LIMITS: Kinematics = Kinematics {
        max_speed_mps: 1.0,
        max_accel_mps2: 2.0,
        max_jerk_mps3: 5.0,
    };

    #[test]
    fn a_brake_passes_a_point_once_and_never_one_past_its_stop() {
        let b = Brake::new(
            State {
                x_m: 3.0,
                v_mps: 1.0,
                a_mps2: 0.0,
            },
            LIMITS,
        );
        assert_eq!(b.time_to_pass_s(2.0), Some(0.0));
        assert_eq!(b.time_to_pass_s(b.stop_m() + 1e-3), None);
        let t = b.time_to_pass_s(3.3).expect("passes");
        assert!((b.state_at(t).x_m - 3.3).abs() < 1e-5, "{t}");
        assert!(b.state_at(t - 1e-4).x_m < 3.3);
        let end = b.time_to_pass_s(b.stop_m()).expect("reaches its stop");
        assert!((end - b.duration_s()).abs() < 1e-5, "{end}");
    }

    #[test]
    fn braking_from_any_point_of_a_profile_ends_at_rest_within_the_limits() {
        let p = Profile::new(3.0, LIMITS);
        let steps = 200;
        for i in 0..=steps {
            let t = p.duration_s() * f64::from(i) / f64::from(steps);
            let b = Brake::new(p.state_at(t), LIMITS);
            let end = pieces::state_at(b.start, &b.pieces, b.duration_s());
            assert!(
                end.v_mps.abs() < 1e-9 && end.a_mps2.abs() < 1e-9,
                "at {t}: {end:?}"
            );
            let dt = 1e-3;
            let mut prev = b.state_at(0.0);
            for k in 1..=(b.duration_s() / dt) as usize {
                let s = b.state_at(k as f64 * dt);
                assert!(
                    s.v_mps >= -1e-9 && s.a_mps2.abs() <= 2.0 + 1e-9,
                    "at {t}: {s:?}"
                );
                assert!(
                    (s.a_mps2 - prev.a_mps2).abs() <= 5.0 * dt + 1e-9,
                    "jerk at {t}"
                );
                prev = s;
            }
        }
    }

    #[test]
    fn the_stop_point_never_moves_back_along_a_profile() {
        // What the follower's braking decision rests on.
        let p = Profile::new(3.0, LIMITS);
        let mut last_m = 0.0;
        for i in 0..=1000 {
            let t = p.duration_s() * f64::from(i) / 1000.0;
            let stop_m = Brake::new(p.state_at(t), LIMITS).stop_m();
            assert!(stop_m >= last_m - 1e-9, "at {t}: {stop_m} < {last_m}");
            assert!(
                stop_m <= 3.0 + 1e-9,
                "at {t}: stops beyond the run at {stop_m}"
            );
            last_m = stop_m;
        }
    }

    #[test]
    fn at_rest_it_stays() {
        let b = Brake::new(State::rest(2.0), LIMITS);
        assert_eq!(b.duration_s(), 0.0);
        assert_eq!(b.stop_m(), 2.0);
    }
}
