//! Pre-flight placement: where each vehicle's own local frame sits in the mission
//! frame, and whether the vehicle stands on its pad.
//!
//! Real autopilots start their local frame where they first got a GPS fix, so every
//! vehicle has its own. swarmctl learns each vehicle's `mission_from_local`
//! transform ([`VehicleFrame`]) here, once, before anybody arms:
//!
//! * **`world.geo_origin` given:** horizontally from the vehicle's GPS origin
//!   (`GPS_GLOBAL_ORIGIN`, requested; else `HOME_POSITION`, taken as where it stands
//!   now). Where that puts the vehicle must be its pad, within the start tolerance:
//!   a vehicle on the wrong pad is refused with both positions named.
//! * **no geo origin:** from placement — the vehicle stands on its pad. Nothing can
//!   tell a wrong pad then; the flight log says which frames were placed this way.
//! * **[`FrameSource::Shared`]:** every vehicle reports in the mission frame (a
//!   common EKF origin set by hand, or the bundled simulator's `--shared-frame`), and
//!   its reported position must be its pad.
//!
//! Heights always come from placement: every pad is on the ground (mission z = 0),
//! and GPS altitude is metres too coarse to hover 0.5 m above a pad by.

use crate::link::{Session, VehicleFrame, frames};
use crate::mission::Geodetic;
use serde::{Deserialize, Serialize};
use std::time::Duration;

/// MAVLink message ids asked for when the vehicle has not sent them on its own.
const GPS_GLOBAL_ORIGIN_ID: u32 = 49;
const HOME_POSITION_ID: u32 = 242;
/// How long to wait for a requested origin.
const ORIGIN_WAIT: Duration = Duration::from_secs(3);

/// How the vehicles' local frames relate to the mission frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameSource {
    /// Each vehicle has its own local frame (real autopilots): learned from its GPS
    /// origin with `world.geo_origin`, else from its placement on its pad.
    #[default]
    PerVehicle,
    /// Every vehicle reports in the mission frame already.
    Shared,
}

/// How one vehicle's frame was found, for the flight log.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameFix {
    /// Its reported frame is the mission's.
    Shared,
    /// From its GPS_GLOBAL_ORIGIN and the mission's geo origin.
    GpsOrigin,
    /// From its HOME_POSITION (it stands at home) and the mission's geo origin.
    HomePosition,
    /// From its placement on its pad (no geo origin: a wrong pad goes unnoticed).
    Placement,
}

impl std::fmt::Display for FrameFix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FrameFix::Shared => "shared frame",
            FrameFix::GpsOrigin => "GPS origin",
            FrameFix::HomePosition => "home position",
            FrameFix::Placement => "placement on its pad",
        })
    }
}

/// One vehicle's transform and how it was found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placed {
    /// Its `mission_from_local` transform.
    pub frame: VehicleFrame,
    /// How it was found.
    pub fix: FrameFix,
}

/// What placing a vehicle needs besides its session.
#[derive(Debug, Clone, Copy)]
pub struct PlacementRules {
    /// Shared or per-vehicle frames.
    pub source: FrameSource,
    /// The mission's `world.geo_origin`.
    pub geo_origin: Option<Geodetic>,
    /// Horizontal distance allowed between where a vehicle is found and its pad.
    pub tolerance_m: f64,
}

/// Finds the frame of the vehicle `id` standing (it should) on the pad at
/// `pad_enu_m` and reporting `reported_ned_m`; `Err` is a one-line refusal.
pub async fn place(
    id: &str,
    session: &Session,
    pad_enu_m: [f64; 3],
    reported_ned_m: [f32; 3],
    rules: PlacementRules,
) -> Result<Placed, String> {
    let by_placement = VehicleFrame::from_placement(pad_enu_m, reported_ned_m);
    let (frame, fix) = match (rules.source, rules.geo_origin) {
        (FrameSource::Shared, _) => (VehicleFrame::SHARED, FrameFix::Shared),
        (FrameSource::PerVehicle, None) => {
            return Ok(Placed {
                frame: by_placement,
                fix: FrameFix::Placement,
            });
        }
        (FrameSource::PerVehicle, Some(mission_origin)) => {
            let (origin_enu_m, fix) =
                vehicle_origin(id, session, &mission_origin, reported_ned_m).await?;
            // Horizontal from GPS, height from placement (see the module docs).
            let z = by_placement.local_origin_enu_m()[2];
            (
                VehicleFrame::with_origin([origin_enu_m[0], origin_enu_m[1], z]),
                fix,
            )
        }
    };
    let at = frame.mission_from_local(reported_ned_m);
    let off_m = (at[0] - pad_enu_m[0]).hypot(at[1] - pad_enu_m[1]);
    // NaN (no position) fails too.
    if off_m.is_nan() || off_m > rules.tolerance_m {
        let how = match fix {
            FrameFix::Shared => "reports itself",
            _ => "its GPS puts it",
        };
        return Err(format!(
            "{id}: {how} at ENU ({:.2}, {:.2}) m, {off_m:.2} m from its pad at ({:.2}, {:.2}) m — on the wrong pad? (tolerance {:.2} m)",
            centimetres(at[0]),
            centimetres(at[1]),
            pad_enu_m[0],
            pad_enu_m[1],
            rules.tolerance_m
        ));
    }
    Ok(Placed { frame, fix })
}

/// `x` rounded to the centimetre, without the sign of a rounded-away noise
/// (a vehicle a millimetre west of its pad is at 0.00, not -0.00).
fn centimetres(x: f64) -> f64 {
    (x * 100.0).round() / 100.0 + 0.0
}

/// Mission ENU position of the vehicle's local origin from its GPS origin, asked
/// for if not yet heard; else from its home position, where it stands now.
async fn vehicle_origin(
    id: &str,
    session: &Session,
    mission_origin: &Geodetic,
    reported_ned_m: [f32; 3],
) -> Result<([f64; 3], FrameFix), String> {
    if let Some(origin) = wait_for(session, GPS_GLOBAL_ORIGIN_ID, |s| s.gps_origin).await {
        return Ok((
            frames::enu_between(mission_origin, &origin),
            FrameFix::GpsOrigin,
        ));
    }
    if let Some(home) = wait_for(session, HOME_POSITION_ID, |s| s.home).await {
        let home_enu_m = frames::enu_between(mission_origin, &home);
        let here = frames::enu_from_ned_f32(reported_ned_m);
        let origin = std::array::from_fn(|i| home_enu_m[i] - here[i]);
        return Ok((origin, FrameFix::HomePosition));
    }
    Err(format!(
        "{id}: sent neither GPS_GLOBAL_ORIGIN nor HOME_POSITION within {:.0} s of asking, so its frame cannot be placed from world.geo_origin (no GPS fix yet?)",
        2.0 * ORIGIN_WAIT.as_secs_f64()
    ))
}

/// The value `get` reads from the vehicle state, requesting message `id` once if
/// it is not there yet and waiting up to [`ORIGIN_WAIT`] for it.
async fn wait_for<T>(
    session: &Session,
    message_id: u32,
    get: impl Fn(&crate::link::VehicleState) -> Option<T>,
) -> Option<T> {
    if let Some(v) = get(&session.state()) {
        return Some(v);
    }
    // Unsupported is fine: the vehicle may still send it on its own.
    let _ = session.request_message(message_id).await;
    let started = std::time::Instant::now();
    while started.elapsed() < ORIGIN_WAIT {
        if let Some(v) = get(&session.state()) {
            return Some(v);
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    None
}
