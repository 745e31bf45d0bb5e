//! Plan-gated flight: the schedule's trajectories flown over MAVLink, each drone
//! held back at a TPG gate until the events it depends on are seen in telemetry.
//!
//! ```text
//! connect ─► pre-flight (all) ─► arm (all or none) ─► take off to start voxels
//!   ─► execute: per drone, follow its route; stop short of a closed gate ─► land
//! ```
//!
//! The plan clock starts once every drone hovers at its start voxel. From then on
//! each drone runs its own rest-to-rest runs (never before their scheduled start,
//! never past a gate whose predecessors are unobserved), so slack absorbs a late
//! drone without replanning and only the drones that depend on it wait.

pub mod contingency;
pub mod error;
pub mod executor;
pub mod faults;
pub mod follower;
pub mod gate;
pub mod log;
pub mod observer;
pub mod path;
pub mod preflight;

pub use error::FlyError;
pub use faults::{FaultSpec, parse_fault};
pub use log::{DroneLog, FlightLog, Summary};
pub use observer::{DroneStatus, FlightObserver, FlightStatus};

use crate::link::{CommandPolicy, Flavour, Session, SigningKey, frames};
use crate::mission::Mission;
use crate::plan::DiscretePlan;
use crate::schedule;
use executor::{DroneRun, LoopSettings, Phase};
use follower::Follower;
use gate::Progress;
use path::Route;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Where to reach one drone's autopilot.
#[derive(Debug, Clone)]
pub struct VehicleLink {
    /// rust-mavlink address, e.g. `udpout:127.0.0.1:14540`.
    pub endpoint: String,
    pub system_id: u8,
}

/// Everything `fly` needs besides the mission and plan.
#[derive(Clone)]
pub struct FlyOptions {
    /// One per drone, in plan order.
    pub vehicles: Vec<VehicleLink>,
    pub heartbeat_timeout: Duration,
    /// Horizontal distance allowed between a vehicle and the point below its start voxel.
    pub start_tolerance_m: f64,
    /// Telemetry this close to a commanded rest point counts as arrived.
    pub settle_tolerance_m: f64,
    /// Plan execution gives up (holds, lands) after `factor × makespan + 30 s`.
    pub timeout_factor: f64,
    pub command_policy: CommandPolicy,
    /// See every telemetry sample, event and status live (a Rerun recorder, a
    /// status line), in this order.
    pub observers: Vec<Arc<dyn FlightObserver>>,
    /// MAVLink 2 signing key shared with the vehicles; `None` flies unsigned.
    pub signing_key: Option<SigningKey>,
}

impl std::fmt::Debug for FlyOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FlyOptions")
            .field("vehicles", &self.vehicles)
            .field("heartbeat_timeout", &self.heartbeat_timeout)
            .field("start_tolerance_m", &self.start_tolerance_m)
            .field("settle_tolerance_m", &self.settle_tolerance_m)
            .field("timeout_factor", &self.timeout_factor)
            .field("command_policy", &self.command_policy)
            .field("observers", &self.observers.len())
            .field("signing_key", &self.signing_key)
            .finish()
    }
}

impl FlyOptions {
    pub fn new(vehicles: Vec<VehicleLink>) -> Self {
        Self {
            vehicles,
            heartbeat_timeout: Duration::from_secs(5),
            start_tolerance_m: 0.3,
            settle_tolerance_m: 0.05,
            timeout_factor: 4.0,
            command_policy: CommandPolicy::default(),
            observers: Vec::new(),
            signing_key: None,
        }
    }
}

/// Flies `plan` for `mission`. Returns the flight log whether or not every drone
/// reached its goal (see `summary.completed`); errors are failures before takeoff.
pub async fn fly(
    mission: &Mission,
    plan: &DiscretePlan,
    options: &FlyOptions,
    abort: tokio::sync::watch::Receiver<bool>,
) -> Result<FlightLog, FlyError> {
    let tpg = schedule::build(mission, plan)?;
    let sched = schedule::solve(&tpg)?;
    let trajectories = crate::trajectory::from_schedule(&sched);
    let execution = schedule::execution_plan(&tpg, &sched);
    if options.vehicles.len() != plan.drones.len() {
        return Err(FlyError::VehicleCount {
            plan: plan.drones.len(),
            vehicles: options.vehicles.len(),
        });
    }
    let routes: Vec<Route> = trajectories
        .drones
        .iter()
        .zip(&execution.drones)
        .map(|(t, e)| Route::new(t, e))
        .collect();
    let ids: Vec<String> = routes.iter().map(|r| r.id.clone()).collect();

    let mut sessions = Vec::new();
    for (id, v) in ids.iter().zip(&options.vehicles) {
        let session = Session::connect(
            &v.endpoint,
            v.system_id,
            options.command_policy,
            options.signing_key.as_ref(),
        )
        .await
        .map_err(|source| FlyError::Link {
            drone: id.clone(),
            source,
        })?;
        sessions.push(Arc::new(session));
    }
    let grounds: Vec<[f64; 3]> = routes
        .iter()
        .map(|r| [r.start_m[0], r.start_m[1], 0.0])
        .collect();
    let limits = preflight::PreflightLimits {
        heartbeat_timeout: options.heartbeat_timeout,
        start_tolerance_m: options.start_tolerance_m,
        position_rate_hz: mission.link.setpoint_rate_hz,
    };
    let flavours = preflight::check_all(&ids, &sessions, &grounds, limits).await?;
    let armed_at = Instant::now();
    for s in &sessions {
        s.state().recording = true;
    }
    preflight::arm_all(&ids, &sessions, &flavours).await?;

    let l = &mission.limits;
    let mut drones: Vec<DroneRun> = routes
        .into_iter()
        .zip(sessions.iter().cloned())
        .zip(flavours)
        .map(|((route, session), flavour)| DroneRun {
            id: route.id.clone(),
            session,
            flavour,
            follower: Follower::new(l.max_speed_mps, l.max_accel_mps2),
            progress: Progress::default(),
            passed_events: 0,
            phase: match flavour {
                Flavour::Px4 => Phase::EnterOffboard {
                    since: Instant::now(),
                    task: None,
                },
                Flavour::Ardupilot => Phase::Takeoff { task: None },
            },
            route,
            position_m: None,
            speed_mps: 0.0,
            link_lost: false,
            link_losses: 0,
            silent_s: 0.0,
            retired: None,
            released: false,
            telemetry_stale: false,
            resume_task: None,
            gating_waits: 0,
            gating_wait_s: 0.0,
            waiting_for: None,
            final_distance_to_goal_m: None,
            last_setpoint: None,
        })
        .collect();
    let settings = LoopSettings {
        setpoint_rate_hz: mission.link.setpoint_rate_hz,
        link_timeout_s: mission.link.link_timeout_s,
        max_speed_mps: l.max_speed_mps,
        max_accel_mps2: l.max_accel_mps2,
        settle_tolerance_m: options.settle_tolerance_m,
        execution_timeout_s: options.timeout_factor * execution.makespan_s + 30.0,
        safety_distance_m: l.safety_distance_m,
        // Drones fly at voxel centres; the lowest layer's centre is at origin z.
        ground_clear: mission.world.origin_m()[2] >= l.safety_distance_m,
    };
    let outcome = executor::run(&mut drones, settings, armed_at, abort, &options.observers).await;
    let duration_s = armed_at.elapsed().as_secs_f64();

    let drone_logs: Vec<DroneLog> = drones
        .iter()
        .zip(&options.vehicles)
        .map(|(d, v)| {
            let s = d.session.state();
            DroneLog {
                id: d.id.clone(),
                system_id: v.system_id,
                endpoint: v.endpoint.clone(),
                autopilot: Some(d.flavour.to_string()),
                goal_m: d.route.goal_m(),
                final_distance_to_goal_m: d.final_distance_to_goal_m,
                gating_waits: d.gating_waits,
                gating_wait_s: d.gating_wait_s,
                link_losses: d.link_losses,
                samples: s
                    .track
                    .iter()
                    .map(|p| {
                        let e = frames::enu_from_ned_f32(p.position_ned_m);
                        let t = p.received.saturating_duration_since(armed_at).as_secs_f64();
                        [t, e[0], e[1], e[2]]
                    })
                    .collect(),
            }
        })
        .collect();
    let summary = Summary {
        completed: outcome.completed,
        duration_s,
        planned_makespan_s: execution.makespan_s,
        executed_makespan_s: outcome.executed_makespan_s,
        min_separation_m: outcome.min_separation_m,
        closest_pair: outcome.closest_pair,
        min_separation_takeoff_landing_m: outcome.min_separation_takeoff_landing_m,
        safety_distance_m: l.safety_distance_m,
        max_speed_mps: outcome.max_speed_mps,
        speed_limit_mps: l.max_speed_mps,
        gating_waits: drone_logs.iter().map(|d| d.gating_waits).sum(),
        gating_wait_s: drone_logs.iter().map(|d| d.gating_wait_s).sum(),
        lost: ids_where(&drones, |d| matches!(d.phase, Phase::Lost { .. })),
        retired: ids_where(&drones, |d| d.retired.is_some()),
        handed_over: ids_where(&drones, |d| matches!(d.phase, Phase::HandedOver { .. })),
        max_final_distance_to_goal_m: drone_logs
            .iter()
            .filter_map(|d| d.final_distance_to_goal_m)
            .fold(0.0, f64::max),
    };
    Ok(FlightLog {
        mission: mission.name.clone(),
        summary,
        drones: drone_logs,
        events: outcome.events,
    })
}

fn ids_where(drones: &[DroneRun], keep: impl Fn(&DroneRun) -> bool) -> Vec<String> {
    drones
        .iter()
        .filter(|d| keep(d))
        .map(|d| d.id.clone())
        .collect()
}
