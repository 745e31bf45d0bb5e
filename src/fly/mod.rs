//! Plan-gated flight: the schedule's trajectories flown over MAVLink, each drone
//! held back at a TPG gate until the events it depends on are seen in telemetry.
//!
//! ```text
//! checked plan ─► connect ─► pre-flight (all) ─► arm (all or none) ─► climb to
//!   the pad layer ─► execute: per drone, follow its route; stop short of a closed
//!   gate ─► land
//! ```
//!
//! The routes are the checked plan's own trajectories ([`compiled::CheckedPlan`]:
//! composed once, passed by the independent checker before anything starts), and
//! every replan's spliced trajectories pass the same checker before they fly.
//!
//! The plan clock starts once every drone hovers above its pad. From then on
//! each drone runs its own rest-to-rest runs (never before their scheduled start,
//! never past a gate whose predecessors are unobserved), so slack absorbs a late
//! drone without replanning and only the drones that depend on it wait.

mod autopilot;
mod command;
mod contingency;
mod course;
mod drone;
mod dry_run;
mod error;
mod executor;
mod feedforward;
mod fence;
mod follower;
mod freeze;
mod gate;
mod gate_limits;
mod last_known;
mod lateness;
mod link_traffic;
mod log;
mod observer;
mod options;
mod path;
mod phase;
mod placement;
mod preflight;
mod replan;
mod report;
mod settings;
mod splice;
mod start_at;
mod tap;
mod unaccounted;
mod vehicle_limits;

pub use dry_run::{DryRun, DryRunDrone, ReadyVehicle, dry_run};
pub use error::FlyError;
pub use fence::{FencePlan, FenceSpan, VehicleFence};
pub use lateness::{EventLateness, LatenessSummary};
pub use link_traffic::LinkTraffic;
pub use log::{
    DroneLog, FlightLog, LogEvent, PLAN_STARTED, ReplanRecord, SPEED_TOLERANCE, Summary,
    TrackingError,
};
pub use observer::{DroneStatus, FlightObserver, FlightStatus};
pub use options::{FlyOptions, VehicleLink};
pub use placement::{FrameFix, FrameSource};
pub use replan::ReplanOptions;
pub use start_at::{StartAt, plan_start_delay_s};

/// The pieces of a replan in flight, public for the replan benchmark
/// (`benches/replan.rs`), which times them apart from a flight.
pub mod replanning {
    pub use super::freeze::{freeze_target, lost_voxels, replan_from_leg};
    pub use super::path::routes;
    pub use super::splice::{Splice, SpliceError, SpliceInput, Survivor, plan_splice};
}

use crate::compiled::{self, CheckedPlan};
use crate::link::Session;
use crate::mission::Mission;
use crate::plan::DiscretePlan;
use drone::DroneRun;
use follower::Follower;
use settings::LoopSettings;
use std::sync::Arc;
use std::time::Instant;

/// Flies `plan` for `mission`: composes and checks it ([`compiled::compile_plan`],
/// refusing before any vehicle is contacted when a limit breaks), then
/// [`fly_checked`]. Returns the flight log whether or not every drone reached
/// its goal (see `summary.completed`); errors are failures before takeoff.
pub async fn fly(
    mission: &Mission,
    plan: &DiscretePlan,
    options: &FlyOptions,
    abort: tokio::sync::watch::Receiver<bool>,
) -> Result<FlightLog, FlyError> {
    let checked = compiled::compile_plan(mission, plan, 0)?;
    fly_checked(mission, &checked, options, abort).await
}

/// Flies `plan` for `mission`: the routes streamed are its trajectories, the
/// ones the checker passed, gated on its execution graph; a replan in flight is
/// checked the same way before it flies. Returns the flight log whether or not
/// every drone reached its goal (see `summary.completed`); errors are failures
/// before takeoff.
pub async fn fly_checked(
    mission: &Mission,
    plan: &CheckedPlan,
    options: &FlyOptions,
    mut abort: tokio::sync::watch::Receiver<bool>,
) -> Result<FlightLog, FlyError> {
    let routes = routes(mission, plan, options)?;
    fits_link_budget(mission)?;
    // Pre-flight gets until the swarm must arm for the start instant, at most.
    let ready_timeout = match &options.start_at {
        Some(start) => start
            .until_arming(std::time::SystemTime::now(), false)?
            .min(options.ready_timeout),
        None => options.ready_timeout,
    };
    let planned_makespan_s = plan.compiled().execution.makespan_s;
    let ids: Vec<String> = routes.iter().map(|r| r.id.clone()).collect();
    let sessions = connect_all(&ids, options).await?;
    let grounds = grounds(&routes);
    let limits = preflight_limits(mission, options, ready_timeout);
    let checked = preflight::check_all(&ids, &sessions, &grounds, limits).await?;
    let flavours: Vec<_> = checked.iter().map(|c| c.flavour).collect();
    start_at::wait_to_arm(options.start_at.as_ref(), &mut abort).await?;
    let armed_at = Instant::now();
    let armed_at_unix_s = start_at::unix_s(std::time::SystemTime::now());
    let bytes_at_arming: Vec<_> = sessions.iter().map(|s| s.bytes()).collect();
    for s in &sessions {
        s.state().recording = true;
    }
    preflight::arm_all(&ids, &sessions, &flavours).await?;

    let l = &mission.limits;
    let commanded = mission.commanded_limits();
    let (commands, inbox) = command::channel();
    let mut drones: Vec<DroneRun> = routes
        .into_iter()
        .zip(sessions)
        .zip(&checked)
        .enumerate()
        .map(|(i, ((route, session), checked))| {
            let response = checked.own_response;
            let follower = Follower::new(commanded.kinematics(), response.accel_lead_s);
            let vehicle = drone::Vehicle {
                session,
                flavour: checked.flavour,
                placed: checked.placed,
                speed_clamp: response.speed_clamp,
            };
            DroneRun::new(i, route, vehicle, follower, commands.clone())
        })
        .collect();
    let settings = loop_settings(mission, options, planned_makespan_s);
    let replanner = replan::Replanner::new(
        options.replan,
        mission.clone(),
        plan.discrete(),
        planned_makespan_s,
        drones.len(),
    );
    let outcome = executor::run(
        &mut drones,
        settings,
        armed_at,
        abort,
        &options.observers,
        inbox,
        replanner,
    )
    .await;
    let duration_s = armed_at.elapsed().as_secs_f64();
    let traffic = report::link_traffic(&drones, &bytes_at_arming, duration_s, mission);
    let drone_logs = report::drone_logs(&drones, &options.vehicles, &traffic, armed_at);
    let flown = report::Flown {
        drones: &drones,
        logs: &drone_logs,
        duration_s,
        planned_makespan_s,
        limits: l,
        check: plan.figures(),
    };
    let summary = report::summary(&flown, &outcome);
    let mut events = report::preflight_events(&ids, &checked);
    events.extend(outcome.events);
    Ok(FlightLog {
        mission: mission.name.clone(),
        summary,
        drones: drone_logs,
        events,
        armed_at_unix_s: Some(armed_at_unix_s),
        start_at_unix_s: options.start_at.map(|s| start_at::unix_s(s.at)),
    })
}

/// Where each drone's vehicle should stand: below its start, on the ground.
fn grounds(routes: &[path::Route]) -> Vec<[f64; 3]> {
    routes
        .iter()
        .map(|r| [r.start_m[0], r.start_m[1], 0.0])
        .collect()
}

/// What pre-flight asks of every vehicle, from the mission and the fly options.
fn preflight_limits(
    mission: &Mission,
    options: &FlyOptions,
    ready_timeout: std::time::Duration,
) -> preflight::PreflightLimits {
    preflight::PreflightLimits {
        frames: options.frames,
        geo_origin: mission.geo_origin,
        mission_limits: mission.limits,
        commanded_limits: mission.commanded_limits(),
        heartbeat_timeout: options.heartbeat_timeout,
        ready_timeout,
        start_tolerance_m: options.start_tolerance_m,
        position_rate_hz: mission.link.setpoint_rate_hz,
        fence: FencePlan::of(mission),
    }
}

/// Refuses a mission whose radios cannot carry its drones' traffic, before any
/// vehicle is contacted.
fn fits_link_budget(mission: &Mission) -> Result<(), FlyError> {
    let refusals = crate::link::budget::Budget::of(mission).refusals();
    if refusals.is_empty() {
        return Ok(());
    }
    Err(FlyError::LinkBudget(
        refusals.into_iter().map(|r| format!("  {r}")).collect(),
    ))
}

/// The flight loop's tunables, from the mission and the fly options.
fn loop_settings(mission: &Mission, options: &FlyOptions, planned_makespan_s: f64) -> LoopSettings {
    let l = &mission.limits;
    let commanded = mission.commanded_limits();
    LoopSettings {
        setpoint_rate_hz: mission.link.setpoint_rate_hz,
        link_timeout_s: mission.link.link_timeout_s,
        lost_after_s: mission.link.lost_after_s,
        limits: commanded.kinematics(),
        tracking_error_m: l.tracking_error_m,
        settle_tolerance_m: settle_tolerance_m(options.settle_tolerance_m, l.tracking_error_m),
        execution_timeout_s: options.timeout_factor * planned_makespan_s
            + settings::TIMEOUT_MARGIN_S,
        timeout_factor: options.timeout_factor,
        safety_distance_m: l.safety_distance_m,
        ellipsoid: l.is_ellipsoid().then(|| l.separation()),
        // Drones fly at cell centres; the lowest, the pad layer's, at the pad height.
        ground_clear: mission.pad_height_m() >= l.safety_distance_m,
        plan_start: options.start_at.map(|s| s.instant()),
        airspace: fence::AirspaceBox::of(mission),
    }
}

/// The checked plan's routes, if it was checked for `mission` and there is a
/// vehicle for each drone.
fn routes(
    mission: &Mission,
    plan: &CheckedPlan,
    options: &FlyOptions,
) -> Result<Vec<path::Route>, FlyError> {
    // Checked against another mission's world and limits is not checked.
    if plan.compiled().mission != mission.name {
        return Err(FlyError::OtherMission {
            plan: plan.compiled().mission.clone(),
            mission: mission.name.clone(),
        });
    }
    let routes = path::routes(plan);
    if options.vehicles.len() != routes.len() {
        return Err(FlyError::VehicleCount {
            plan: routes.len(),
            vehicles: options.vehicles.len(),
        });
    }
    Ok(routes)
}

/// Opens a session with every vehicle, in plan order.
async fn connect_all(ids: &[String], options: &FlyOptions) -> Result<Vec<Arc<Session>>, FlyError> {
    let mut sessions = Vec::new();
    for (id, v) in ids.iter().zip(&options.vehicles) {
        let session = match &v.carried {
            Some(link) => Session::carried(link, v.system_id, options.command_policy),
            None => {
                Session::connect(
                    &v.endpoint,
                    v.system_id,
                    options.command_policy,
                    options.signing_key.as_ref(),
                )
                .await
            }
        }
        .map_err(|source| FlyError::Link {
            drone: id.clone(),
            source,
        })?;
        sessions.push(Arc::new(session));
    }
    Ok(sessions)
}

/// How close telemetry must be to a rest point for the drone to count as there:
/// the option (10 cm by default), or half the tracking bound `e` when that is
/// larger, but never more than `e` (0: not enforced, the option alone).
///
/// Never above `e`: a run started further from its rest point than `e` would hold
/// its setpoint at once. Half of `e`, because the bound is what the safety
/// argument rests on (it is enforced in motion), while waiting to settle closer
/// only costs time: a vehicle that hovers 0.3 m off its setpoint (PX4 SITL's SIH
/// does) would otherwise never count as arrived at 10 cm, and real ArduCopter,
/// 7–15 cm behind its setpoint in motion, spent 3 s per drone of the formation
/// change waiting to come within 10 cm of its corners (1.12× the plan; 1.05× at
/// half the 0.29 m bound, no setpoint held for straying). Starting the next run
/// half the bound away still leaves half of it for lag in motion.
fn settle_tolerance_m(option_m: f64, tracking_error_m: f64) -> f64 {
    if tracking_error_m > 0.0 {
        option_m.max(tracking_error_m / 2.0).min(tracking_error_m)
    } else {
        option_m
    }
}

#[cfg(test)]
mod tests {
    use super::settle_tolerance_m;

    #[test]
    fn settle_tolerance_is_the_option_half_the_bound_or_the_bound() {
        // Tight bound: never more than the bound.
        assert!((settle_tolerance_m(0.10, 0.05) - 0.05).abs() < 1e-12);
        // The swap corridor's 0.115 m: the option.
        assert!((settle_tolerance_m(0.10, 0.115) - 0.10).abs() < 1e-12);
        // The formation change's 0.29 m, or a loose, GPS-grade bound: half of it.
        assert!((settle_tolerance_m(0.10, 0.29) - 0.145).abs() < 1e-12);
        assert!((settle_tolerance_m(0.10, 1.2) - 0.6).abs() < 1e-12);
        // Not enforced: the option alone.
        assert!((settle_tolerance_m(0.10, 0.0) - 0.10).abs() < 1e-12);
    }
}
