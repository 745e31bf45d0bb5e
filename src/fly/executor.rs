//! The flight loop: one tick per setpoint period streams every drone's setpoint,
//! folds in telemetry, opens TPG gates, watches separation and link health, and
//! moves each drone through its phases (take off, fly the plan, land).

use super::contingency::{self, RetireStage, Retirement};
use super::follower::{Follower, Hold, Setpoint};
use super::gate::{Progress, closed_gate};
use super::log::LogEvent;
use super::observer::{DroneStatus, FlightObserver, FlightStatus};
use super::path::Route;
use crate::link::{Flavour, LinkError, Session, frames};
use crate::trajectory::Profile;
use std::sync::Arc;
use std::time::{Duration, Instant};
use tokio::task::JoinHandle;

/// Copter reports takeoff done within some 0.1–0.2 m of the target height and then
/// holds; from this close we take over with our own setpoint for the last bit.
const TAKEOFF_NEAR_M: f64 = 0.3;

/// Above this height a vehicle has certainly left the ground.
const TAKEOFF_STARTED_M: f64 = 0.2;
/// A stuck plan (see `contingency::plan_stuck`) must stay stuck this long before
/// the flight ends, so a drone that is merely slow to settle is not mistaken for it.
const STUCK_CONFIRM: Duration = Duration::from_secs(3);
/// Takeoff of the whole swarm must finish within this long after arming.
const TAKEOFF_TIMEOUT_S: f64 = 60.0;
/// Position telemetry older than this (ten periods at 20 Hz) means we cannot see
/// the drone: its commanded motion pauses long before the heartbeat timeout.
const TELEMETRY_STALE_S: f64 = 0.5;

/// Where a drone is in the flight.
#[derive(Debug)]
pub enum Phase {
    /// PX4: streaming a ground hold so OFFBOARD is accepted, then switching.
    EnterOffboard {
        since: Instant,
        task: Option<JoinHandle<Result<(), LinkError>>>,
    },
    /// PX4: climbing on our setpoints along a vertical profile started at `t0`.
    Climb {
        t0: Instant,
        from_z_m: f64,
    },
    /// ArduPilot: the vehicle's own takeoff to the start altitude.
    Takeoff {
        task: Option<JoinHandle<Result<(), LinkError>>>,
    },
    /// ArduPilot: takeoff accepted, climbing to the start altitude.
    AwaitAltitude,
    /// Hovering at the start voxel until everyone is.
    AtStart,
    /// Following the plan.
    Flying,
    /// Holding at the goal until everyone is.
    AtGoal,
    /// Nothing heard for `contingency::LOST_AFTER_S`: left to its own failsafe.
    Lost {
        was_at_goal: bool,
    },
    /// Leaving the plan early (low battery, autopilot failsafe): see `contingency`.
    Retiring {
        stage: RetireStage,
    },
    /// Done (at its goal or held for good): lands once nothing is below it.
    AwaitLanding,
    /// Could never land safely: put in the autopilot's hold mode for manual control.
    HandedOver {
        task: Option<JoinHandle<Result<(), LinkError>>>,
    },
    /// Land commanded; waiting for touchdown and disarm.
    Landing {
        task: Option<JoinHandle<Result<(), LinkError>>>,
    },
    Landed,
    /// Gave up on this drone (a refused command); it holds or lands by itself.
    Failed(String),
}

impl Phase {
    pub fn name(&self) -> &'static str {
        match self {
            Phase::EnterOffboard { .. } => "offboard",
            Phase::Climb { .. } | Phase::Takeoff { .. } | Phase::AwaitAltitude => "takeoff",
            Phase::AtStart => "at start",
            Phase::Flying => "flying",
            Phase::AtGoal => "at goal",
            Phase::Lost { .. } => "LOST",
            Phase::Retiring { .. } => "retiring",
            Phase::AwaitLanding => "to land",
            Phase::HandedOver { .. } => "HANDED OVER",
            Phase::Landing { .. } => "landing",
            Phase::Landed => "landed",
            Phase::Failed(_) => "FAILED",
        }
    }
}

/// Everything the loop keeps per drone.
pub struct DroneRun {
    pub id: String,
    pub session: Arc<Session>,
    pub flavour: Flavour,
    pub route: Route,
    pub follower: Follower,
    pub progress: Progress,
    pub passed_events: usize,
    pub phase: Phase,
    /// Latest telemetry position (ENU) and velocity.
    pub position_m: Option<[f64; 3]>,
    pub speed_mps: f64,
    pub link_lost: bool,
    pub link_losses: usize,
    /// Seconds since any message from the vehicle.
    pub silent_s: f64,
    /// Why the drone left its plan early, if it did.
    pub retired: Option<Retirement>,
    /// A retired drone's remaining events have been released (it is down).
    pub released: bool,
    /// No position telemetry for `TELEMETRY_STALE_S`: the follower pauses.
    pub telemetry_stale: bool,
    /// PX4: re-entering OFFBOARD after the vehicle left it (offboard-loss failsafe).
    pub resume_task: Option<JoinHandle<Result<(), LinkError>>>,
    pub gating_waits: usize,
    pub gating_wait_s: f64,
    pub waiting_for: Option<u32>,
    pub final_distance_to_goal_m: Option<f64>,
    /// Last setpoint streamed (held during takeoff phases and aborts).
    pub last_setpoint: Option<Setpoint>,
}

/// Tunables of the loop.
#[derive(Debug, Clone, Copy)]
pub struct LoopSettings {
    pub setpoint_rate_hz: f64,
    pub link_timeout_s: f64,
    pub max_speed_mps: f64,
    pub max_accel_mps2: f64,
    /// Telemetry this close to a commanded rest point counts as settled there.
    pub settle_tolerance_m: f64,
    /// Give up on plan execution (hold, then land) after this long.
    pub execution_timeout_s: f64,
    pub safety_distance_m: f64,
    /// The ground lies below the voxel world by at least the safety distance, so a
    /// landed drone is in nobody's way.
    pub ground_clear: bool,
}

/// What the loop measured.
#[derive(Debug, Default)]
pub struct Outcome {
    pub completed: bool,
    pub executed_makespan_s: Option<f64>,
    pub min_separation_m: f64,
    pub closest_pair: Option<(String, String, f64)>,
    pub min_separation_takeoff_landing_m: f64,
    pub max_speed_mps: f64,
    pub events: Vec<LogEvent>,
}

/// Runs the flight from armed-on-the-ground to landed (or to every drone given up).
pub async fn run(
    drones: &mut [DroneRun],
    settings: LoopSettings,
    armed_at: Instant,
    mut abort: tokio::sync::watch::Receiver<bool>,
    observers: &[Arc<dyn FlightObserver>],
) -> Outcome {
    let dt_s = 1.0 / settings.setpoint_rate_hz;
    let mut tick = tokio::time::interval(Duration::from_secs_f64(dt_s));
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut out = Outcome {
        min_separation_m: f64::INFINITY,
        min_separation_takeoff_landing_m: f64::INFINITY,
        ..Outcome::default()
    };
    let mut execution_t0: Option<Instant> = None;
    let mut aborting = false;
    let mut landing_started = false;
    let mut tap = Tap::new(drones.len());
    let mut stuck_since: Option<Instant> = None;
    loop {
        tick.tick().await;
        let now = Instant::now();
        let since_arm_s = now.duration_since(armed_at).as_secs_f64();
        if !aborting && (*abort.borrow_and_update()) {
            aborting = true;
            out.events.push(event(
                since_arm_s,
                None,
                "abort requested: every drone holds, then lands",
            ));
        }
        if let Some(t0) = execution_t0
            && !aborting
            && now.duration_since(t0).as_secs_f64() > settings.execution_timeout_s
        {
            aborting = true;
            out.events.push(event(
                since_arm_s,
                None,
                "plan execution timed out: holding, then landing",
            ));
        }
        if execution_t0.is_none() && !aborting {
            if let Some(d) = drones.iter().find(|d| matches!(d.phase, Phase::Failed(_))) {
                aborting = true;
                let why = format!(
                    "{} failed before the plan started: holding, then landing",
                    d.id
                );
                out.events.push(event(since_arm_s, None, &why));
            } else if since_arm_s > TAKEOFF_TIMEOUT_S {
                aborting = true;
                out.events.push(event(
                    since_arm_s,
                    None,
                    "takeoff timed out: holding, then landing",
                ));
            }
        }
        read_telemetry(drones, &settings, now, since_arm_s, &mut out.events);
        let t_exec_s = execution_t0.map(|t0| now.duration_since(t0).as_secs_f64());
        if t_exec_s.is_some() {
            contingency::track_lost(drones, since_arm_s, &mut out.events);
            if !landing_started {
                contingency::detect_retirement(drones, since_arm_s, &mut out.events);
            }
            contingency::advance_retirements(
                drones,
                settings.safety_distance_m,
                since_arm_s,
                &mut out.events,
            );
            contingency::release_landed(
                drones,
                settings.ground_clear,
                since_arm_s,
                &mut out.events,
            );
        }

        // Gates first (from everyone's progress), then commanded motion.
        if let Some(t_s) = t_exec_s {
            let paused = contingency::swarm_paused(drones);
            step_flying(drones, &settings, t_s, dt_s, aborting, paused);
        }
        for d in drones.iter_mut() {
            advance_phase(d, &settings, now, since_arm_s, &mut out.events);
        }
        stream(drones).await;
        measure(drones, t_exec_s, landing_started, &mut out);

        // Everyone at the start: the plan clock starts.
        if execution_t0.is_none()
            && !aborting
            && drones.iter().all(|d| matches!(d.phase, Phase::AtStart))
        {
            execution_t0 = Some(now);
            for d in drones.iter_mut() {
                d.phase = Phase::Flying;
            }
            out.events.push(event(
                since_arm_s,
                None,
                "all drones at their start: executing the plan",
            ));
        }
        let all_at_goal = drones.iter().all(|d| matches!(d.phase, Phase::AtGoal));
        // Retired drones that are down count as done: the others finished without them.
        let plan_done = drones.iter().any(|d| matches!(d.phase, Phase::AtGoal))
            && drones.iter().all(|d| {
                matches!(d.phase, Phase::AtGoal) || (d.released && matches!(d.phase, Phase::Landed))
            });
        if all_at_goal && !landing_started {
            out.completed = true;
            out.executed_makespan_s = t_exec_s;
        }
        let all_holding = drones
            .iter()
            .all(|d| !matches!(d.phase, Phase::Flying) || d.follower.at_rest());
        stuck_since = match (stuck_since, contingency::plan_stuck(drones)) {
            (_, false) => None,
            (None, true) => Some(now),
            (Some(t), true) => Some(t),
        };
        let stuck = stuck_since.is_some_and(|t| now.duration_since(t) > STUCK_CONFIRM);
        if stuck && !landing_started {
            out.events.push(event(
                since_arm_s,
                None,
                "the plan cannot finish without the missing drones: the others land where they are, each once its column is clear",
            ));
        }
        if !landing_started && (all_at_goal || plan_done || stuck || (aborting && all_holding)) {
            landing_started = true;
            for d in drones.iter_mut() {
                if let Some(p) = d.position_m {
                    d.final_distance_to_goal_m = Some(distance(p, d.route.goal_m()));
                }
                // A drone that failed anything but landing still lands (or, on the
                // ground, disarms): nobody is left armed.
                let landing_failed =
                    matches!(&d.phase, Phase::Failed(why) if why.starts_with("landing"));
                let done = matches!(
                    d.phase,
                    Phase::Landed | Phase::Lost { .. } | Phase::Landing { .. }
                );
                if !done && !landing_failed {
                    d.phase = Phase::AwaitLanding;
                }
            }
        }
        if landing_started {
            start_landings(drones, &settings, since_arm_s, &mut out.events);
        }
        if !observers.is_empty() {
            tap.forward(observers, drones, armed_at, &out.events);
        }
        if observers.iter().any(|o| o.wants_status()) {
            let status = FlightStatus {
                since_arm_s,
                t_exec_s,
                min_separation_m: out.min_separation_m,
                drones: drones.iter().map(status_of).collect(),
            };
            for o in observers.iter().filter(|o| o.wants_status()) {
                o.status(&status);
            }
        }
        let handed_over = |d: &DroneRun| matches!(&d.phase, Phase::HandedOver { task: Some(t) } if t.is_finished());
        if landing_started
            && drones.iter().all(|d| {
                matches!(
                    d.phase,
                    Phase::Landed | Phase::Failed(_) | Phase::Lost { .. }
                ) || handed_over(d)
            })
        {
            break;
        }
    }
    if out.closest_pair.is_none() && out.min_separation_m.is_infinite() {
        out.min_separation_m = f64::INFINITY;
    }
    out
}

/// What the observer has been given so far: the newest sample per drone and the
/// number of events.
struct Tap {
    last_sample: Vec<Option<Instant>>,
    events_sent: usize,
}

impl Tap {
    fn new(drones: usize) -> Self {
        Self {
            last_sample: vec![None; drones],
            events_sent: 0,
        }
    }

    /// Hands over each drone's newest telemetry (once) and the events since last time.
    fn forward(
        &mut self,
        observers: &[Arc<dyn FlightObserver>],
        drones: &[DroneRun],
        armed_at: Instant,
        events: &[LogEvent],
    ) {
        for (i, d) in drones.iter().enumerate() {
            let Some(p) = d.session.state().position else {
                continue;
            };
            if self.last_sample[i] == Some(p.received) {
                continue;
            }
            self.last_sample[i] = Some(p.received);
            let t_s = p.received.saturating_duration_since(armed_at).as_secs_f64();
            let position_m = frames::enu_from_ned_f32(p.position_ned_m);
            for o in observers {
                o.sample(i, t_s, position_m);
            }
        }
        for e in &events[self.events_sent.min(events.len())..] {
            for o in observers {
                o.event(e);
            }
        }
        self.events_sent = events.len();
    }
}

fn event(t_s: f64, drone: Option<&str>, message: &str) -> LogEvent {
    LogEvent::new(t_s, drone, message)
}

/// Lets each drone waiting to land descend once nothing is below it; a drone whose
/// column stays blocked by one that will never move is handed to its autopilot.
fn start_landings(
    drones: &mut [DroneRun],
    settings: &LoopSettings,
    since_arm_s: f64,
    events: &mut Vec<LogEvent>,
) {
    for i in 0..drones.len() {
        if matches!(drones[i].phase, Phase::AwaitLanding)
            && contingency::column_blocker(drones, i, settings.safety_distance_m).is_none()
        {
            drones[i].phase = Phase::Landing { task: None };
        }
    }
    for i in contingency::stranded(drones, settings.safety_distance_m) {
        let blocker = contingency::column_blocker(drones, i, settings.safety_distance_m)
            .map_or_else(String::new, |j| drones[j].id.clone());
        let d = &mut drones[i];
        events.push(event(
            since_arm_s,
            Some(&d.id),
            &format!("cannot land: {blocker} is below it; left in the autopilot's position hold — take manual control"),
        ));
        d.phase = Phase::HandedOver { task: None };
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Copies the newest telemetry into each drone and detects link loss.
fn read_telemetry(
    drones: &mut [DroneRun],
    settings: &LoopSettings,
    now: Instant,
    since_arm_s: f64,
    events: &mut Vec<LogEvent>,
) {
    for d in drones.iter_mut() {
        let (position, silent_s) = {
            let s = d.session.state();
            (
                s.position,
                s.last_message
                    .map(|t| now.saturating_duration_since(t).as_secs_f64()),
            )
        };
        d.silent_s = silent_s.unwrap_or(f64::INFINITY);
        let stale = position.is_none_or(|p| {
            now.saturating_duration_since(p.received).as_secs_f64() > TELEMETRY_STALE_S
        });
        if stale != d.telemetry_stale && matches!(d.phase, Phase::Flying) {
            let what = if stale {
                "position telemetry stopped: pausing at the next possible stop"
            } else {
                "position telemetry back: resuming"
            };
            events.push(event(since_arm_s, Some(&d.id), what));
        }
        d.telemetry_stale = stale;
        if let Some(p) = position {
            d.position_m = Some(frames::enu_from_ned_f32(p.position_ned_m));
            let v = p.velocity_ned_mps.map(f64::from);
            d.speed_mps = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        }
        // Any message proves the link: under heavy loss heartbeats alone (1 Hz) go
        // missing for seconds while telemetry (20 Hz) still gets through.
        let lost = silent_s.is_none_or(|age| age > settings.link_timeout_s);
        if lost && !d.link_lost {
            d.link_losses += 1;
            events.push(event(
                since_arm_s,
                Some(&d.id),
                &format!(
                    "link lost: nothing heard for {:.1} s",
                    settings.link_timeout_s
                ),
            ));
        } else if !lost && d.link_lost {
            events.push(event(since_arm_s, Some(&d.id), "link back"));
        }
        d.link_lost = lost;
    }
}

/// Observed progress, gates and commanded motion of every flying drone.
fn step_flying(
    drones: &mut [DroneRun],
    settings: &LoopSettings,
    t_s: f64,
    dt_s: f64,
    aborting: bool,
    swarm_paused: bool,
) {
    for d in drones.iter_mut() {
        let observed = matches!(
            d.phase,
            Phase::Flying | Phase::AtGoal | Phase::Retiring { .. }
        );
        if !observed || d.link_lost || d.telemetry_stale {
            continue;
        }
        if let Some(p) = d.position_m {
            let arc = d.follower.arc_m(&d.route, t_s);
            let run = d.follower.run_index();
            d.progress.observe(&d.route, p, arc, run);
        }
    }
    let progress: Vec<Progress> = drones.iter().map(|d| d.progress.clone()).collect();
    for d in drones.iter_mut() {
        let retiring = matches!(
            d.phase,
            Phase::Retiring {
                stage: RetireStage::Halting | RetireStage::WaitColumn { .. }
            }
        );
        if !matches!(d.phase, Phase::Flying) && !retiring {
            continue;
        }
        if aborting {
            d.follower.halt();
        }

        let arc = d.follower.arc_m(&d.route, t_s);
        let (gate_arc_m, blocker) = closed_gate(&d.route, &mut d.passed_events, &progress, arc);
        let rest_point = d.follower.setpoint(&d.route, t_s).position_m;
        let settled = d
            .position_m
            .is_some_and(|p| distance(p, rest_point) <= settings.settle_tolerance_m);
        let paused = d.link_lost || d.telemetry_stale || d.resume_task.is_some() || swarm_paused;
        let was_gated = d.follower.hold == Hold::Gate;
        d.follower.set_paused(paused);
        let setpoint = d.follower.step(&d.route, t_s, dt_s, gate_arc_m, settled);
        // A paused drone waits for its own link, not for a TPG predecessor.
        if d.follower.hold == Hold::Gate && !aborting && !paused {
            if !was_gated {
                d.gating_waits += 1;
            }
            d.gating_wait_s += dt_s;
            d.waiting_for = blocker;
        } else {
            d.waiting_for = None;
        }
        d.last_setpoint = Some(setpoint);
        if matches!(d.phase, Phase::Flying)
            && d.follower.finished(&d.route)
            && d.position_m
                .is_some_and(|p| distance(p, d.route.goal_m()) <= settings.settle_tolerance_m)
        {
            d.phase = Phase::AtGoal;
        }
    }
}

/// Phase transitions that depend on commands and telemetry rather than the plan.
fn advance_phase(
    d: &mut DroneRun,
    settings: &LoopSettings,
    now: Instant,
    since_arm_s: f64,
    events: &mut Vec<LogEvent>,
) {
    let start_m = d.route.start_m;
    let hold_start = Setpoint {
        position_m: start_m,
        velocity_mps: [0.0; 3],
    };
    let failed = |d: &mut DroneRun, what: &str, e: String, events: &mut Vec<LogEvent>| {
        events.push(event(since_arm_s, Some(&d.id), &format!("{what}: {e}")));
        d.phase = Phase::Failed(format!("{what}: {e}"));
    };
    match &mut d.phase {
        Phase::EnterOffboard { since, task } => {
            // Hold on the ground where the vehicle is until OFFBOARD is in.
            let ground = d.position_m.map_or([start_m[0], start_m[1], 0.0], |p| p);
            if d.last_setpoint.is_none() {
                d.last_setpoint = Some(Setpoint {
                    position_m: ground,
                    velocity_mps: [0.0; 3],
                });
            }
            let since = *since;
            match task {
                None if now.duration_since(since) > Duration::from_millis(500) => {
                    let session = d.session.clone();
                    let mode = d.flavour.external_control_mode();
                    *task = Some(tokio::spawn(async move { session.set_mode(mode).await }));
                }
                Some(t) if t.is_finished() => {
                    let result = finished(t);
                    match result {
                        Ok(()) => {
                            let from_z_m = d.last_setpoint.map_or(0.0, |s| s.position_m[2]);
                            d.phase = Phase::Climb { t0: now, from_z_m };
                        }
                        Err(e) => failed(d, "OFFBOARD refused", e, events),
                    }
                }
                _ => {}
            }
        }
        Phase::Climb { t0, from_z_m } => {
            let height_m = start_m[2] - *from_z_m;
            let profile = Profile::new(
                height_m.abs(),
                settings.max_speed_mps,
                settings.max_accel_mps2,
            );
            let tau = now.duration_since(*t0).as_secs_f64();
            let sign = height_m.signum();
            d.last_setpoint = Some(Setpoint {
                position_m: [
                    start_m[0],
                    start_m[1],
                    *from_z_m + sign * profile.distance_at_m(tau),
                ],
                velocity_mps: [0.0, 0.0, sign * profile.speed_at_mps(tau)],
            });
            if tau >= profile.duration_s()
                && d.position_m
                    .is_some_and(|p| distance(p, start_m) <= settings.settle_tolerance_m)
            {
                d.phase = Phase::AtStart;
            }
        }
        Phase::Takeoff { task } => match task {
            None => {
                let session = d.session.clone();
                let height_m = start_m[2] as f32;
                *task = Some(tokio::spawn(async move { session.takeoff(height_m).await }));
            }
            Some(t) if t.is_finished() => match finished(t) {
                // A lost ACK makes the retry meet a vehicle already climbing, which
                // Copter answers FAILED: telemetry decides.
                Err(_) if d.position_m.is_some_and(|p| p[2] > TAKEOFF_STARTED_M) => {
                    d.phase = Phase::AwaitAltitude
                }
                Err(e) => failed(d, "takeoff refused", e, events),
                Ok(()) => d.phase = Phase::AwaitAltitude,
            },
            _ => {}
        },
        Phase::AwaitAltitude => {
            // Copter climbs by itself; stream only once it is up, then correct the
            // last centimetres with our setpoint.
            if d.position_m
                .is_some_and(|p| p[2] >= start_m[2] - TAKEOFF_NEAR_M)
            {
                d.last_setpoint = Some(hold_start);
                if d.position_m
                    .is_some_and(|p| distance(p, start_m) <= settings.settle_tolerance_m)
                {
                    d.phase = Phase::AtStart;
                }
            }
        }
        Phase::AtStart => d.last_setpoint = Some(hold_start),
        Phase::Flying | Phase::AtGoal => resume_external_control(d, since_arm_s, events),
        Phase::Retiring {
            stage: RetireStage::Halting | RetireStage::WaitColumn { .. },
        } => resume_external_control(d, since_arm_s, events),
        Phase::Lost { .. }
        | Phase::AwaitLanding
        | Phase::Retiring {
            stage: RetireStage::AutopilotLanding,
        } => {}
        Phase::HandedOver { task } => {
            if task.is_none() {
                let session = d.session.clone();
                let mode = d.flavour.hold_mode();
                *task = Some(tokio::spawn(async move { session.set_mode(mode).await }));
            }
        }
        Phase::Landing { task } => match task {
            None => {
                let session = d.session.clone();
                let mode = d.flavour.land_mode();
                *task = Some(tokio::spawn(async move {
                    if let Err(e) = session.set_mode(mode).await {
                        // Still on the ground (takeoff never happened): disarming is the landing.
                        if session.state().on_ground() {
                            return session.disarm(false).await;
                        }
                        return Err(e);
                    }
                    session
                        .confirm("touchdown and disarm", Duration::from_secs(60), |s| {
                            !s.armed
                        })
                        .await
                }));
            }
            Some(t) if t.is_finished() => match finished(t) {
                Ok(()) => d.phase = Phase::Landed,
                Err(e) => failed(d, "landing", e, events),
            },
            _ => {}
        },
        Phase::Landed | Phase::Failed(_) => {}
    }
}

/// PX4 leaves OFFBOARD when our stream stops for a second (a cut link) and holds,
/// then lands by itself; once telemetry is back, ask for OFFBOARD again. The
/// follower stays paused until the vehicle is back, then resumes from rest.
/// ArduPilot stays in GUIDED on a lost stream, so it needs nothing here.
fn resume_external_control(d: &mut DroneRun, since_arm_s: f64, events: &mut Vec<LogEvent>) {
    if d.flavour != Flavour::Px4 {
        return;
    }
    let mode = d.flavour.external_control_mode();
    match &mut d.resume_task {
        None => {
            let current = d.session.state().custom_mode;
            // Land and return are the autopilot's own failsafes: never fight them
            // (`contingency` takes the drone out of the plan instead).
            if contingency::autopilot_failsafe_mode(d.flavour, current) {
                return;
            }
            let out_of_mode = current != mode.custom_mode;
            if out_of_mode && !d.link_lost && !d.telemetry_stale {
                events.push(event(
                    since_arm_s,
                    Some(&d.id),
                    "vehicle left OFFBOARD (offboard-loss failsafe): re-entering it",
                ));
                let session = d.session.clone();
                d.resume_task = Some(tokio::spawn(async move { session.set_mode(mode).await }));
            }
        }
        Some(t) if t.is_finished() => {
            let message = match finished(t) {
                Ok(()) => "back in OFFBOARD: resuming".to_string(),
                Err(e) => format!("OFFBOARD re-entry failed (will retry): {e}"),
            };
            events.push(event(since_arm_s, Some(&d.id), &message));
            d.resume_task = None;
        }
        Some(_) => {}
    }
}

/// The result of a finished command task (panics and cancellations become errors).
fn finished(task: &mut JoinHandle<Result<(), LinkError>>) -> Result<(), String> {
    let Some(result) = futures_now(task) else {
        return Err("task not finished".into());
    };
    result
}

fn futures_now(task: &mut JoinHandle<Result<(), LinkError>>) -> Option<Result<(), String>> {
    use std::future::Future;
    use std::task::{Context, Poll, Waker};
    let mut cx = Context::from_waker(Waker::noop());
    // Outside tokio's cooperative budget: polling 200 finished handles in one tick
    // would otherwise see handle 129 onwards "pending" (the budget is 128), and a
    // drone whose command succeeded would be failed.
    let mut task = tokio::task::unconstrained(task);
    match std::pin::Pin::new(&mut task).poll(&mut cx) {
        Poll::Ready(Ok(r)) => Some(r.map_err(|e| e.to_string())),
        Poll::Ready(Err(e)) => Some(Err(format!("command task failed: {e}"))),
        Poll::Pending => None,
    }
}

/// Sends every streaming drone its setpoint (NED on the wire).
async fn stream(drones: &[DroneRun]) {
    for d in drones {
        let streaming = matches!(
            d.phase,
            Phase::EnterOffboard { .. }
                | Phase::Climb { .. }
                | Phase::AtStart
                | Phase::Flying
                | Phase::AtGoal
                | Phase::AwaitLanding
                | Phase::Lost { .. }
                | Phase::Retiring {
                    stage: RetireStage::Halting | RetireStage::WaitColumn { .. }
                }
        ) || (matches!(d.phase, Phase::AwaitAltitude) && d.last_setpoint.is_some());
        if !streaming {
            continue;
        }
        if let Some(s) = d.last_setpoint {
            // A failed send is one missed setpoint; the vehicle's own timeout and our
            // link-loss detection deal with a link that stays down.
            let _ = d
                .session
                .send_setpoint(
                    frames::ned_f32_from_enu(s.position_m),
                    frames::ned_f32_from_enu(s.velocity_mps),
                )
                .await;
        }
    }
}

/// Separation and speed from telemetry.
fn measure(drones: &[DroneRun], t_exec_s: Option<f64>, landing: bool, out: &mut Outcome) {
    let airborne: Vec<(usize, [f64; 3])> = drones
        .iter()
        .enumerate()
        .filter(|(_, d)| !matches!(d.phase, Phase::Landed | Phase::EnterOffboard { .. }))
        .filter_map(|(i, d)| d.position_m.filter(|p| p[2] > 0.1).map(|p| (i, p)))
        .collect();
    let executing = t_exec_s.is_some() && !landing;
    for (k, (i, a)) in airborne.iter().enumerate() {
        for (j, b) in &airborne[k + 1..] {
            let sep = distance(*a, *b);
            if executing {
                if sep < out.min_separation_m {
                    out.min_separation_m = sep;
                    out.closest_pair = Some((
                        drones[*i].id.clone(),
                        drones[*j].id.clone(),
                        t_exec_s.unwrap_or(0.0),
                    ));
                }
            } else if sep < out.min_separation_takeoff_landing_m {
                out.min_separation_takeoff_landing_m = sep;
            }
        }
    }
    if executing {
        for d in drones {
            out.max_speed_mps = out.max_speed_mps.max(d.speed_mps);
        }
    }
}

fn status_of(d: &DroneRun) -> DroneStatus {
    let events = d.route.events.len().max(1);
    DroneStatus {
        id: d.id.clone(),
        phase: if d.link_lost {
            "LINK LOST"
        } else {
            d.phase.name()
        },
        progress: d.progress.reached as f64 / events as f64,
        next_reach_s: d.route.events.get(d.progress.reached).map(|e| e.reach_s),
        waiting_for: d.waiting_for,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 200 command tasks finishing in the same tick must all read as finished:
    /// polling join handles inside tokio's cooperative budget (128 per tick) used
    /// to report the later ones pending, failing drones whose command succeeded.
    #[tokio::test(flavor = "current_thread")]
    async fn many_finished_tasks_read_as_finished_in_one_tick() {
        let mut tasks: Vec<JoinHandle<Result<(), LinkError>>> =
            (0..200).map(|_| tokio::spawn(async { Ok(()) })).collect();
        for _ in 0..100 {
            if tasks.iter().all(|t| t.is_finished()) {
                break;
            }
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
        let results: Vec<Result<(), String>> = tasks.iter_mut().map(finished).collect();
        assert!(
            results.iter().all(Result::is_ok),
            "{} of 200 read as not finished",
            results.iter().filter(|r| r.is_err()).count()
        );
    }
}
