//! `fly --dry-run`: everything a flight does before arming, on every vehicle,
//! and nothing after. It connects, runs the whole pre-flight (heartbeat and
//! autopilot, readiness, each vehicle's frame and pad, its own limits and its
//! fence set and read back, the streams the link budget has no room for turned off) and
//! weighs the link budget, then drops the sessions without arming anyone.
//!
//! Unlike a flight, which stops at the first vehicle that fails, a dry run
//! answers for every drone, so an operator fixes the whole swarm in one pass.

use super::error::FlyError;
use super::options::FlyOptions;
use super::placement::FrameFix;
use super::{connect_all, grounds, preflight, preflight_limits, routes};
use crate::compiled::CheckedPlan;
use crate::link::budget::Budget;
use crate::mission::Mission;

/// What a dry run found.
#[derive(Debug, Clone)]
pub struct DryRun {
    /// Every drone, in plan order.
    pub drones: Vec<DryRunDrone>,
    /// The mission's link budget.
    pub budget: Budget,
}

impl DryRun {
    /// Whether the swarm would be allowed to fly: every vehicle ready and every
    /// radio able to carry its drones.
    pub fn ready(&self) -> bool {
        self.drones.iter().all(|d| d.readiness.is_ok()) && self.budget.refusals().is_empty()
    }
}

/// One drone's answer.
#[derive(Debug, Clone)]
pub struct DryRunDrone {
    /// The drone's mission id.
    pub id: String,
    /// Ready, or why not (one line naming the drone).
    pub readiness: Result<ReadyVehicle, String>,
}

/// A vehicle that passed pre-flight.
#[derive(Debug, Clone)]
pub struct ReadyVehicle {
    /// `px4` or `ardupilot`.
    pub autopilot: String,
    /// How its local frame was placed.
    pub frame: FrameFix,
    /// Mission ENU position of its local origin, metres.
    pub local_origin_enu_m: [f64; 3],
    /// Message ids it streamed by default and was asked to stop.
    pub streams_off: Vec<u32>,
    /// Message ids it kept streaming after being asked to stop.
    pub streams_still_on: Vec<u32>,
    /// The fence set on it and read back (it stays set); `None` when the mission
    /// sets none.
    pub fence: Option<super::VehicleFence>,
}

/// Runs the pre-flight of a flight of `plan` on every vehicle of `options` and
/// reports each; arms nobody. Errors are what stops it before any vehicle is
/// checked: the plan is for another mission, a vehicle is missing, a link
/// cannot be opened.
pub async fn dry_run(
    mission: &Mission,
    plan: &CheckedPlan,
    options: &FlyOptions,
) -> Result<DryRun, FlyError> {
    let routes = routes(mission, plan, options)?;
    let ids: Vec<String> = routes.iter().map(|r| r.id.clone()).collect();
    let sessions = connect_all(&ids, options).await?;
    let limits = preflight_limits(mission, options, options.ready_timeout);
    let results = preflight::check_each(&ids, &sessions, &grounds(&routes), limits).await;
    let drones = ids
        .into_iter()
        .zip(results)
        .map(|(id, result)| DryRunDrone {
            id,
            readiness: result.map(|c| ReadyVehicle {
                autopilot: c.flavour.autopilot().to_string(),
                frame: c.placed.fix,
                local_origin_enu_m: c.placed.frame.local_origin_enu_m(),
                streams_off: c.quieted.off,
                streams_still_on: c.quieted.still_on,
                fence: c.fence,
            }),
        })
        .collect();
    // Dropping the sessions stops their tasks: nothing more is sent.
    drop(sessions);
    Ok(DryRun {
        drones,
        budget: Budget::of(mission),
    })
}
