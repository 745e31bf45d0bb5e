//! One drone in flight: its route, its commanded motion, what telemetry says
//! about it and where it is in the flight. Everything else (the loop, the
//! contingencies) goes through its methods.
//!
//! Takeoff differs by autopilot and lives in `px4` (OFFBOARD climb on our
//! setpoints) and `ardupilot` (the vehicle's own takeoff); following the plan
//! is in `plan`; landing and hand-over in `landing`.

mod ardupilot;
mod landing;
mod plan;
mod px4;
mod settle;
mod tracking;

use super::command::{Command, CommandError, CommandSender};
use super::follower::{Follower, Setpoint};
use super::gate::Progress;
use super::log::LogEvent;
use super::observer::DroneStatus;
use super::path::Route;
use super::phase::{FailReason, Phase, Request, RetireStage, Retirement};
use super::placement::Placed;
use super::settings::LoopSettings;
use crate::link::{Flavour, Session, VehicleFrame, frames};
use std::sync::Arc;
use std::time::Instant;

/// Position telemetry older than this (ten periods at 20 Hz) means we cannot see
/// the drone: its commanded motion pauses long before the heartbeat timeout.
const TELEMETRY_STALE_S: f64 = 0.5;

/// What the whole swarm decides for every flying drone this tick.
#[derive(Debug, Clone, Copy)]
pub struct SwarmTick {
    /// Seconds on the plan clock.
    pub t_s: f64,
    /// The setpoint period, seconds.
    pub dt_s: f64,
    /// Abort or timeout: every drone brakes to rest and stays.
    pub aborting: bool,
    /// A retiring drone needs the swarm at rest (see `contingency::swarm_paused`).
    pub swarm_paused: bool,
}

/// The vehicle a drone flies on: its session, its autopilot family and where its
/// local frame sits in the mission frame.
pub struct Vehicle {
    /// The MAVLink session with it.
    pub session: Arc<Session>,
    /// Its autopilot family.
    pub flavour: Flavour,
    /// Its local frame, as pre-flight placed it.
    pub placed: Placed,
}

/// Everything the loop keeps per drone.
pub struct DroneRun {
    /// Plan order, as command results and observers name it.
    index: usize,
    id: String,
    session: Arc<Session>,
    flavour: Flavour,
    /// Its `mission_from_local` transform: every position in and out goes through it.
    placed: Placed,
    route: Route,
    follower: Follower,
    progress: Progress,
    /// Events already behind the commanded position (see `gate::closed_gate`).
    passed_events: usize,
    phase: Phase,
    /// Latest telemetry position, ENU metres.
    position_m: Option<[f64; 3]>,
    /// Latest telemetry velocity, ENU metres per second.
    velocity_mps: [f64; 3],
    link_lost: bool,
    link_losses: usize,
    /// Seconds since any message from the vehicle.
    silent_s: f64,
    /// Why the drone left its plan early, if it did.
    retired: Option<Retirement>,
    /// A retired drone's remaining events have been released (it is down).
    released: bool,
    /// A replan flies on without it (lost, or retired and down).
    left_plan: bool,
    /// No position telemetry for `TELEMETRY_STALE_S`: the follower pauses.
    telemetry_stale: bool,
    /// PX4: re-entering OFFBOARD after the vehicle left it (offboard-loss failsafe).
    resume: Request,
    gating_waits: usize,
    gating_wait_s: f64,
    /// The drone (plan order) this one waits for at a closed gate.
    waiting_for: Option<u32>,
    final_distance_to_goal_m: Option<f64>,
    /// Distances from telemetry to the streamed setpoint, metres (see `tracking`).
    tracking_m: Vec<f64>,
    /// Setpoints streamed in the last second, with when (see `tracking`).
    setpoint_history: std::collections::VecDeque<(Instant, [f64; 3])>,
    /// When the newest position sample arrived.
    position_received: Option<Instant>,
    /// Times its setpoint waited for the vehicle to come back within the tracking error.
    tracking_holds: usize,
    /// Seconds its setpoint waited so.
    tracking_hold_s: f64,
    /// Since when telemetry has shown it where it is going and at rest (see `settle`).
    settled_since: Option<Instant>,
    /// Last setpoint streamed (held during takeoff phases and aborts).
    last_setpoint: Option<Setpoint>,
    commands: CommandSender,
}

impl DroneRun {
    /// A drone armed on the ground, about to take off the way its autopilot does.
    pub fn new(
        index: usize,
        route: Route,
        vehicle: Vehicle,
        follower: Follower,
        commands: CommandSender,
    ) -> Self {
        let Vehicle {
            session,
            flavour,
            placed,
        } = vehicle;
        let phase = match flavour {
            Flavour::Px4 => Phase::EnterOffboard {
                since: Instant::now(),
                request: Request::NotSent,
            },
            Flavour::Ardupilot => Phase::Takeoff {
                request: Request::NotSent,
            },
        };
        Self {
            index,
            id: route.id.clone(),
            session,
            flavour,
            placed,
            route,
            follower,
            progress: Progress::default(),
            passed_events: 0,
            phase,
            position_m: None,
            velocity_mps: [0.0; 3],
            link_lost: false,
            link_losses: 0,
            silent_s: 0.0,
            retired: None,
            released: false,
            left_plan: false,
            telemetry_stale: false,
            resume: Request::NotSent,
            gating_waits: 0,
            gating_wait_s: 0.0,
            waiting_for: None,
            final_distance_to_goal_m: None,
            settled_since: None,
            tracking_m: Vec::new(),
            setpoint_history: std::collections::VecDeque::new(),
            position_received: None,
            tracking_holds: 0,
            tracking_hold_s: 0.0,
            last_setpoint: None,
            commands,
        }
    }

    /// The drone's mission id.
    pub fn id(&self) -> &str {
        &self.id
    }

    /// The MAVLink session with its vehicle.
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// The vehicle's autopilot family.
    pub fn flavour(&self) -> Flavour {
        self.flavour
    }

    /// Its vehicle's `mission_from_local` transform.
    pub fn frame(&self) -> VehicleFrame {
        self.placed.frame
    }

    /// Its vehicle's frame and how pre-flight found it.
    pub fn placed(&self) -> Placed {
        self.placed
    }

    /// The route it flies.
    pub fn route(&self) -> &Route {
        &self.route
    }

    /// Where it is in the flight.
    pub fn phase(&self) -> &Phase {
        &self.phase
    }

    /// Its commanded motion along the route.
    pub fn follower(&self) -> &Follower {
        &self.follower
    }

    /// Which of its events telemetry has shown it reach.
    pub fn progress(&self) -> &Progress {
        &self.progress
    }

    /// Latest telemetry position, ENU metres (`None` until heard).
    pub fn position_m(&self) -> Option<[f64; 3]> {
        self.position_m
    }

    /// Latest telemetry speed, metres per second.
    pub fn speed_mps(&self) -> f64 {
        super::path::distance_m(self.velocity_mps, [0.0; 3])
    }

    /// Where telemetry says it would come to rest braking within `limits` from its
    /// current velocity (its position when at rest), ENU metres.
    pub fn stopping_point_m(&self, limits: crate::profile::Kinematics) -> Option<[f64; 3]> {
        let p = self.position_m?;
        let speed_mps = self.speed_mps();
        if speed_mps <= 0.0 {
            return Some(p);
        }
        let moving = crate::profile::State {
            x_m: 0.0,
            v_mps: speed_mps,
            a_mps2: 0.0,
        };
        let reach_s = crate::profile::Brake::new(moving, limits).stop_m() / speed_mps;
        let v = self.velocity_mps;
        Some(std::array::from_fn(|i| p[i] + v[i] * reach_s))
    }

    /// Nothing heard for the mission's link timeout.
    pub fn link_lost(&self) -> bool {
        self.link_lost
    }

    /// Times its link was lost during the flight.
    pub fn link_losses(&self) -> usize {
        self.link_losses
    }

    /// Seconds since any message from the vehicle (∞ if none ever).
    pub fn silent_s(&self) -> f64 {
        self.silent_s
    }

    /// No position telemetry for a while: its commanded motion is paused.
    pub fn telemetry_stale(&self) -> bool {
        self.telemetry_stale
    }

    /// Why it left the plan early, if it did.
    pub fn retired(&self) -> Option<Retirement> {
        self.retired
    }

    /// Retired, down, and its remaining events released.
    pub fn released(&self) -> bool {
        self.released
    }

    /// Times it stopped (or could not start) because a TPG predecessor was late.
    pub fn gating_waits(&self) -> usize {
        self.gating_waits
    }

    /// Seconds it spent waiting at closed gates.
    pub fn gating_wait_s(&self) -> f64 {
        self.gating_wait_s
    }

    /// Distance to its goal when plan execution ended, metres.
    pub fn final_distance_to_goal_m(&self) -> Option<f64> {
        self.final_distance_to_goal_m
    }

    /// Starts `command` in its own task; its result comes back through the loop's
    /// inbox to [`DroneRun::deliver`].
    fn send(&self, command: Command) {
        self.commands
            .spawn(self.index, command, self.session.clone(), self.flavour);
    }

    /// Hands a finished command's result to whatever waits for it. A result that
    /// nobody waits for any more (the phase moved on, as an abort does to a
    /// takeoff) is dropped, as the command's task was.
    pub fn deliver(&mut self, command: Command, result: Result<(), CommandError>) {
        let waiting = match (command, &mut self.phase) {
            (Command::ResumeExternalControl, _) => &mut self.resume,
            (Command::EnterExternalControl, Phase::EnterOffboard { request, .. })
            | (Command::Takeoff { .. }, Phase::Takeoff { request })
            | (Command::Land, Phase::Landing { request })
            | (Command::Hold, Phase::HandedOver { request }) => request,
            _ => return,
        };
        if matches!(waiting, Request::Sent) {
            *waiting = Request::Done(result);
        }
    }

    /// Copies the newest telemetry in and detects link loss and stale positions.
    pub fn read_telemetry(
        &mut self,
        settings: &LoopSettings,
        now: Instant,
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) {
        let (position, silent_s) = {
            let s = self.session.state();
            (s.position, s.message_age_s(now))
        };
        self.silent_s = silent_s.unwrap_or(f64::INFINITY);
        let stale = position.is_none_or(|p| {
            now.saturating_duration_since(p.received).as_secs_f64() > TELEMETRY_STALE_S
        });
        if stale != self.telemetry_stale && matches!(self.phase, Phase::Flying) {
            let what = if stale {
                "position telemetry stopped: pausing at the next possible stop"
            } else {
                "position telemetry back: resuming"
            };
            events.push(LogEvent::new(since_arm_s, Some(&self.id), what));
        }
        self.telemetry_stale = stale;
        if let Some(p) = position {
            self.position_m = Some(self.placed.frame.mission_from_local(p.position_ned_m));
            self.position_received = Some(p.received);
            self.velocity_mps = frames::enu_from_ned_f32(p.velocity_ned_mps);
        }
        // Any message proves the link: under heavy loss heartbeats alone (1 Hz) go
        // missing for seconds while telemetry (20 Hz) still gets through.
        // A carrier that says the vehicle is out of reach (its relay left) is
        // believed at once: waiting out the timeout would only fly blind longer.
        let carrier_down = self.session.carrier_down();
        let lost =
            carrier_down.is_some() || silent_s.is_none_or(|age| age > settings.link_timeout_s);
        if lost && !self.link_lost {
            self.link_losses += 1;
            let why = carrier_down
                .unwrap_or_else(|| format!("nothing heard for {:.1} s", settings.link_timeout_s));
            events.push(LogEvent::new(
                since_arm_s,
                Some(&self.id),
                &format!("link lost: {why}"),
            ));
        } else if !lost && self.link_lost {
            events.push(LogEvent::new(since_arm_s, Some(&self.id), "link back"));
        }
        self.link_lost = lost;
    }

    /// Phase transitions that depend on commands and telemetry rather than the plan.
    pub fn advance(
        &mut self,
        settings: &LoopSettings,
        now: Instant,
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) {
        match &self.phase {
            Phase::EnterOffboard { .. } => self.enter_offboard(now, since_arm_s, events),
            Phase::Climb { .. } => self.climb(settings, now),
            Phase::Takeoff { .. } => self.take_off(since_arm_s, events),
            Phase::AwaitAltitude => self.await_altitude(settings),
            Phase::AtStart => self.last_setpoint = Some(self.hold_start()),
            Phase::Flying | Phase::AtGoal => self.resume_external_control(since_arm_s, events),
            phase if phase.retiring_on_our_setpoints() => {
                self.resume_external_control(since_arm_s, events);
            }
            Phase::HandedOver { .. } => self.request_hold(),
            Phase::Landing { .. } => self.land(since_arm_s, events),
            Phase::Lost { .. }
            | Phase::AwaitLanding
            | Phase::Retiring { .. }
            | Phase::Landed
            | Phase::Failed(_) => {}
        }
    }

    /// A setpoint holding above the pad (where the route begins).
    fn hold_start(&self) -> Setpoint {
        Setpoint::rest(self.route.start_m)
    }

    /// Gives up on the drone for `reason`, logging it.
    fn fail(&mut self, reason: FailReason, since_arm_s: f64, events: &mut Vec<LogEvent>) {
        events.push(LogEvent::new(
            since_arm_s,
            Some(&self.id),
            &reason.to_string(),
        ));
        self.phase = Phase::Failed(reason);
    }

    /// Whether this drone gets our setpoint stream this tick.
    fn streaming(&self) -> bool {
        match self.phase {
            Phase::EnterOffboard { .. }
            | Phase::Climb { .. }
            | Phase::AtStart
            | Phase::Flying
            | Phase::AtGoal
            | Phase::AwaitLanding
            | Phase::Lost { .. } => true,
            Phase::AwaitAltitude => self.last_setpoint.is_some(),
            ref phase => phase.retiring_on_our_setpoints(),
        }
    }

    /// Sends the drone its setpoint (NED on the wire) if it is streaming.
    pub async fn stream_setpoint(&self) {
        if !self.streaming() {
            return;
        }
        if let Some(s) = self.last_setpoint {
            // A failed send is one missed setpoint; the vehicle's own timeout and our
            // link-loss detection deal with a link that stays down.
            let _ = self
                .session
                .send_setpoint(
                    self.placed.frame.local_from_mission(s.position_m),
                    frames::ned_f32_from_enu(s.velocity_mps),
                    frames::ned_f32_from_enu(s.acceleration_mps2),
                )
                .await;
        }
    }

    /// What the status view shows about it.
    pub fn status(&self) -> DroneStatus {
        let events = self.route.events.len().max(1);
        DroneStatus {
            id: self.id.clone(),
            // Once given up for the flight, LOST says more than its link's state.
            phase: if self.link_lost && !matches!(self.phase, Phase::Lost { .. }) {
                "LINK LOST"
            } else {
                self.phase.name()
            },
            progress: self.progress.reached as f64 / events as f64,
            next_reach_s: self
                .route
                .events
                .get(self.progress.reached)
                .map(|e| e.reach_s),
            waiting_for: self.waiting_for,
        }
    }

    /// Everyone is at the start: the plan clock runs.
    pub fn start_plan(&mut self) {
        self.phase = Phase::Flying;
    }

    /// Silent for too long: given up for now; its commanded motion pauses.
    pub fn mark_lost(&mut self) {
        self.follower.set_paused(true);
        self.phase = Phase::Lost {
            was_at_goal: matches!(self.phase, Phase::AtGoal),
        };
    }

    /// Heard again after being lost: back where it was in the plan.
    pub fn rejoin_plan(&mut self) {
        if let Phase::Lost { was_at_goal } = self.phase {
            self.phase = if was_at_goal {
                Phase::AtGoal
            } else {
                Phase::Flying
            };
        }
    }

    /// Leaves the plan early for `why`: brakes and starts down at `stage`.
    pub fn retire(&mut self, why: Retirement, stage: RetireStage) {
        self.follower.halt();
        self.retired = Some(why);
        self.phase = Phase::Retiring { stage };
    }

    /// Moves a retiring drone to `stage` (waiting for its column, halting again).
    pub fn set_retire_stage(&mut self, stage: RetireStage) {
        if matches!(self.phase, Phase::Retiring { .. }) {
            self.phase = Phase::Retiring { stage };
        }
    }

    /// Its autopilot brought it down and disarmed it.
    pub fn mark_landed(&mut self) {
        self.phase = Phase::Landed;
    }

    /// Flies `route` from here on, a replan's: the old route's progress, gates and
    /// commanded motion are gone (the follower starts at rest at the route's start,
    /// where the freeze left it).
    pub fn splice(&mut self, route: Route) {
        self.route = route;
        self.follower = self.follower.restarted();
        self.progress = Progress::default();
        self.passed_events = 0;
        self.waiting_for = None;
        self.settled_since = None;
        if matches!(self.phase, Phase::AtGoal) {
            self.phase = Phase::Flying;
        }
    }

    /// A replan flies on without it.
    pub fn leave_plan(&mut self) {
        self.left_plan = true;
    }

    /// A replan flies on without it (lost, or retired and down).
    pub fn left_plan(&self) -> bool {
        self.left_plan
    }

    /// Heard again after a replan left it out: it holds where it is and lands
    /// once its column is clear (nobody was planned into it).
    pub fn land_out_of_plan(&mut self) {
        if let Some(p) = self.position_m {
            self.last_setpoint = Some(Setpoint::rest(p));
        }
        self.phase = Phase::AwaitLanding;
    }

    /// A retired drone that is down: its remaining events no longer hold anyone
    /// up when `ground_clear`. Marks it released either way (once).
    pub fn release_events(&mut self, ground_clear: bool) {
        self.released = true;
        if ground_clear {
            self.progress.reached = self.route.events.len();
        }
    }
}
