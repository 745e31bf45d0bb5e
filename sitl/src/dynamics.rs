//! Point-mass quadrotor: a position controller with speed and acceleration
//! limits and a first-order lag, integrated at a fixed step, plus ground contact.
//!
//! The model is deliberately simple: a swarm executor needs a vehicle that
//! lags, saturates and lands like a multirotor, not aerodynamics. The limits
//! are hard guarantees (tested): |v| never exceeds the speed limit and the
//! change of velocity per step never exceeds `max_accel · dt`.

/// Standard gravity, m/s², for free fall and attitude estimation.
pub const GRAVITY_MPS2: f32 = 9.806_65;

/// Time constant of the first-order velocity response, seconds.
pub const LAG_TAU_S: f32 = 0.25;

/// Proportional gain of the position loop, 1/s.
const POSITION_GAIN_PER_S: f32 = 1.2;

/// Height above ground (metres) under which the vehicle counts as touching it.
pub const GROUND_CONTACT_M: f32 = 0.02;

/// Speed under which a vehicle in ground contact counts as landed, m/s.
pub const LANDED_SPEED_MPS: f32 = 0.25;

/// A 3-vector in metres or metres per second (north, east, down).
pub type Vec3 = [f32; 3];

/// What the controller is asked to track, per axis; `None` ignores that axis
/// component (MAVLink `type_mask` semantics).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Setpoint {
    /// Position target (NED metres) per axis.
    pub position_ned_m: [Option<f32>; 3],
    /// Velocity target or feed-forward (NED m/s) per axis.
    pub velocity_ned_mps: [Option<f32>; 3],
    /// Yaw target in radians, if any.
    pub yaw_rad: Option<f32>,
    /// Acceleration feed-forward (NED m/s²) per axis: the velocity loop leads by
    /// it, so a vehicle following a smooth trajectory does not lag by its own
    /// response time.
    pub accel_ned_mps2: [Option<f32>; 3],
}

impl Setpoint {
    /// Hold the given position with zero velocity.
    pub fn hold(position_ned_m: Vec3) -> Self {
        Self {
            position_ned_m: position_ned_m.map(Some),
            velocity_ned_mps: [Some(0.0); 3],
            yaw_rad: None,
            accel_ned_mps2: [None; 3],
        }
    }
}

/// Kinematic limits of one vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Largest speed (3-D norm), m/s, already scaled by any speed-factor fault.
    pub max_speed_mps: f32,
    /// Largest acceleration (3-D norm), m/s².
    pub max_accel_mps2: f32,
}

/// The true physical state of a vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// Position, NED metres in the swarm's shared frame.
    pub position_ned_m: Vec3,
    /// Velocity, NED m/s.
    pub velocity_ned_mps: Vec3,
    /// Acceleration applied during the last step, NED m/s² (for attitude).
    pub accel_ned_mps2: Vec3,
    /// Heading, radians from north.
    pub yaw_rad: f32,
    /// Down coordinate of the ground under the vehicle.
    pub ground_down_m: f32,
}

impl Body {
    /// A vehicle resting on the ground at `position_ned_m`.
    pub fn on_ground(position_ned_m: Vec3) -> Self {
        Self {
            position_ned_m,
            velocity_ned_mps: [0.0; 3],
            accel_ned_mps2: [0.0; 3],
            yaw_rad: 0.0,
            ground_down_m: position_ned_m[2],
        }
    }

    /// Height above the ground, metres (positive up).
    pub fn height_m(&self) -> f32 {
        self.ground_down_m - self.position_ned_m[2]
    }

    /// Whether the vehicle touches the ground.
    pub fn in_ground_contact(&self) -> bool {
        self.height_m() <= GROUND_CONTACT_M
    }

    /// Touching the ground and (almost) still: what landed detection reports.
    pub fn is_resting(&self) -> bool {
        self.in_ground_contact() && norm(self.velocity_ned_mps) < LANDED_SPEED_MPS
    }

    /// Advances one fixed step of `dt_s` seconds. With `thrust` false (motors
    /// off) the vehicle falls under gravity until it hits the ground.
    pub fn step(&mut self, dt_s: f32, setpoint: &Setpoint, limits: &Limits, thrust: bool) {
        let accel = if thrust {
            let desired = desired_velocity(self, setpoint, limits);
            // First-order lag towards the desired velocity, then saturate.
            clamp_norm(
                std::array::from_fn(|i| (desired[i] - self.velocity_ned_mps[i]) / LAG_TAU_S),
                limits.max_accel_mps2,
            )
        } else {
            [0.0, 0.0, GRAVITY_MPS2]
        };
        let old_velocity = self.velocity_ned_mps;
        let mut velocity: Vec3 = std::array::from_fn(|i| old_velocity[i] + accel[i] * dt_s);
        if thrust {
            // Projection onto the speed ball is non-expansive, so this never
            // makes the step's velocity change larger than max_accel · dt.
            velocity = clamp_norm(velocity, limits.max_speed_mps);
        }
        let mut position: Vec3 = std::array::from_fn(|i| {
            self.position_ned_m[i] + 0.5 * (old_velocity[i] + velocity[i]) * dt_s
        });
        // Ground contact: the ground pushes back, nothing sinks through it.
        if position[2] > self.ground_down_m {
            position[2] = self.ground_down_m;
            if velocity[2] > 0.0 {
                velocity[2] = 0.0;
            }
            if !thrust {
                velocity = [0.0; 3];
            }
        }
        self.accel_ned_mps2 = std::array::from_fn(|i| (velocity[i] - old_velocity[i]) / dt_s);
        self.velocity_ned_mps = velocity;
        self.position_ned_m = position;
        if let Some(yaw) = setpoint.yaw_rad.filter(|y| y.is_finite()) {
            let max_step = std::f32::consts::FRAC_PI_2 * dt_s; // 90°/s yaw rate limit
            let error = wrap_pi(yaw - self.yaw_rad);
            self.yaw_rad = wrap_pi(self.yaw_rad + error.clamp(-max_step, max_step));
        }
    }
}

/// Velocity the position loop asks for: feed-forward plus a gain on the
/// position error, shaped so the vehicle can still stop within its
/// acceleration limit, capped at the speed limit.
///
/// Computed in f64: a target 1e30 m away is finite in f32, but its squared
/// distance is not, and f32 arithmetic would turn it into a NaN velocity.
fn desired_velocity(body: &Body, setpoint: &Setpoint, limits: &Limits) -> Vec3 {
    let mut error = [0.0f64; 3];
    let mut feed_forward = [0.0f64; 3];
    for i in 0..3 {
        if let Some(target) = setpoint.position_ned_m[i].filter(|v| v.is_finite()) {
            error[i] = f64::from(target) - f64::from(body.position_ned_m[i]);
        }
        if let Some(v) = setpoint.velocity_ned_mps[i].filter(|v| v.is_finite()) {
            feed_forward[i] = f64::from(v);
        }
        if let Some(a) = setpoint.accel_ned_mps2[i].filter(|a| a.is_finite()) {
            // Leading the first-order lag by its time constant cancels it.
            feed_forward[i] += f64::from(LAG_TAU_S) * f64::from(a);
        }
    }
    let distance_m = norm_f64(error);
    let mut correction = [0.0f64; 3];
    if distance_m > 1e-6 {
        // sqrt(2·(a/2)·d): the speed from which it can brake in d metres using
        // half its acceleration, leaving margin for the lag.
        let braking_mps = (f64::from(limits.max_accel_mps2) * distance_m).sqrt();
        let speed_mps = (f64::from(POSITION_GAIN_PER_S) * distance_m).min(braking_mps);
        correction = error.map(|e| e / distance_m * speed_mps);
    }
    let desired: [f64; 3] = std::array::from_fn(|i| feed_forward[i] + correction[i]);
    let scale = clamp_scale(norm_f64(desired), limits.max_speed_mps);
    desired.map(|c| (c * scale) as f32)
}

/// Euclidean norm of a 3-vector, computed in f64 so squaring a large but
/// finite component cannot overflow (the result is +∞ only if the norm
/// itself exceeds `f32::MAX`).
pub fn norm(v: Vec3) -> f32 {
    norm_f64(v.map(f64::from)) as f32
}

fn norm_f64(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Factor that scales a vector of norm `n` down to at most `limit` (1 if it is within).
fn clamp_scale(n: f64, limit: f32) -> f64 {
    let limit = f64::from(limit);
    if n > limit && n > 0.0 { limit / n } else { 1.0 }
}

/// `v` scaled down, if needed, so its norm is at most `limit`.
fn clamp_norm(v: Vec3, limit: f32) -> Vec3 {
    let v64 = v.map(f64::from);
    let scale = clamp_scale(norm_f64(v64), limit);
    if scale < 1.0 {
        v64.map(|c| (c * scale) as f32)
    } else {
        v
    }
}

/// Angle wrapped to (-π, π].
fn wrap_pi(angle_rad: f32) -> f32 {
    let two_pi = std::f32::consts::TAU;
    let mut a = angle_rad % two_pi;
    if a > std::f32::consts::PI {
        a -= two_pi;
    } else if a <= -std::f32::consts::PI {
        a += two_pi;
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT_S: f32 = 0.01;

    fn limits() -> Limits {
        Limits {
            max_speed_mps: 2.0,
            max_accel_mps2: 3.0,
        }
    }

    fn airborne() -> Body {
        let mut b = Body::on_ground([0.0, 0.0, 0.0]);
        b.position_ned_m[2] = -5.0;
        b
    }

    #[test]
    fn speed_and_acceleration_limits_are_never_exceeded() {
        let mut body = airborne();
        let targets = [
            [30.0, 0.0, -5.0],
            [30.0, 40.0, -20.0],
            [-10.0, -10.0, -2.0],
            [0.0, 0.0, -5.0],
        ];
        for target in targets {
            let sp = Setpoint::hold(target);
            for _ in 0..6000 {
                let before = body.velocity_ned_mps;
                body.step(DT_S, &sp, &limits(), true);
                let dv: Vec3 = std::array::from_fn(|i| body.velocity_ned_mps[i] - before[i]);
                assert!(
                    norm(body.velocity_ned_mps) <= 2.0 + 1e-4,
                    "speed {:?}",
                    body.velocity_ned_mps
                );
                assert!(norm(dv) <= 3.0 * DT_S + 1e-4, "accel {}", norm(dv) / DT_S);
            }
            let err: Vec3 = std::array::from_fn(|i| body.position_ned_m[i] - target[i]);
            assert!(
                norm(err) < 0.05,
                "did not converge to {target:?}: {:?}",
                body.position_ned_m
            );
        }
    }

    #[test]
    fn velocity_feed_forward_lags_first_order() {
        let mut body = airborne();
        let sp = Setpoint {
            position_ned_m: [None; 3],
            velocity_ned_mps: [Some(1.0), Some(0.0), Some(0.0)],
            yaw_rad: None,
            accel_ned_mps2: [None; 3],
        };
        // After one time constant a first-order lag reaches 1 - 1/e ≈ 63 %.
        let steps = (LAG_TAU_S / DT_S).round() as usize;
        for _ in 0..steps {
            body.step(
                DT_S,
                &sp,
                &Limits {
                    max_speed_mps: 5.0,
                    max_accel_mps2: 50.0,
                },
                true,
            );
        }
        let v = body.velocity_ned_mps[0];
        assert!((0.58..0.68).contains(&v), "v after tau = {v}");
    }

    #[test]
    fn type_mask_ignored_axes_are_not_tracked() {
        let mut body = airborne();
        let sp = Setpoint {
            position_ned_m: [Some(3.0), None, None],
            velocity_ned_mps: [None; 3],
            yaw_rad: None,
            accel_ned_mps2: [None; 3],
        };
        for _ in 0..1000 {
            body.step(DT_S, &sp, &limits(), true);
        }
        assert!((body.position_ned_m[0] - 3.0).abs() < 0.05);
        assert!(body.position_ned_m[1].abs() < 1e-6);
        assert!((body.position_ned_m[2] + 5.0).abs() < 1e-6);
    }

    #[test]
    fn motors_off_falls_and_rests_on_ground() {
        let mut body = airborne();
        assert!(!body.is_resting());
        for _ in 0..300 {
            body.step(DT_S, &Setpoint::default(), &limits(), false);
        }
        assert_eq!(body.position_ned_m[2], 0.0);
        assert!(body.is_resting());
    }

    #[test]
    fn descending_setpoint_below_ground_lands_without_sinking() {
        let mut body = airborne();
        let sp = Setpoint::hold([0.0, 0.0, 3.0]);
        let mut touched = false;
        for _ in 0..2000 {
            body.step(DT_S, &sp, &limits(), true);
            assert!(body.position_ned_m[2] <= 0.0);
            touched |= body.is_resting();
        }
        assert!(touched);
    }

    #[test]
    fn yaw_turns_at_limited_rate_and_wraps() {
        let mut body = airborne();
        let sp = Setpoint {
            yaw_rad: Some(3.0),
            ..Setpoint::hold([0.0, 0.0, -5.0])
        };
        body.step(DT_S, &sp, &limits(), true);
        assert!((body.yaw_rad - std::f32::consts::FRAC_PI_2 * DT_S).abs() < 1e-6);
        assert!((wrap_pi(3.5) - (3.5 - std::f32::consts::TAU)).abs() < 1e-6);
    }

    #[test]
    fn huge_but_finite_targets_stay_finite() {
        // Found by the receive-path fuzzer: a setpoint 1e30 m away made the
        // f32 squared distance overflow and the velocity NaN.
        for target in [
            [0.0, 1e30, -3.0],
            [f32::MAX, f32::MAX, f32::MIN],
            [-3e38, 0.0, 0.0],
        ] {
            let mut body = airborne();
            let sp = Setpoint {
                velocity_ned_mps: [Some(f32::MAX), Some(1.0), Some(-720.0)],
                ..Setpoint::hold(target)
            };
            for _ in 0..500 {
                body.step(DT_S, &sp, &limits(), true);
                let all = body.position_ned_m.iter().chain(&body.velocity_ned_mps);
                assert!(all.copied().all(f32::is_finite), "{body:?}");
                assert!(norm(body.velocity_ned_mps) <= 2.0 + 1e-4);
            }
        }
        assert_eq!(norm([3e38, 3e38, 0.0]), f32::INFINITY);
        assert_eq!(norm([3e20, 4e20, 0.0]), 5e20);
    }
}
