//! The acceleration feed-forward a vehicle is sent: the setpoint's, less what would
//! push the vehicle past its autopilot's own speed maximum.
//!
//! PX4's position controller clamps its velocity setpoint — the position error
//! times its gain plus our velocity feed-forward — at its own maximum
//! (`MPC_XY_VEL_MAX`, `MPC_Z_VEL_MAX_UP`/`_DN`), and only then adds our
//! acceleration feed-forward to the velocity loop's output (`PositionControl`'s
//! `_positionControl`, then `_velocityControl`). While the vehicle trails its
//! setpoint far enough for that clamp to hold, the velocity setpoint no longer
//! rises with the trajectory, yet the feed-forward still pushes: the vehicle
//! speeds past the maximum until the velocity loop's error cancels it (`a / P`
//! in the steady state: 0.6 m/s for 1.08 m/s² at PX4's default gain of 1.8).
//! Measured on one PX4 SIH vehicle (`MPC_XY_VEL_MAX` 0.625 m/s, its setpoint
//! stepped 8 m ahead with 0.5 m/s velocity feed-forward, 2026-12-07): 0.64 m/s
//! at most by its estimate; with 1 m/s² of acceleration feed-forward for the
//! first second as well, 0.77 m/s.
//!
//! Here the controller's velocity setpoint is predicted from the vehicle's
//! position, and the feed-forward that would speed it up along a clamped velocity
//! setpoint is tapered off over the last [`TAPER_MPS`] below the maximum:
//! braking, turning and a vehicle on its setpoint keep all of it. ArduCopter
//! shapes its own target within its own limits (`WPNAV_*`, `PSC_JERK_*`) and gets
//! the setpoint's feed-forward unchanged.

use crate::fly::follower::Setpoint;

/// How far below the autopilot's own maximum the feed-forward along a velocity
/// setpoint starts to taper, m/s: a little more than SIH's velocity noise, so a
/// vehicle at the edge of the clamp does not get its feed-forward switched on and
/// off from tick to tick.
pub const TAPER_MPS: f64 = 0.1;

/// An autopilot's velocity clamp, as its position controller applies it before
/// adding the acceleration feed-forward.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedClamp {
    /// Its own speed maximum, horizontally and up and down (pre-flight sets one
    /// for every axis: `vehicle_limits::own_max_speed_mps`), m/s.
    pub max_speed_mps: f64,
    /// Horizontal position gain, 1/s (PX4 `MPC_XY_P`).
    pub horizontal_gain_per_s: f64,
    /// Vertical position gain, 1/s (PX4 `MPC_Z_P`).
    pub vertical_gain_per_s: f64,
}

/// The acceleration feed-forward to send with `setpoint`, ENU m/s², for a vehicle
/// at `vehicle_m` (mission ENU; `None` when unseen) whose autopilot clamps as
/// `clamp` says (`None`: the setpoint's own, unchanged).
pub fn acceleration_to_send(
    setpoint: &Setpoint,
    vehicle_m: Option<[f64; 3]>,
    clamp: Option<&SpeedClamp>,
) -> [f64; 3] {
    let a = setpoint.acceleration_mps2;
    let (Some(clamp), Some(p)) = (clamp, vehicle_m) else {
        return a;
    };
    let sp = setpoint.position_m;
    let v = setpoint.velocity_mps;
    let k_xy = clamp.horizontal_gain_per_s;
    let asked_xy = [k_xy * (sp[0] - p[0]) + v[0], k_xy * (sp[1] - p[1]) + v[1]];
    let [ax, ay] = taper_along([a[0], a[1]], asked_xy, clamp.max_speed_mps);
    let asked_z = clamp.vertical_gain_per_s * (sp[2] - p[2]) + v[2];
    let [az] = taper_along([a[2]], [asked_z], clamp.max_speed_mps);
    [ax, ay, az]
}

/// `accel` with its component along `asked` (the velocity the controller asks
/// for) scaled down to nothing as `asked` nears `max_mps`, when that component
/// would speed the vehicle up; every other part kept.
fn taper_along<const N: usize>(accel: [f64; N], asked: [f64; N], max_mps: f64) -> [f64; N] {
    let speed_mps = asked.iter().map(|c| c * c).sum::<f64>().sqrt();
    let keep = ((max_mps - speed_mps) / TAPER_MPS).clamp(0.0, 1.0);
    if keep >= 1.0 || speed_mps <= 0.0 {
        return accel;
    }
    let unit = asked.map(|c| c / speed_mps);
    let along: f64 = accel.iter().zip(&unit).map(|(a, u)| a * u).sum();
    if along <= 0.0 {
        return accel;
    }
    let removed = along * (1.0 - keep);
    let mut out = accel;
    for (o, u) in out.iter_mut().zip(unit) {
        *o -= removed * u;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const CLAMP: SpeedClamp = SpeedClamp {
        max_speed_mps: 0.625,
        horizontal_gain_per_s: 0.95,
        vertical_gain_per_s: 1.0,
    };

    fn setpoint(velocity_mps: [f64; 3], acceleration_mps2: [f64; 3]) -> Setpoint {
        Setpoint {
            position_m: [0.0, 0.0, 5.0],
            velocity_mps,
            acceleration_mps2,
        }
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    #[test]
    fn on_its_setpoint_a_vehicle_gets_all_of_it_half_a_metre_behind_none() {
        let speeding_up = Setpoint {
            position_m: [1.0, 0.0, 5.0],
            velocity_mps: [0.3, 0.0, 0.0],
            acceleration_mps2: [1.0, 0.0, 0.0],
        };
        let on = acceleration_to_send(&speeding_up, Some([1.0, 0.0, 5.0]), Some(&CLAMP));
        assert_eq!(on, [1.0, 0.0, 0.0]);
        // Its controller asks for 0.3 + 0.475 m/s, past the 0.625 maximum.
        let behind = acceleration_to_send(&speeding_up, Some([0.5, 0.0, 5.0]), Some(&CLAMP));
        assert!(close(behind, [0.0, 0.0, 0.0]), "{behind:?}");
    }

    #[test]
    fn without_a_clamp_or_a_position_the_feedforward_is_the_setpoints() {
        let s = setpoint([0.5, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let far = Some([-3.0, 0.0, 5.0]);
        assert_eq!(acceleration_to_send(&s, far, None), [1.0, 0.0, 0.0]);
        assert_eq!(
            acceleration_to_send(&s, None, Some(&CLAMP)),
            [1.0, 0.0, 0.0]
        );
    }

    #[test]
    fn a_trailing_vehicle_is_not_pushed_past_its_clamp() {
        // 0.2 m behind at 0.5 m/s: 0.69 m/s asked, over the 0.625 maximum.
        let s = setpoint([0.5, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let a = acceleration_to_send(&s, Some([-0.2, 0.0, 5.0]), Some(&CLAMP));
        assert!(close(a, [0.0, 0.0, 0.0]), "{a:?}");
    }

    #[test]
    fn braking_and_sideways_feedforward_is_kept_however_far_behind() {
        let brake = setpoint([0.5, 0.0, 0.0], [-1.0, 0.0, 0.0]);
        let behind = Some([-2.0, 0.0, 5.0]);
        assert_eq!(
            acceleration_to_send(&brake, behind, Some(&CLAMP)),
            [-1.0, 0.0, 0.0]
        );
        // Asked along x; a turn's y part stays, the x part goes.
        let turn = setpoint([0.5, 0.0, 0.0], [1.0, 0.5, 0.0]);
        let a = acceleration_to_send(&turn, behind, Some(&CLAMP));
        assert!(close(a, [0.0, 0.5, 0.0]), "{a:?}");
    }

    #[test]
    fn the_feedforward_tapers_over_the_last_tenth_below_the_maximum() {
        // 0.575 m/s asked: halfway into the taper, half the push is kept.
        let s = setpoint([0.575, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let a = acceleration_to_send(&s, Some([0.0, 0.0, 5.0]), Some(&CLAMP));
        assert!(close(a, [0.5, 0.0, 0.0]), "{a:?}");
    }

    #[test]
    fn vertical_feedforward_is_clamped_on_its_own_maximum() {
        // Climbing at 0.4 m/s, 0.3 m low: 0.7 m/s asked up, over 0.625.
        let climb = setpoint([0.0, 0.0, 0.4], [0.3, 0.0, 0.8]);
        let a = acceleration_to_send(&climb, Some([0.0, 0.0, 4.7]), Some(&CLAMP));
        assert!(close(a, [0.3, 0.0, 0.0]), "{a:?}");
    }
}
