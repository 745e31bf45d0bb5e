//! Straight-line motion as a sequence of pieces of constant jerk.
//!
//! Both the rest-to-rest [`Profile`](super::Profile) and the [`Brake`](super::Brake)
//! are such sequences; this is the one place that integrates them, in closed form
//! piece by piece, so position, speed and acceleration always agree.

/// One piece: how long it lasts (seconds) and its constant jerk (m/s³).
pub(super) type Piece = (f64, f64);

/// Position (m), speed (m/s) and acceleration (m/s²) along the line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// Distance along the line, metres.
    pub x_m: f64,
    /// Speed along the line, m/s.
    pub v_mps: f64,
    /// Acceleration along the line, m/s².
    pub a_mps2: f64,
}

impl State {
    /// At rest at `x_m`.
    pub fn rest(x_m: f64) -> Self {
        Self {
            x_m,
            v_mps: 0.0,
            a_mps2: 0.0,
        }
    }

    /// The state `t_s` later under constant jerk `j_mps3`.
    fn after(self, t_s: f64, j_mps3: f64) -> Self {
        let (x, v, a) = (self.x_m, self.v_mps, self.a_mps2);
        Self {
            x_m: x + v * t_s + a * t_s * t_s / 2.0 + j_mps3 * t_s * t_s * t_s / 6.0,
            v_mps: v + a * t_s + j_mps3 * t_s * t_s / 2.0,
            a_mps2: a + j_mps3 * t_s,
        }
    }
}

/// The state `t_s` after `start`, following `pieces` (clamped to their span:
/// before it the start, after it the state at the end with no jerk applied).
pub(super) fn state_at(start: State, pieces: &[Piece], t_s: f64) -> State {
    let mut state = start;
    let mut left_s = t_s.max(0.0);
    for &(duration_s, jerk_mps3) in pieces {
        if left_s <= duration_s {
            return state.after(left_s, jerk_mps3);
        }
        state = state.after(duration_s, jerk_mps3);
        left_s -= duration_s;
    }
    state
}

/// When the motion from `start` along `pieces` first reaches `x_m` (to within
/// `tolerance_s`), `None` if it never does. Position must not decrease along
/// the pieces (speed never negative), as on a rest-to-rest run: the piece
/// holding `x_m` is found from the pieces' ends, and only it is bisected.
pub(super) fn time_to_reach_s(
    start: State,
    pieces: &[Piece],
    x_m: f64,
    tolerance_s: f64,
) -> Option<f64> {
    if start.x_m >= x_m {
        return Some(0.0);
    }
    let (mut state, mut began_s) = (start, 0.0);
    for &(duration_s, jerk_mps3) in pieces {
        let end = state.after(duration_s, jerk_mps3);
        if end.x_m >= x_m {
            let (mut lo, mut hi) = (0.0, duration_s);
            while hi - lo >= tolerance_s {
                let mid = 0.5 * (lo + hi);
                if state.after(mid, jerk_mps3).x_m < x_m {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return Some(began_s + hi);
        }
        (state, began_s) = (end, began_s + duration_s);
    }
    None
}

/// The total duration of `pieces`, seconds.
pub(super) fn duration_s(pieces: &[Piece]) -> f64 {
    pieces.iter().map(|p| p.0).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_jerk_integrates_to_the_textbook_cubic() {
        let s = state_at(State::rest(1.0), &[(2.0, 3.0)], 2.0);
        // x = 1 + j t³/6 = 1 + 4, v = j t²/2 = 6, a = j t = 6.
        assert!((s.x_m - 5.0).abs() < 1e-12);
        assert!((s.v_mps - 6.0).abs() < 1e-12);
        assert!((s.a_mps2 - 6.0).abs() < 1e-12);
    }

    #[test]
    fn the_time_to_reach_a_point_inverts_the_position() {
        let pieces = [(1.0, 2.0), (0.5, 0.0), (1.0, -2.0), (2.0, 0.0)];
        let end = state_at(State::rest(0.0), &pieces, 4.5).x_m;
        for i in 0..=40 {
            let x = end * f64::from(i) / 40.0;
            let t = time_to_reach_s(State::rest(0.0), &pieces, x, 1e-10).expect("on the run");
            assert!(
                (state_at(State::rest(0.0), &pieces, t).x_m - x).abs() < 1e-8,
                "x {x}"
            );
            // Reached first there: a moment before, not yet (where it moves at all).
            if t > 1e-6 {
                assert!(state_at(State::rest(0.0), &pieces, t - 1e-6).x_m < x);
            }
        }
        assert_eq!(
            time_to_reach_s(State::rest(0.0), &pieces, end + 0.1, 1e-10),
            None
        );
    }

    #[test]
    fn pieces_chain_and_clamp() {
        let pieces = [(1.0, 2.0), (1.0, -2.0)];
        let end = state_at(State::rest(0.0), &pieces, 5.0);
        // Up to a = 2, back to a = 0: v = 2, x = 1/3 + (1 + 1 - 1/3) = 2.
        assert!((end.v_mps - 2.0).abs() < 1e-12);
        assert!(end.a_mps2.abs() < 1e-12);
        assert!((end.x_m - 2.0).abs() < 1e-12);
        assert_eq!(duration_s(&pieces), 2.0);
        assert_eq!(state_at(State::rest(0.0), &pieces, -1.0), State::rest(0.0));
    }
}
