//! The commanded motion of one drone: its route, run by run, stopping short of
//! any event whose TPG predecessors have not been observed yet.
//!
//! The motion is a continuous function of time built from three pieces, each
//! within the speed and acceleration limits: *rest*, a rest-to-rest trapezoidal
//! *run* (the scheduler's own profile), and a *brake* at full deceleration. A
//! drone starts a run only at rest, and while moving it checks every tick that
//! braking one tick from now would still stop before the first closed gate; if
//! not, it brakes now. Because gates only ever open, the check made at the
//! previous tick stays valid, so a stop is always possible in time and no
//! commanded setpoint needs more than `max_accel`. A drone stopped mid-run by a
//! gate resumes with a fresh rest-to-rest profile over the rest of the run.

use super::path::Route;
use crate::trajectory::Profile;

/// Stop this far short of a closed gate's marker.
pub const STOP_MARGIN_M: f64 = 0.01;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Motion {
    /// At rest `x_m` along the current run.
    Rest { x_m: f64 },
    /// Following `profile` from `x0_m`, started at `t0_s`.
    Moving {
        x0_m: f64,
        profile: Profile,
        t0_s: f64,
    },
    /// Braking at full deceleration from speed `v0_mps` at `x0_m`, started at `t0_s`.
    Braking { x0_m: f64, v0_mps: f64, t0_s: f64 },
}

/// Why a drone is not moving right now (for the status view and the log).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Hold {
    /// Not holding: moving, or done.
    None,
    /// Its next run is not due yet (scheduled rest).
    Schedule,
    /// Waiting for its own telemetry to settle at the rest point (a slow drone).
    Settling,
    /// A TPG gate is closed ahead.
    Gate,
    /// The vehicle is further from its setpoint than the mission's tracking error:
    /// the setpoint waits for it.
    Tracking,
}

/// One commanded setpoint, ENU.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setpoint {
    /// Where the drone should be, ENU metres.
    pub position_m: [f64; 3],
    /// How fast it should move there, ENU metres per second (feed-forward).
    pub velocity_mps: [f64; 3],
    /// How it should be accelerating, ENU m/s² (feed-forward: the profile's
    /// acceleration, so the vehicle's controller need not lag to build it up).
    pub acceleration_mps2: [f64; 3],
}

impl Setpoint {
    /// At rest at `position_m`.
    pub fn rest(position_m: [f64; 3]) -> Self {
        Self {
            position_m,
            velocity_mps: [0.0; 3],
            acceleration_mps2: [0.0; 3],
        }
    }
}

/// The commanded motion of one drone along its route.
#[derive(Debug, Clone)]
pub struct Follower {
    max_speed_mps: f64,
    max_accel_mps2: f64,
    /// Index of the current run; `runs.len()` when the route is finished.
    run: usize,
    motion: Motion,
    /// Braking from the commanded state at this time is known to stop in time.
    validated_until_s: f64,
    /// Stop as soon as possible and stay (Ctrl-C, mission timeout).
    halted: bool,
    /// Stop as soon as possible until unpaused (telemetry or link lost: the
    /// commanded target must not run away from a vehicle we cannot see).
    paused: bool,
    /// The vehicle strays from its setpoint: the setpoint brakes and waits, as when
    /// paused, until the vehicle is back (see [`Follower::hold_for_tracking`]).
    tracking_hold: bool,
    /// Why it is not moving this tick, for gate-wait counting and the status view.
    pub hold: Hold,
}

impl Follower {
    /// At rest at the start of the route, within the mission's speed (m/s) and
    /// acceleration (m/s²) limits.
    pub fn new(max_speed_mps: f64, max_accel_mps2: f64) -> Self {
        Self {
            max_speed_mps,
            max_accel_mps2,
            run: 0,
            motion: Motion::Rest { x_m: 0.0 },
            validated_until_s: 0.0,
            halted: false,
            paused: false,
            tracking_hold: false,
            hold: Hold::Schedule,
        }
    }

    /// The acceleration limit it keeps, m/s².
    pub fn max_accel_mps2(&self) -> f64 {
        self.max_accel_mps2
    }

    /// True once the last run is finished (commanded; telemetry may still lag).
    pub fn finished(&self, route: &Route) -> bool {
        self.run >= route.runs.len()
    }

    /// Commanded arc length along the route.
    pub fn arc_m(&self, route: &Route, t_s: f64) -> f64 {
        match route.runs.get(self.run) {
            None => route.length_m(),
            Some(r) => r.arc_start_m + self.state_at(t_s).0,
        }
    }

    /// The run the follower is on (or `runs.len()` when done).
    pub fn run_index(&self) -> usize {
        self.run
    }

    /// Brake to a stop and stay there (used for Ctrl-C and timeouts).
    pub fn halt(&mut self) {
        self.halted = true;
    }

    /// Brake to a stop and wait while `paused`; resume (from rest, once the
    /// telemetry has settled at the rest point) when it clears.
    pub fn set_paused(&mut self, paused: bool) {
        self.paused = paused;
    }

    /// While `straying` (the vehicle is further from its setpoint than the tracking
    /// error it is trusted to keep), the setpoint brakes to a stop within the
    /// acceleration limit and waits there, on the scheduled path and short of any
    /// closed gate, as for a pause. (Stopping it dead instead made ArduCopter, still
    /// moving, overshoot by most of a metre and swing back.) The run resumes from
    /// rest once the vehicle has settled there.
    pub fn hold_for_tracking(&mut self, straying: bool) {
        self.tracking_hold = straying;
    }

    /// The setpoint is held for the vehicle to come back within the tracking error.
    pub fn holding_for_tracking(&self) -> bool {
        self.tracking_hold
    }

    /// True when the commanded motion is at rest.
    pub fn at_rest(&self) -> bool {
        matches!(self.motion, Motion::Rest { .. })
    }

    /// Signed acceleration along the current run at `t_s`, for the current motion.
    fn accel_at(&self, t_s: f64) -> f64 {
        match self.motion {
            Motion::Rest { .. } => 0.0,
            Motion::Moving { profile, t0_s, .. } => profile.accel_at_mps2(t_s - t0_s),
            Motion::Braking { v0_mps, t0_s, .. } => {
                let tau = t_s - t0_s;
                if tau >= 0.0 && tau < v0_mps / self.max_accel_mps2 {
                    -self.max_accel_mps2
                } else {
                    0.0
                }
            }
        }
    }

    /// Position along the current run and speed at `t_s`, for the current motion.
    fn state_at(&self, t_s: f64) -> (f64, f64) {
        match self.motion {
            Motion::Rest { x_m } => (x_m, 0.0),
            Motion::Moving {
                x0_m,
                profile,
                t0_s,
            } => {
                let tau = t_s - t0_s;
                (x0_m + profile.distance_at_m(tau), profile.speed_at_mps(tau))
            }
            Motion::Braking { x0_m, v0_mps, t0_s } => {
                let a = self.max_accel_mps2;
                let tau = (t_s - t0_s).clamp(0.0, v0_mps / a);
                (x0_m + v0_mps * tau - 0.5 * a * tau * tau, v0_mps - a * tau)
            }
        }
    }

    /// Advances the commanded motion to mission time `t_s` and returns the setpoint.
    ///
    /// `gate_arc_m` is the arc length of the first closed gate ahead (∞ if none);
    /// `settled` says the drone's telemetry is at its commanded rest point, which a
    /// new run requires so a lagging drone never has its target run away from it.
    /// `dt_s` is the setpoint period: braking is decided one period ahead.
    pub fn step(
        &mut self,
        route: &Route,
        t_s: f64,
        dt_s: f64,
        gate_arc_m: f64,
        settled: bool,
    ) -> Setpoint {
        let a = self.max_accel_mps2;
        // A handful of transitions at most happen in one tick (finish a run, start the next).
        for _ in 0..4 {
            let Some(run) = route.runs.get(self.run) else {
                self.hold = Hold::None;
                break;
            };
            let limit_x_m = gate_arc_m - run.arc_start_m - STOP_MARGIN_M;
            match self.motion {
                Motion::Rest { x_m } => {
                    if x_m >= run.length_m - 1e-9 {
                        self.run += 1;
                        self.motion = Motion::Rest { x_m: 0.0 };
                        continue;
                    }
                    self.hold = if self.halted || self.paused {
                        Hold::Gate
                    } else if self.tracking_hold {
                        Hold::Tracking
                    } else if x_m <= 0.0 && t_s < run.scheduled_start_s {
                        Hold::Schedule
                    } else if !settled {
                        Hold::Settling
                    } else if limit_x_m - x_m < a * dt_s * dt_s + 1e-9 {
                        // Starting would already need braking within one period.
                        Hold::Gate
                    } else {
                        Hold::None
                    };
                    if self.hold != Hold::None {
                        break;
                    }
                    self.motion = Motion::Moving {
                        x0_m: x_m,
                        profile: Profile::new(run.length_m - x_m, self.max_speed_mps, a),
                        t0_s: t_s,
                    };
                    self.validated_until_s = t_s;
                }
                Motion::Moving {
                    x0_m,
                    profile,
                    t0_s,
                } => {
                    self.hold = Hold::None;
                    if t_s - t0_s >= profile.duration_s() {
                        self.motion = Motion::Rest {
                            x_m: x0_m + profile.length_m,
                        };
                        continue;
                    }
                    let (x_next, v_next) = self.state_at(t_s + dt_s);
                    let stop_next_m = x_next + v_next * v_next / (2.0 * a);
                    if self.halted || self.paused || self.tracking_hold || stop_next_m > limit_x_m {
                        // Braking from any earlier state stops no later (the stop point
                        // only grows along a profile), so the last validated time is safe.
                        let t_brake = t_s.min(self.validated_until_s);
                        let (x0_m, v0_mps) = self.state_at(t_brake);
                        self.motion = Motion::Braking {
                            x0_m,
                            v0_mps,
                            t0_s: t_brake,
                        };
                        continue;
                    }
                    self.validated_until_s = t_s + dt_s;
                    break;
                }
                Motion::Braking { x0_m, v0_mps, t0_s } => {
                    self.hold = Hold::Gate;
                    if t_s - t0_s >= v0_mps / a {
                        self.motion = Motion::Rest {
                            x_m: x0_m + v0_mps * v0_mps / (2.0 * a),
                        };
                        continue;
                    }
                    break;
                }
            }
        }
        self.setpoint(route, t_s)
    }

    /// The commanded position and velocity at `t_s` (ENU).
    pub fn setpoint(&self, route: &Route, t_s: f64) -> Setpoint {
        match route.runs.get(self.run) {
            None => Setpoint::rest(route.goal_m()),
            Some(run) => {
                let (x, v) = self.state_at(t_s);
                let a = self.accel_at(t_s);
                let u = run.unit();
                Setpoint {
                    position_m: run.point_m(x),
                    velocity_mps: u.map(|c| c * v),
                    acceleration_mps2: u.map(|c| c * a),
                }
            }
        }
    }
}
