//! The commanded motion of one drone: its route, run by run, stopping short of
//! any event whose TPG predecessors have not been observed yet.
//!
//! The motion is a continuous function of time built from three pieces, each
//! within the speed, acceleration and jerk limits: *rest*, a rest-to-rest S-curve
//! *run* (the scheduler's own profile), and the shortest *brake* those limits allow.
//! A drone starts a run only at rest, and while moving it checks every tick that
//! braking one tick from now would still stop before the first closed gate; if
//! not, it brakes now. Because gates only ever open, the check made at the
//! previous tick stays valid, so a stop is always possible in time and no
//! commanded setpoint breaks a limit (the acceleration never jumps, so an
//! autopilot that shapes its target with a jerk limit can follow it exactly). A
//! drone braking for a gate that opens before it has stopped picks up again from
//! the state it is in ([`Resume`]), as soon as flying on from there would pass the
//! same check; one that did stop starts over with a rest-to-rest profile.

use super::course::Course;
use super::gate::GateAhead;
use super::gate_limits::GateLimits;
use super::path::{Route, RouteRun};
use crate::profile::{Brake, Kinematics, Profile, Resume, State};

#[derive(Debug, Clone, Copy, PartialEq)]
enum Motion {
    /// At rest `x_m` along the current run.
    Rest { x_m: f64 },
    /// Following `course` from `x0_m`, started at `t0_s`.
    Moving {
        x0_m: f64,
        course: Course,
        t0_s: f64,
    },
    /// Braking to a stop (positions along the current run), started at `t0_s`;
    /// `for_gate` when a gate ahead was all that made it brake (then it may pick
    /// up again before it stops; a halt, pause or straying vehicle stops first).
    Braking {
        brake: Brake,
        t0_s: f64,
        for_gate: bool,
    },
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
    limits: Kinematics,
    /// The acceleration feed-forward is that of this much later, seconds, so the
    /// vehicle's attitude lag does not make it trail (see
    /// `fly::vehicle_limits::accel_lead_s`).
    accel_lead_s: f64,
    /// Index of the current run; `runs.len()` when the route is finished.
    run: usize,
    motion: Motion,
    /// Braking from the commanded state at this time is known to stop in time.
    validated_until_s: f64,
    /// When the current rest began (the motion before it ended), seconds.
    rest_since_s: f64,
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
    /// The hold was a halt or pause (reported as [`Hold::Gate`] too), not a gate.
    hold_is_pause: bool,
}

impl Follower {
    /// At rest at the start of the route, within the mission's kinematic limits,
    /// sending its acceleration feed-forward `accel_lead_s` ahead of the motion.
    pub fn new(limits: Kinematics, accel_lead_s: f64) -> Self {
        Self {
            limits,
            accel_lead_s,
            run: 0,
            motion: Motion::Rest { x_m: 0.0 },
            validated_until_s: 0.0,
            rest_since_s: f64::NEG_INFINITY,
            halted: false,
            paused: false,
            tracking_hold: false,
            hold: Hold::Schedule,
            hold_is_pause: false,
        }
    }

    /// A follower with the same limits and lead, at rest at the start of a new
    /// route (a replan's).
    pub fn restarted(&self) -> Self {
        Self::new(self.limits, self.accel_lead_s)
    }

    /// The kinematic limits it keeps.
    pub fn limits(&self) -> Kinematics {
        self.limits
    }

    /// True once the last run is finished (commanded; telemetry may still lag).
    pub fn finished(&self, route: &Route) -> bool {
        self.run >= route.runs.len()
    }

    /// Commanded arc length along the route.
    pub fn arc_m(&self, route: &Route, t_s: f64) -> f64 {
        match route.runs.get(self.run) {
            None => route.length_m(),
            Some(r) => r.arc_start_m + self.state_at(t_s).x_m,
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

    /// The latest plan-clock time the setpoint passes `arc_m` along `route`, if it
    /// is committed to: on the current run and no further than braking now would
    /// stop. Braking now is the slowest the setpoint can go from here (a gate, a
    /// halt or a pause brakes from the last validated state, and a profile flown on
    /// and braked later is ahead of it at every moment), so it passes `arc_m` by
    /// then whatever happens; `None` when at rest short of it or past where it
    /// could stop. A brake that stops within `schedule::COMMIT_TOLERANCE_M` short of it counts
    /// (a run coming to rest at the event brakes exactly as hard, and rounding puts
    /// its stop either side).
    pub fn latest_pass_s(&self, route: &Route, arc_m: f64, t_s: f64) -> Option<f64> {
        let run = route.runs.get(self.run)?;
        let x_m = arc_m - run.arc_start_m - crate::schedule::COMMIT_TOLERANCE_M;
        let (brake, t0_s) = match self.motion {
            Motion::Rest { x_m: at_m } => return (x_m <= at_m).then_some(t_s),
            Motion::Moving { .. } => {
                let t_brake = t_s.min(self.validated_until_s);
                (Brake::new(self.state_at(t_brake), self.limits), t_brake)
            }
            Motion::Braking { brake, t0_s, .. } => (brake, t0_s),
        };
        brake.time_to_pass_s(x_m).map(|after_s| t0_s + after_s)
    }

    /// Position along the current run, speed and acceleration at `t_s`, for the
    /// current motion.
    fn state_at(&self, t_s: f64) -> State {
        match self.motion {
            Motion::Rest { x_m } => State::rest(x_m),
            Motion::Moving { x0_m, course, t0_s } => {
                let s = course.state_at(t_s - t0_s);
                State {
                    x_m: x0_m + s.x_m,
                    ..s
                }
            }
            Motion::Braking { brake, t0_s, .. } => brake.state_at(t_s - t0_s),
        }
    }

    /// Advances the commanded motion to mission time `t_s` and returns the setpoint.
    ///
    /// `gate` gives the closed gates ahead: the drone stops short of the first
    /// unless every closed gate before `gate.hard_arc_m` opens by
    /// `gate.opens_by_s` and its setpoint, on its present motion, reaches the first
    /// no earlier than that (it can only be slower: see [`Follower::latest_pass_s`]
    /// for the other side); `settled` says the drone's telemetry is at its commanded rest point, which a
    /// new run requires so a lagging drone never has its target run away from it.
    /// `dt_s` is the setpoint period: braking is decided one period ahead.
    pub fn step(
        &mut self,
        route: &Route,
        t_s: f64,
        dt_s: f64,
        gate: GateAhead,
        settled: bool,
    ) -> Setpoint {
        // Held last tick by the vehicle (settling, straying) or a pause, which this
        // tick's observations cleared: a run starts now, from where the vehicle is.
        // Otherwise it was only due (its scheduled start, the end of the motion
        // before it, or its gate's opening, observed this tick) at some moment since
        // the last tick, and starts then — see `start_s`.
        let held_by_observation = match self.hold {
            Hold::None | Hold::Schedule => false,
            Hold::Gate => self.hold_is_pause,
            Hold::Settling | Hold::Tracking => true,
        };
        self.hold_is_pause = self.halted || self.paused;
        // A handful of transitions at most happen in one tick (finish a run, start the next).
        for _ in 0..4 {
            let Some(run) = route.runs.get(self.run) else {
                self.hold = Hold::None;
                break;
            };
            let limits = GateLimits::on(run, gate);
            match self.motion {
                Motion::Rest { x_m } => {
                    if x_m >= run.length_m - 1e-9 {
                        self.run += 1;
                        self.motion = Motion::Rest { x_m: 0.0 };
                        continue;
                    }
                    let t0_s = if held_by_observation {
                        t_s
                    } else {
                        let due_s = if x_m <= 0.0 {
                            run.scheduled_start_s
                        } else {
                            f64::NEG_INFINITY
                        };
                        start_s(t_s, dt_s, due_s.max(self.rest_since_s))
                    };
                    // The run flies the very course its start was checked on.
                    let course = Course::Planned(Profile::new(run.length_m - x_m, self.limits));
                    self.hold =
                        self.start_hold(run, (x_m, course, t0_s), (t_s, dt_s), limits, settled);
                    if self.hold != Hold::None {
                        break;
                    }
                    self.motion = Motion::Moving {
                        x0_m: x_m,
                        course,
                        t0_s,
                    };
                    self.validated_until_s = t_s;
                }
                Motion::Moving { x0_m, course, t0_s } => {
                    self.hold = Hold::None;
                    if t_s - t0_s >= course.duration_s() {
                        self.motion = Motion::Rest {
                            x_m: x0_m + course.length_m(),
                        };
                        self.rest_since_s = t0_s + course.duration_s();
                        continue;
                    }
                    let held = self.halted || self.paused || self.tracking_hold;
                    if held || limits.must_brake((x0_m, course, t0_s), (t_s, dt_s), self.limits) {
                        // Braking from any earlier state stops no later (the stop point
                        // only grows along a profile), so the last validated time is safe.
                        let t_brake = t_s.min(self.validated_until_s);
                        self.motion = Motion::Braking {
                            brake: Brake::new(self.state_at(t_brake), self.limits),
                            t0_s: t_brake,
                            for_gate: !held,
                        };
                        continue;
                    }
                    self.validated_until_s = t_s + dt_s;
                    break;
                }
                Motion::Braking {
                    brake,
                    t0_s,
                    for_gate,
                } => {
                    self.hold = Hold::Gate;
                    if t_s - t0_s >= brake.duration_s() {
                        self.motion = Motion::Rest {
                            x_m: brake.stop_m(),
                        };
                        self.rest_since_s = t0_s + brake.duration_s();
                        continue;
                    }
                    if !for_gate {
                        break;
                    }
                    if let Some(resumed) =
                        self.resume(run, brake.state_at(t_s - t0_s), (t_s, dt_s), limits)
                    {
                        self.hold = Hold::None;
                        self.motion = resumed;
                        self.validated_until_s = t_s + dt_s;
                    }
                    break;
                }
            }
        }
        self.setpoint(route, t_s)
    }

    /// The motion that picks a braking drone up again at tick `t_s` from `now` (on
    /// the brake, metres along `run`), if nothing but a gate holds it and flying on
    /// from there passes the same check a moving drone passes every tick; `None`
    /// keeps braking. Resuming brakes no harder than the brake it replaces would
    /// (the brake is the shortest stop), so it only ever goes further along.
    fn resume(
        &self,
        run: &RouteRun,
        now: State,
        (t_s, dt_s): (f64, f64),
        limits: GateLimits,
    ) -> Option<Motion> {
        if self.halted || self.paused || self.tracking_hold {
            return None;
        }
        let resume = Resume::new(
            State { x_m: 0.0, ..now },
            run.length_m - now.x_m,
            self.limits,
        )?;
        let course = Course::Resumed(resume);
        (!limits.must_brake((now.x_m, course, t_s), (t_s, dt_s), self.limits)).then_some(
            Motion::Moving {
                x0_m: now.x_m,
                course,
                t0_s: t_s,
            },
        )
    }

    /// Why `run` cannot start at tick `t_s` from rest `x_m` on `course` (which
    /// would begin at `t0_s`, `dt_s` being the period), or [`Hold::None`]. A run
    /// starts only when the check a moving drone passes every tick passes for it
    /// at once: starting and braking on the same tick would only creep.
    fn start_hold(
        &self,
        run: &RouteRun,
        (x_m, course, t0_s): (f64, Course, f64),
        (t_s, dt_s): (f64, f64),
        limits: GateLimits,
        settled: bool,
    ) -> Hold {
        if self.halted || self.paused {
            Hold::Gate
        } else if self.tracking_hold {
            Hold::Tracking
        } else if x_m <= 0.0 && t_s < run.scheduled_start_s {
            Hold::Schedule
        } else if !settled {
            Hold::Settling
        } else if limits.must_brake((x_m, course, t0_s), (t_s, dt_s), self.limits) {
            // A gate ahead not committed to open, or committed but reached first.
            Hold::Gate
        } else {
            Hold::None
        }
    }

    /// The commanded position and velocity at `t_s`, and the acceleration of the
    /// current motion at `t_s` plus the lead (ENU). Only the current motion is
    /// known, so at a run's start the led acceleration begins at that of the lead
    /// time (a step of jerk × lead), and a brake decided later takes over from it.
    pub fn setpoint(&self, route: &Route, t_s: f64) -> Setpoint {
        match route.runs.get(self.run) {
            None => Setpoint::rest(route.goal_m()),
            Some(run) => {
                let s = self.state_at(t_s);
                let led = self.state_at(t_s + self.accel_lead_s);
                let u = run.unit();
                Setpoint {
                    position_m: run.point_m(s.x_m),
                    velocity_mps: u.map(|c| c * s.v_mps),
                    acceleration_mps2: u.map(|c| c * led.a_mps2),
                }
            }
        }
    }
}

/// When a run that became due at `due_s` starts, seen at the tick `t_s` (the
/// previous one `dt_s` earlier): at `due_s` if that was since the previous tick,
/// so a run waits for nothing but its schedule and a drone on time stays on time
/// instead of losing up to a tick at every run; never before the previous tick.
/// The profile begins at rest with its jerk, so starting it up to a tick in the
/// past moves the first setpoint by at most `jerk · dt³ / 6` and its acceleration
/// by at most `jerk · dt`: what the jerk limit allows over one tick. A run held by
/// a gate that opened since the last tick starts the same way: the setpoint is
/// streamed only now, after the opening was observed, and lies those
/// `jerk · dt³ / 6` (0.05 mm at 2.5 m/s³ and 20 Hz) from the rest point.
fn start_s(t_s: f64, dt_s: f64, due_s: f64) -> f64 {
    due_s.clamp(t_s - dt_s, t_s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::gate_limits::STOP_MARGIN_M;
    use crate::fly::path::{RouteRun, distance_m};

    const LIMITS: Kinematics = Kinematics {
        max_speed_mps: 1.0,
        max_accel_mps2: 1.0,
        max_jerk_mps3: 2.5,
    };

    /// Straight runs along x, each starting when scheduled (`(length, start)`).
    fn route(runs: &[(f64, f64)]) -> Route {
        let mut arc_m = 0.0;
        let runs = runs
            .iter()
            .map(|&(length_m, scheduled_start_s)| {
                let run = RouteRun {
                    from_m: [arc_m, 0.0, 0.0],
                    to_m: [arc_m + length_m, 0.0, 0.0],
                    length_m,
                    arc_start_m: arc_m,
                    scheduled_start_s,
                    profile: Profile::new(length_m, LIMITS),
                };
                arc_m += length_m;
                run
            })
            .collect();
        Route {
            id: "a".into(),
            start_m: [0.0; 3],
            runs,
            events: Vec::new(),
        }
    }

    /// With nothing to wait for, the follower flies the schedule itself: at every
    /// tick its setpoint is where the schedule puts the drone (runs back to back,
    /// and a run due between two ticks), never a tick behind per run; and from one
    /// tick to the next its acceleration changes by at most what the jerk limit
    /// allows over a tick.
    #[test]
    fn a_drone_with_nothing_to_wait_for_keeps_the_schedule_to_the_tick() {
        let one = Profile::new(1.0, LIMITS).duration_s();
        // Three back-to-back runs, a rest, then a run due between two ticks.
        let r = route(&[
            (1.0, 0.0),
            (1.0, one),
            (1.0, 2.0 * one),
            (1.0, 3.0 * one + 1.013),
        ]);
        let dt_s = 0.05;
        let mut f = Follower::new(LIMITS, 0.0);
        let mut last_a = 0.0;
        for k in 0..=(((4.0 * one + 1.2) / dt_s) as usize) {
            let t_s = k as f64 * dt_s;
            let s = f.step(&r, t_s, dt_s, GateAhead::OPEN, true);
            let scheduled = r.scheduled_arc_m(t_s);
            let flown = f.arc_m(&r, t_s);
            assert!(
                (flown - scheduled).abs() < 1e-9,
                "t {t_s:.2} s: flown {flown:.6} m, scheduled {scheduled:.6} m"
            );
            assert!(distance_m(s.velocity_mps, [0.0; 3]) <= LIMITS.max_speed_mps + 1e-9);
            let a = s.acceleration_mps2[0];
            assert!(
                (a - last_a).abs() <= LIMITS.max_jerk_mps3 * dt_s + 1e-9,
                "t {t_s:.2} s: acceleration {last_a:.4} → {a:.4} m/s²"
            );
            last_a = a;
        }
        assert!(f.finished(&r));
    }

    /// A run held by a closed gate starts when the gate opens: the setpoint never
    /// moves while its gate is closed, and the tick the opening is seen it is
    /// started up to one tick back (as a run due between ticks is), so it is no
    /// further along than the jerk allows in a tick.
    #[test]
    fn a_run_held_at_a_gate_starts_only_once_it_opens() {
        let r = route(&[(1.0, 0.0)]);
        let dt_s = 0.05;
        let mut f = Follower::new(LIMITS, 0.0);
        for k in 0..10 {
            let t_s = k as f64 * dt_s;
            f.step(&r, t_s, dt_s, GateAhead::closed_at(0.005), true);
            assert_eq!(f.arc_m(&r, t_s), 0.0);
            assert_eq!(f.hold, Hold::Gate);
        }
        let t_s = 10.0 * dt_s;
        f.step(&r, t_s, dt_s, GateAhead::OPEN, true);
        let first_m = f.arc_m(&r, t_s);
        let one_tick_m = LIMITS.max_jerk_mps3 * dt_s.powi(3) / 6.0;
        assert!(
            first_m > 0.0 && first_m <= one_tick_m + 1e-12,
            "started a tick back, from rest: {first_m} m"
        );
        let later = f.arc_m(&r, t_s + dt_s);
        assert!(later > 0.0);
    }

    /// A gate right at a run's end (the event of leaving the point the schedule
    /// holds the drone at) lets the run end there, at rest, and holds the next
    /// run until it opens; a gate inside a run is stopped short of by the margin.
    #[test]
    fn a_gate_at_a_runs_end_is_waited_for_at_that_point() {
        let r = route(&[(1.0, 0.0), (1.0, 0.0)]);
        let dt_s = 0.05;
        let rest_at = |gate: GateAhead| {
            let mut f = Follower::new(LIMITS, 0.0);
            for k in 0..100 {
                f.step(&r, k as f64 * dt_s, dt_s, gate, true);
            }
            f.arc_m(&r, 100.0 * dt_s)
        };
        assert_eq!(rest_at(GateAhead::closed_at(1.0)), 1.0);
        let short_m = rest_at(GateAhead::closed_at(1.5));
        assert!(
            short_m <= 1.5 - STOP_MARGIN_M + 1e-9 && short_m > 1.4,
            "{short_m}"
        );
    }

    /// A gate mid-run whose predecessor is committed to open it in time is flown
    /// through at speed; one that would open after the drone reached it is not
    /// reached before it opens, and one not committed at all is stopped short of.
    #[test]
    fn a_committed_gate_is_flown_through_only_if_it_opens_before_the_drone_arrives() {
        let r = route(&[(4.0, 0.0)]);
        let gate_at_m = 2.0;
        let arrival_s = r.runs[0].profile.time_at_distance_s(gate_at_m);
        let dt_s = 0.05;
        // The plan-clock time the setpoint first reached the gate (∞: never).
        let reached_s = |opens_by_s: f64, hard_arc_m: f64| {
            let gate = GateAhead {
                arc_m: gate_at_m,
                hard_arc_m,
                opens_by_s,
            };
            let mut f = Follower::new(LIMITS, 0.0);
            for k in 0..200 {
                let t_s = k as f64 * dt_s;
                f.step(&r, t_s, dt_s, gate, true);
                if f.arc_m(&r, t_s) >= gate_at_m {
                    return t_s;
                }
            }
            f64::INFINITY
        };
        let through_s = reached_s(arrival_s - 0.1, f64::INFINITY);
        assert!((through_s - arrival_s).abs() <= dt_s, "through at speed");
        let late_s = reached_s(arrival_s + 0.5, f64::INFINITY);
        assert!(
            late_s.is_finite() && late_s >= arrival_s + 0.5,
            "waited: {late_s}"
        );
        assert!(
            reached_s(arrival_s - 0.1, gate_at_m).is_infinite(),
            "not committed"
        );
    }

    /// A gate that opens while the drone brakes for it is flown through without
    /// stopping: the speed never reaches zero, the acceleration changes no faster
    /// than the jerk allows, and the run ends within a tick or two of a run that
    /// never braked.
    #[test]
    fn a_gate_that_opens_mid_brake_is_flown_through_without_stopping() {
        let r = route(&[(4.0, 0.0)]);
        let dt_s = 0.05;
        let gate = GateAhead::closed_at(2.0);
        // Fly until braking for the gate, then open it `open_after` ticks later;
        // returns when the run ended and the slowest speed between the brake and
        // the gate.
        let fly = |open_after: usize| {
            let mut f = Follower::new(LIMITS, 0.0);
            let (mut braked_at, mut slowest_mps, mut last_a) = (None, f64::INFINITY, 0.0);
            for k in 0..400 {
                let t_s = k as f64 * dt_s;
                let open = braked_at.is_some_and(|b| k >= b + open_after);
                let s = f.step(
                    &r,
                    t_s,
                    dt_s,
                    if open { GateAhead::OPEN } else { gate },
                    true,
                );
                let a = s.acceleration_mps2[0];
                assert!(
                    (a - last_a).abs() <= LIMITS.max_jerk_mps3 * dt_s + 1e-9,
                    "t {t_s:.2} s: acceleration {last_a:.4} → {a:.4} m/s²"
                );
                assert!(s.velocity_mps[0] <= LIMITS.max_speed_mps + 1e-9);
                last_a = a;
                if braked_at.is_none() && matches!(f.motion, Motion::Braking { .. }) {
                    braked_at = Some(k);
                }
                if braked_at.is_some() && f.arc_m(&r, t_s) < 2.0 {
                    slowest_mps = slowest_mps.min(s.velocity_mps[0]);
                }
                if f.finished(&r) {
                    return (t_s, slowest_mps);
                }
            }
            panic!("never finished");
        };
        let (through_s, slowest_mps) = fly(4);
        assert!(slowest_mps > 0.1, "stopped: slowest {slowest_mps} m/s");
        let (restarted_s, stopped_mps) = fly(60);
        assert!(stopped_mps < 1e-9, "the late gate stops it");
        // Held 0.2 s it loses less than a tenth of a second on the whole run;
        // stopped, it loses the wait and the restart.
        let unbraked_s = r.runs[0].profile.duration_s();
        assert!(
            through_s <= unbraked_s + 0.1 + dt_s,
            "through at {through_s:.2} s, unbraked {unbraked_s:.2} s"
        );
        assert!(
            restarted_s >= unbraked_s + 50.0 * dt_s,
            "{restarted_s:.2} s"
        );
    }

    /// The latest time a moving setpoint passes a point is where braking now
    /// would pass it: never before the planned profile passes it, and nothing
    /// beyond where braking now would stop is promised.
    #[test]
    fn braking_now_is_the_latest_a_setpoint_passes() {
        let r = route(&[(4.0, 0.0)]);
        let mut f = Follower::new(LIMITS, 0.0);
        let dt_s = 0.05;
        for k in 0..=20 {
            f.step(&r, k as f64 * dt_s, dt_s, GateAhead::OPEN, true);
        }
        let t_s = 1.0;
        let here_m = f.arc_m(&r, t_s);
        let stop_m = Brake::new(f.state_at(t_s), LIMITS).stop_m();
        let ahead_m = 0.5 * (here_m + stop_m);
        let latest_s = f.latest_pass_s(&r, ahead_m, t_s).expect("committed");
        assert!(latest_s >= r.runs[0].profile.time_at_distance_s(ahead_m) - 1e-9);
        assert!(f.latest_pass_s(&r, stop_m + 0.01, t_s).is_none());
        assert_eq!(f.latest_pass_s(&r, here_m - 0.1, t_s), Some(t_s));
    }
}
