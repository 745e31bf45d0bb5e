//! One drone in flight: its route, its commanded motion, what telemetry says
//! about it and where it is in the flight. Everything else (the loop, the
//! contingencies) goes through its methods.
//!
//! Each concern is a small type the drone owns, in its own file:
//!
//! - how its autopilot takes off: the [`Takeoff`](super::autopilot::Takeoff) its
//!   flavour hands it (`fly::autopilot`), stepped by the phase machine in
//!   `transitions`; back into external control after a failsafe left it: `resume`;
//! - following the route: the `Follower` and its gates (`Gating`, `gating`), in
//!   `plan`;
//! - arriving: `Settling` (`settle`), within tolerance and at rest for a moment;
//! - tracking: `Tracking` (`tracking`), telemetry against the setpoint streamed;
//! - link health and what the vehicle last said: `Telemetry` (`telemetry`);
//! - in or out of the plan: `Membership` (`membership`), changed as contingencies
//!   and replans ask (`replanned`);
//! - landing and hand-over: `landing`; what goes out to the vehicle: `vehicle_io`;
//! - still inside the mission's airspace, or gone from the plan: `airspace`.

mod airspace;
mod gating;
mod landing;
mod membership;
mod plan;
mod replanned;
mod resume;
mod settle;
mod telemetry;
mod tracking;
mod transitions;
mod vehicle_io;

use super::autopilot::Flavour;
use super::command::{CommandSender, Request};
use super::feedforward::SpeedClamp;
use super::follower::{Follower, Setpoint};
use super::gate::Progress;
use super::lateness::EventLateness;
use super::log::{LogEvent, TrackingError};
use super::observer::DroneStatus;
use super::path::Route;
use super::phase::Phase;
use super::placement::Placed;
use super::settings::LoopSettings;
use crate::link::{Session, VehicleFrame};
use gating::Gating;
use membership::Membership;
use settle::Settling;
use std::sync::Arc;
use std::time::Instant;
use telemetry::Telemetry;
use tracking::Tracking;

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
    pub flavour: &'static dyn Flavour,
    /// Its local frame, as pre-flight placed it.
    pub placed: Placed,
    /// Its controller's velocity clamp, which the acceleration feed-forward is
    /// tapered by (see [`crate::fly::feedforward`]).
    pub speed_clamp: Option<SpeedClamp>,
}

/// Everything the loop keeps per drone.
pub struct DroneRun {
    /// Plan order, as command results and observers name it.
    index: usize,
    id: String,
    session: Arc<Session>,
    flavour: &'static dyn Flavour,
    /// Its `mission_from_local` transform: every position in and out goes through it.
    placed: Placed,
    /// See [`Vehicle::speed_clamp`].
    speed_clamp: Option<SpeedClamp>,
    route: Route,
    follower: Follower,
    progress: Progress,
    /// Arc length of the plan setpoint streamed last (see `plan::observe_progress`).
    streamed_arc_m: f64,
    /// Its vehicle was trusted on its setpoint at this tick's observation.
    trusted_now: bool,
    /// Every event telemetry showed it reach, against the schedule.
    lateness: Vec<EventLateness>,
    phase: Phase,
    /// What telemetry says about it, and its link's health.
    telemetry: Telemetry,
    /// Whether it is still in the plan, and why not.
    membership: Membership,
    /// PX4: re-entering OFFBOARD after the vehicle left it (offboard-loss failsafe).
    resume: Request,
    /// Where it stands at its route's gates, and its waits there.
    gating: Gating,
    final_distance_to_goal_m: Option<f64>,
    /// Its tracking error and the holds it caused.
    tracking: Tracking,
    /// Since when telemetry has shown it where it is going and at rest.
    settling: Settling,
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
            speed_clamp,
        } = vehicle;
        let phase = Phase::TakingOff(flavour.takeoff());
        Self {
            index,
            id: route.id.clone(),
            session,
            flavour,
            placed,
            speed_clamp,
            route,
            follower,
            progress: Progress::default(),
            streamed_arc_m: 0.0,
            trusted_now: false,
            lateness: Vec::new(),
            phase,
            telemetry: Telemetry::new(),
            membership: Membership::default(),
            resume: Request::NotSent,
            gating: Gating::default(),
            final_distance_to_goal_m: None,
            settling: Settling::default(),
            tracking: Tracking::new(),
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
    pub fn flavour(&self) -> &'static dyn Flavour {
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
        self.telemetry.position_m
    }

    /// Latest telemetry speed, metres per second.
    pub fn speed_mps(&self) -> f64 {
        self.telemetry.speed_mps()
    }

    /// True once telemetry has shown the drone within `tolerance_m` of `point_m` and
    /// at rest for [`settle::SETTLE_HOLD`] without a break.
    fn settled_at(&mut self, point_m: [f64; 3], tolerance_m: f64) -> bool {
        self.settling.at(&self.telemetry, point_m, tolerance_m)
    }

    /// Telemetry shows the drone at rest: at most [`settle::REST_SPEED_MPS`].
    pub fn at_rest(&self) -> bool {
        self.speed_mps() <= settle::REST_SPEED_MPS
    }

    /// Where telemetry says it would come to rest braking within `limits` from its
    /// current velocity (its position when at rest), ENU metres.
    pub fn stopping_point_m(&self, limits: crate::profile::Kinematics) -> Option<[f64; 3]> {
        self.telemetry.stopping_point_m(limits)
    }

    /// Nothing heard for the mission's link timeout.
    pub fn link_lost(&self) -> bool {
        self.telemetry.link_lost
    }

    /// Times its link was lost during the flight.
    pub fn link_losses(&self) -> usize {
        self.telemetry.link_losses
    }

    /// Seconds since any message from the vehicle (∞ if none ever).
    pub fn silent_s(&self) -> f64 {
        self.telemetry.silent_s
    }

    /// No position telemetry for a while: its commanded motion is paused.
    pub fn telemetry_stale(&self) -> bool {
        self.telemetry.stale
    }

    /// Copies the newest telemetry in and detects link loss and stale positions.
    pub fn read_telemetry(
        &mut self,
        settings: &LoopSettings,
        now: Instant,
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) {
        let flying = matches!(self.phase, Phase::Flying);
        let id = &self.id;
        self.telemetry.read(
            &self.session,
            self.placed.frame,
            settings,
            now,
            flying,
            |what| events.push(LogEvent::new(since_arm_s, Some(id), what)),
        );
    }

    /// Remembers the setpoint streamed at `now` and records the tracking error of
    /// the newest sample, in the phases where the drone follows our setpoints in the
    /// air (see `tracking`).
    pub fn sample_tracking(&mut self, now: Instant) {
        let following = matches!(self.phase, Phase::Flying | Phase::AtStart | Phase::AtGoal);
        let in_plan = matches!(self.phase, Phase::Flying | Phase::AtGoal);
        let streamed = self
            .last_setpoint
            .map(|s| (s, in_plan.then_some(self.streamed_arc_m)));
        self.tracking
            .sample(now, streamed, following, &self.telemetry);
    }

    /// Distance from the newest position sample to the setpoint streamed last before
    /// it arrived (the oldest remembered one if it is older still), metres.
    pub fn tracking_distance_m(&self) -> Option<f64> {
        self.tracking.distance_m(&self.telemetry)
    }

    /// Times its setpoint waited for the vehicle to come back within the bound.
    pub fn tracking_holds(&self) -> usize {
        self.tracking.holds
    }

    /// Seconds its setpoint waited so.
    pub fn tracking_hold_s(&self) -> f64 {
        self.tracking.hold_s
    }

    /// Median, 95th percentile and maximum of the recorded tracking error (`None`
    /// before any sample).
    pub fn tracking_error(&self) -> Option<TrackingError> {
        self.tracking.error()
    }

    /// Times it stopped (or could not start) because a TPG predecessor was late.
    pub fn gating_waits(&self) -> usize {
        self.gating.waits
    }

    /// Seconds it spent waiting at closed gates.
    pub fn gating_wait_s(&self) -> f64 {
        self.gating.wait_s
    }

    /// Its longest single wait at a closed gate, seconds.
    pub fn longest_gating_wait_s(&self) -> f64 {
        self.gating.longest_s
    }

    /// Every event telemetry showed it reach, against the schedule.
    pub fn lateness(&self) -> &[EventLateness] {
        &self.lateness
    }

    /// Distance to its goal when plan execution ended, metres.
    pub fn final_distance_to_goal_m(&self) -> Option<f64> {
        self.final_distance_to_goal_m
    }

    /// What the status view shows about it.
    pub fn status(&self) -> DroneStatus {
        let events = self.route.events.len().max(1);
        DroneStatus {
            id: self.id.clone(),
            // Once given up for the flight, LOST says more than its link's state.
            phase: if self.telemetry.link_lost && !matches!(self.phase, Phase::Lost { .. }) {
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
            waiting_for: self.gating.waiting_for,
        }
    }
}
