//! The flight log's per-drone records and summary, built from the drones after
//! the loop has ended.

use super::drone::DroneRun;
use super::executor::Outcome;
use super::lateness::LatenessSummary;
use super::link_traffic::LinkTraffic;
use super::log::{DroneLog, LastKnown, LogEvent, Summary, Unaccounted};
use super::options::VehicleLink;
use super::phase::Phase;
use super::preflight::Checked;
use crate::compiled::CheckFigures;
use crate::link::LinkBytes;
use crate::link::budget::Budget;
use crate::mission::{Limits, Mission};
use mavlink::dialects::common::MavLandedState;
use std::time::Instant;

/// What the summary needs besides the loop's measurements.
pub struct Flown<'a> {
    /// Every drone, in plan order, as the loop left them.
    pub drones: &'a [DroneRun],
    /// Their log records (see [`drone_logs`]).
    pub logs: &'a [DroneLog],
    /// From the first arm command to the end of the loop, seconds.
    pub duration_s: f64,
    /// The schedule's makespan, seconds.
    pub planned_makespan_s: f64,
    /// The mission's limits (safety distance, speed limit).
    pub limits: &'a Limits,
    /// What the trajectory checker measured on the plan before arming.
    pub check: &'a CheckFigures,
}

/// Each drone's record for the flight log; telemetry times are seconds since `armed_at`.
pub fn drone_logs(
    drones: &[DroneRun],
    vehicles: &[VehicleLink],
    traffic: &[LinkTraffic],
    armed_at: Instant,
) -> Vec<DroneLog> {
    drones
        .iter()
        .zip(vehicles)
        .zip(traffic)
        .map(|((d, v), traffic)| {
            let s = d.session().state();
            DroneLog {
                id: d.id().to_string(),
                system_id: v.system_id,
                endpoint: v.endpoint.clone(),
                autopilot: Some(d.flavour().autopilot().to_string()),
                goal_m: d.route().goal_m(),
                final_distance_to_goal_m: d.final_distance_to_goal_m(),
                gating_waits: d.gating_waits(),
                gating_wait_s: d.gating_wait_s(),
                longest_gating_wait_s: d.longest_gating_wait_s(),
                lateness: d.lateness().to_vec(),
                link_losses: d.link_losses(),
                tracking_error: d.tracking_error(),
                tracking_holds: d.tracking_holds(),
                tracking_hold_s: d.tracking_hold_s(),
                frame: d.placed().fix,
                local_origin_enu_m: d.frame().local_origin_enu_m(),
                link_traffic: Some(*traffic),
                samples: s
                    .track
                    .iter()
                    .map(|p| {
                        let e = d.frame().mission_from_local(p.position_ned_m);
                        let t = p.received.saturating_duration_since(armed_at).as_secs_f64();
                        [t, e[0], e[1], e[2]]
                    })
                    .collect(),
            }
        })
        .collect()
}

/// What each drone's link carried from arming (`at_arming`) over the flight's
/// `duration_s`, against the mission's link budget.
pub fn link_traffic(
    drones: &[DroneRun],
    at_arming: &[LinkBytes],
    duration_s: f64,
    mission: &Mission,
) -> Vec<LinkTraffic> {
    let budget = Budget::of(mission);
    drones
        .iter()
        .zip(at_arming)
        .map(|(d, at_arming)| {
            let bytes = d.session().bytes().since(*at_arming);
            LinkTraffic::measured(bytes, duration_s, &budget.per_drone)
        })
        .collect()
}

/// What pre-flight left on each vehicle, at time 0: the fence set on it, and the
/// streams the link budget has no room for that it kept sending when asked to stop.
pub fn preflight_events(ids: &[String], checked: &[Checked]) -> Vec<LogEvent> {
    let mut events = Vec::new();
    let fences: Vec<_> = checked.iter().filter_map(|c| c.fence).collect();
    if let Some(span) = super::FenceSpan::of(&fences) {
        events.push(LogEvent {
            t_s: 0.0,
            drone: None,
            message: format!(
                "fence set and read back on {} vehicles: {span}, action {}; it stays set after the flight",
                span.vehicles, span.action
            ),
        });
    }
    for (id, c) in ids.iter().zip(checked) {
        if !c.quieted.still_on.is_empty() {
            events.push(LogEvent {
                t_s: 0.0,
                drone: Some(id.clone()),
                message: format!(
                    "kept streaming message ids {:?} after pre-flight asked it to stop: they spend link capacity the budget does not count",
                    c.quieted.still_on
                ),
            });
        }
    }
    events
}

/// How the flight went, for the log and the command line.
pub fn summary(flown: &Flown<'_>, outcome: &Outcome) -> Summary {
    let drones = flown.drones;
    let logs = flown.logs;
    // Held also when nothing was measured (∞): no two drones were ever heard from.
    let ellipsoid = flown.limits.is_ellipsoid();
    let safety_held = if ellipsoid {
        outcome.min_scaled_separation >= 1.0
    } else {
        outcome.min_separation_m >= flown.limits.safety_distance_m
    };
    // A lost drone a replan flew on without is not ours to land.
    let all_landed = drones.iter().all(|d| {
        matches!(d.phase(), Phase::Landed)
            || (d.left_plan() && matches!(d.phase(), Phase::Lost { .. }))
    });
    let speed_limit_mps = flown.limits.max_speed_mps;
    let speed_held = outcome.max_speed_mps <= speed_limit_mps * (1.0 + super::log::SPEED_TOLERANCE);
    Summary {
        completed: outcome.completed && all_landed && safety_held && speed_held,
        safety_held,
        speed_held,
        fastest: outcome.fastest.clone(),
        duration_s: flown.duration_s,
        planned_makespan_s: flown.planned_makespan_s,
        check: Some(flown.check.clone()),
        executed_makespan_s: outcome.executed_makespan_s,
        min_separation_m: outcome.min_separation_m,
        closest_pair: outcome.closest_pair.clone(),
        safety_distance_m: flown.limits.safety_distance_m,
        vertical_separation_m: flown.limits.vertical_separation_m,
        min_scaled_separation: ellipsoid.then_some(outcome.min_scaled_separation),
        closest_scaled_pair: outcome.closest_scaled_pair.clone(),
        max_speed_mps: outcome.max_speed_mps,
        speed_limit_mps: flown.limits.max_speed_mps,
        gating_waits: logs.iter().map(|d| d.gating_waits).sum(),
        gating_wait_s: logs.iter().map(|d| d.gating_wait_s).sum(),
        longest_gating_wait: logs
            .iter()
            .filter(|d| d.gating_waits > 0)
            .map(|d| (d.id.clone(), d.longest_gating_wait_s))
            .max_by(|a, b| a.1.total_cmp(&b.1)),
        lateness: LatenessSummary::of(logs.iter().map(|d| (d.id.as_str(), &d.lateness[..]))),
        lost: ids_where(drones, |d| matches!(d.phase(), Phase::Lost { .. })),
        lost_last_known: drones
            .iter()
            .zip(logs)
            .filter(|(d, _)| matches!(d.phase(), Phase::Lost { .. }))
            .map(|(d, log)| last_known(d, log))
            .collect(),
        retired: ids_where(drones, |d| d.retired().is_some()),
        handed_over: ids_where(drones, |d| matches!(d.phase(), Phase::HandedOver { .. })),
        unaccounted: drones
            .iter()
            .filter(|d| !accounted_for(d))
            .map(|d| Unaccounted {
                id: d.id().to_string(),
                phase: d.phase().name().to_string(),
                reason: match d.phase() {
                    Phase::Failed(why) => Some(why.to_string()),
                    _ => None,
                },
            })
            .collect(),
        replans: outcome.replans.clone(),
        worst_tracking: logs
            .iter()
            .filter_map(|d| d.tracking_error.map(|t| (d.id.clone(), t)))
            .max_by(|a, b| a.1.p95_m.total_cmp(&b.1.p95_m)),
        tracking_bound_m: flown.limits.tracking_error_m,
        tracking_held: logs
            .iter()
            .filter_map(|d| d.tracking_error)
            .all(|t| t.max_m <= flown.limits.tracking_error_m),
        tracking_holds: logs.iter().map(|d| d.tracking_holds).sum(),
        tracking_hold_s: logs.iter().map(|d| d.tracking_hold_s).sum(),
        // A lost drone's last report says where it was, not where it landed; a
        // drone handed over did not land (both are listed on their own).
        max_final_distance_to_goal_m: drones
            .iter()
            .zip(logs)
            .filter(|(d, _)| !matches!(d.phase(), Phase::Lost { .. } | Phase::HandedOver { .. }))
            .filter_map(|(_, l)| l.final_distance_to_goal_m)
            .fold(0.0, f64::max),
    }
}

/// Whether the flight knows `drone` is on the ground: landed under its plan, or
/// (given up before that) heard disarmed and on the ground since. A lost drone's
/// telemetry is stale and a handed-over one is the pilot's: neither is known.
fn accounted_for(drone: &DroneRun) -> bool {
    match drone.phase() {
        Phase::Landed => true,
        Phase::Lost { .. } | Phase::HandedOver { .. } => false,
        _ => {
            let state = drone.session().state();
            !state.armed && state.on_ground()
        }
    }
}

/// Where a lost drone was last heard from (its last logged sample, in mission
/// ENU), and what its last telemetry said.
fn last_known(drone: &DroneRun, log: &DroneLog) -> LastKnown {
    let state = drone.session().state();
    let last = log.samples.last();
    LastKnown {
        id: log.id.clone(),
        t_s: last.map(|s| s[0]),
        position_m: last.map(|s| [s[1], s[2], s[3]]),
        armed: state.armed,
        landed_state: state.landed_state.map(|l| {
            match l {
                MavLandedState::MAV_LANDED_STATE_ON_GROUND => "on the ground",
                MavLandedState::MAV_LANDED_STATE_IN_AIR => "in the air",
                MavLandedState::MAV_LANDED_STATE_TAKEOFF => "taking off",
                MavLandedState::MAV_LANDED_STATE_LANDING => "landing",
                MavLandedState::MAV_LANDED_STATE_UNDEFINED => "landed state unknown",
            }
            .to_string()
        }),
        battery_pct: state.battery_remaining_pct,
    }
}

fn ids_where(drones: &[DroneRun], keep: impl Fn(&DroneRun) -> bool) -> Vec<String> {
    drones
        .iter()
        .filter(|d| keep(d))
        .map(|d| d.id().to_string())
        .collect()
}
