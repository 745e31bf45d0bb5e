//! Pre-flight: every vehicle answers, is a known autopilot, reports a position at
//! its start and passes its pre-arm checks — all before anybody arms. Then arming,
//! all or nothing: if one vehicle refuses, everyone already armed is disarmed.

use super::autopilot::{self, Flavour};
use super::error::FlyError;
use super::fence::{self, FencePlan, VehicleFence};
use super::placement::{self, FrameSource, Placed, PlacementRules};
use crate::link::{Quieted, Session};
use crate::mission::{Geodetic, Limits};
use std::sync::Arc;
use std::time::Duration;
use tokio::task::JoinSet;

/// How a vehicle must present itself before the swarm may arm.
#[derive(Debug, Clone, Copy)]
pub struct PreflightLimits {
    /// Shared or per-vehicle local frames (see `placement`).
    pub frames: FrameSource,
    /// The mission's `world.geo_origin`, if it has one.
    pub geo_origin: Option<Geodetic>,
    /// The mission's limits, set as the autopilot's own (see `vehicle_limits`).
    pub mission_limits: Limits,
    /// The limits trajectories are flown with (`Mission::commanded_limits`): the
    /// autopilot's own landing is slowed to their speed.
    pub commanded_limits: Limits,
    /// How long to wait for each vehicle's first HEARTBEAT.
    pub heartbeat_timeout: Duration,
    /// How long to wait for each vehicle to be ready: position telemetry and pre-arm
    /// checks passing.
    pub ready_timeout: Duration,
    /// Horizontal distance allowed between a vehicle and its pad.
    pub start_tolerance_m: f64,
    /// Rate at which position telemetry is requested.
    pub position_rate_hz: f64,
    /// The fence each vehicle is given around the airspace; `None`: left as it is.
    pub fence: Option<FencePlan>,
}

/// How long pre-flight listens before it turns off the streams the link budget
/// does not keep (`Session::quiet_other_streams`).
const STREAMS_HEARD_WITHIN: Duration = Duration::from_millis(2500);

/// How often a vehicle found off its pad is looked at again.
const PLACE_RETRY: Duration = Duration::from_millis(500);

/// Checks one vehicle and places its frame; `Err` is a one-line explanation naming
/// the drone.
async fn check_one(
    id: String,
    session: Arc<Session>,
    pad_enu_m: [f64; 3],
    limits: PreflightLimits,
) -> Result<Checked, String> {
    let checks_started = std::time::Instant::now();
    let announced = session
        .wait_heartbeat(limits.heartbeat_timeout)
        .await
        .map_err(|e| format!("{id} ({}): {e}", session.endpoint))?;
    let flavour = autopilot::from_heartbeat(announced).ok_or_else(|| {
        format!(
            "{id} ({}): system {} is not a PX4 or ArduPilot autopilot ({announced:?})",
            session.endpoint, session.system_id
        )
    })?;
    session
        .request_rates(limits.position_rate_hz)
        .await
        .map_err(|e| format!("{id}: cannot set telemetry rates: {e}"))?;
    let ready_deadline = std::time::Instant::now() + limits.ready_timeout;
    wait_ready(&id, &session, limits.ready_timeout).await?;
    let (position, prearm_ok, armed, reason) = {
        let s = session.state();
        (
            s.position.map(|p| p.position_ned_m),
            s.prearm_ok.unwrap_or(false),
            s.armed,
            s.prearm_reason
                .clone()
                .or_else(|| s.last_status_text.clone()),
        )
    };
    if armed {
        return Err(format!("{id}: already armed before pre-flight"));
    }
    if !prearm_ok {
        return Err(format!(
            "{id}: pre-arm checks fail (SYS_STATUS){}",
            reason.map(|r| format!(": {r}")).unwrap_or_default()
        ));
    }
    let Some(mut reported_ned_m) = position else {
        return Err(format!("{id}: no position telemetry"));
    };
    let rules = PlacementRules {
        source: limits.frames,
        geo_origin: limits.geo_origin,
        tolerance_m: limits.start_tolerance_m,
    };
    // A fresh estimator is still converging when it first reports ready (PX4 sets
    // its origin from its first, noisy GPS fix and walks its position in over some
    // 10 s): a vehicle found off its pad is looked at again until the readiness
    // deadline before it is refused.
    let placed = loop {
        match placement::place(&id, &session, pad_enu_m, reported_ned_m, rules).await {
            Ok(placed) => break placed,
            Err(why) if std::time::Instant::now() + PLACE_RETRY >= ready_deadline => {
                return Err(why);
            }
            Err(_) => {
                tokio::time::sleep(PLACE_RETRY).await;
                if let Some(p) = session.state().position.map(|p| p.position_ned_m) {
                    reported_ned_m = p;
                }
            }
        }
    };
    let own_response = super::vehicle_limits::apply(
        &id,
        &session,
        flavour,
        &limits.mission_limits,
        &limits.commanded_limits,
    )
    .await?;
    // Last: a vehicle refused before this keeps the fence it had.
    let fence = match limits.fence {
        Some(plan) => {
            let fence = plan.for_pad(pad_enu_m);
            fence::apply(&id, &session, flavour, &fence).await?;
            Some(fence)
        }
        None => None,
    };
    // Long enough to have heard every stream of 1 Hz or faster twice.
    tokio::time::sleep_until((checks_started + STREAMS_HEARD_WITHIN).into()).await;
    let quieted = session.quiet_other_streams().await;
    Ok(Checked {
        flavour,
        placed,
        own_response,
        quieted,
        fence,
    })
}

/// Waits until the vehicle reports a position and passing pre-arm checks, as real
/// autopilots do only once EKF and GPS have converged. When the checks first fail
/// it asks the autopilot to run them again, so it says why (STATUSTEXT). At the
/// deadline, says what is missing.
async fn wait_ready(id: &str, session: &Session, within: Duration) -> Result<(), String> {
    let started = std::time::Instant::now();
    let mut asked = false;
    loop {
        let (position, prearm_ok) = {
            let s = session.state();
            (s.position.is_some(), s.prearm_ok)
        };
        if position && prearm_ok == Some(true) {
            return Ok(());
        }
        if prearm_ok == Some(false) && !asked {
            asked = true;
            // Unsupported (PX4, the mock without a failing check) is fine: the
            // reason, if any, comes by STATUSTEXT either way.
            let _ = session.run_prearm_checks().await;
        }
        if started.elapsed() >= within {
            let mut missing = Vec::new();
            if !position {
                missing.push("no position telemetry".to_string());
            }
            // Failing checks are reported with their reason by the caller.
            if prearm_ok.is_none() {
                missing.push("no SYS_STATUS (health unknown)".to_string());
            }
            if missing.is_empty() {
                return Ok(());
            }
            return Err(format!(
                "{id}: not ready after {:.0} s: {}",
                within.as_secs_f64(),
                missing.join(", ")
            ));
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// What pre-flight learned of one vehicle.
#[derive(Debug, Clone)]
pub struct Checked {
    /// Its autopilot family.
    pub flavour: &'static dyn Flavour,
    /// Its local frame.
    pub placed: Placed,
    /// How its controller takes our feed-forward (see
    /// [`super::vehicle_limits::OwnResponse`]).
    pub own_response: super::vehicle_limits::OwnResponse,
    /// The default streams turned off to keep to the link budget, and any the
    /// vehicle kept sending.
    pub quieted: Quieted,
    /// The fence set on it and read back; `None` when the mission sets none.
    pub fence: Option<VehicleFence>,
}

/// Runs every check concurrently and returns each vehicle's flavour and frame, or
/// every failure.
pub async fn check_all(
    ids: &[String],
    sessions: &[Arc<Session>],
    pads_enu_m: &[[f64; 3]],
    limits: PreflightLimits,
) -> Result<Vec<Checked>, FlyError> {
    let results = check_each(ids, sessions, pads_enu_m, limits).await;
    let mut failures: Vec<String> = results
        .iter()
        .filter_map(|r| r.as_ref().err().map(|why| format!("  {why}")))
        .collect();
    if !failures.is_empty() {
        failures.sort();
        return Err(FlyError::Preflight(failures));
    }
    Ok(results.into_iter().flatten().collect())
}

/// Runs every check concurrently; each vehicle's result in the order of `ids`
/// (a failure is one line naming the drone).
pub async fn check_each(
    ids: &[String],
    sessions: &[Arc<Session>],
    pads_enu_m: &[[f64; 3]],
    limits: PreflightLimits,
) -> Vec<Result<Checked, String>> {
    let mut set = JoinSet::new();
    for (i, (id, session)) in ids.iter().zip(sessions).enumerate() {
        let fut = check_one(id.clone(), session.clone(), pads_enu_m[i], limits);
        set.spawn(async move { (i, fut.await) });
    }
    let mut results: Vec<Option<Result<Checked, String>>> = vec![None; ids.len()];
    let mut crashed = Vec::new();
    while let Some(joined) = set.join_next().await {
        match joined {
            Ok((i, result)) => results[i] = Some(result),
            Err(e) => crashed.push(format!("a check task failed: {e}")),
        }
    }
    // A check task that failed leaves its drone without a result: reported as
    // such (with why, when it is known), never guessed.
    results
        .into_iter()
        .zip(ids)
        .map(|(r, id)| {
            r.unwrap_or_else(|| {
                Err(format!(
                    "{id}: no pre-flight result{}",
                    crashed
                        .first()
                        .map(|c| format!(" ({c})"))
                        .unwrap_or_default()
                ))
            })
        })
        .collect()
}

/// Arms everyone (ArduPilot: GUIDED first, as Copter takes off only from GUIDED).
/// If any vehicle fails, disarms every vehicle that is armed and reports why.
pub async fn arm_all(
    ids: &[String],
    sessions: &[Arc<Session>],
    flavours: &[&'static dyn Flavour],
) -> Result<(), FlyError> {
    let mut set = JoinSet::new();
    for (i, session) in sessions.iter().enumerate() {
        let session = session.clone();
        let flavour = flavours[i];
        set.spawn(async move {
            if flavour.external_control_before_arming() {
                session.set_mode(flavour.external_control_mode()).await?;
            }
            session.arm().await.map(|()| i)
        });
    }
    let mut failures = Vec::new();
    let mut index_of_failure = Vec::new();
    while let Some(joined) = set.join_next().await {
        match joined {
            Ok(Ok(_)) => {}
            Ok(Err(e)) => failures.push(e),
            Err(e) => index_of_failure.push(format!("  an arming task failed: {e}")),
        }
    }
    if failures.is_empty() && index_of_failure.is_empty() {
        return Ok(());
    }
    // Name the drones that refused (the error carries the vehicle's reason).
    let mut lines: Vec<String> = Vec::new();
    for (id, session) in ids.iter().zip(sessions) {
        if !session.state().armed {
            lines.push(format!("  {id}: not armed"));
        }
    }
    for e in &failures {
        lines.push(format!("  {e}"));
    }
    lines.extend(index_of_failure);
    disarm_all(ids, sessions, &mut lines).await;
    Err(FlyError::Arming(lines))
}

/// Disarms every armed vehicle (on the ground: no force), noting failures in `lines`.
pub async fn disarm_all(ids: &[String], sessions: &[Arc<Session>], lines: &mut Vec<String>) {
    let mut set = JoinSet::new();
    for (id, session) in ids.iter().zip(sessions) {
        if session.state().armed {
            let (id, session) = (id.clone(), session.clone());
            set.spawn(async move { (id, session.disarm(false).await) });
        }
    }
    while let Some(joined) = set.join_next().await {
        match joined {
            Ok((id, Ok(()))) => lines.push(format!("  {id}: disarmed")),
            Ok((id, Err(e))) => lines.push(format!("  {id}: DISARM FAILED: {e}")),
            Err(e) => lines.push(format!("  a disarm task failed: {e}")),
        }
    }
}
