//! The latest known state of one vehicle, as its telemetry reported it.

use crate::mission::Geodetic;
use mavlink::dialects::common::{MavAutopilot, MavLandedState};
use std::time::Instant;

/// One LOCAL_POSITION_NED sample, stamped on arrival.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionSample {
    /// When it arrived here (the vehicle's own clock is not comparable to ours).
    pub received: Instant,
    /// Local position, NED metres from the vehicle's home.
    pub position_ned_m: [f32; 3],
    /// Velocity, NED metres per second.
    pub velocity_ned_mps: [f32; 3],
}

/// What the reader task has learned so far. Everything is optional until heard.
///
/// Only messages from the vehicle's own system id change it; see
/// `receive::fold` (the reader's half of the link) for the rules.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VehicleState {
    /// The last HEARTBEAT from the vehicle's autopilot component.
    pub last_heartbeat: Option<Instant>,
    /// The last message of any kind from the vehicle's system id: the link is alive.
    pub last_message: Option<Instant>,
    /// The HEARTBEAT autopilot field: which autopilot firmware it runs.
    pub autopilot: Option<MavAutopilot>,
    /// HEARTBEAT base_mode says SAFETY_ARMED.
    pub armed: bool,
    /// HEARTBEAT custom_mode: the flight mode in the autopilot's own encoding
    /// (see [`super::mode::ModeRequest::custom_mode`]).
    pub custom_mode: u32,
    /// The newest LOCAL_POSITION_NED.
    pub position: Option<PositionSample>,
    /// `time_boot_ms` of the newest accepted LOCAL_POSITION_NED (older samples are
    /// late or replayed packets and are ignored).
    pub position_time_boot_ms: Option<u32>,
    /// EXTENDED_SYS_STATE landed state (on ground, taking off, in air, landing).
    pub landed_state: Option<MavLandedState>,
    /// SYS_STATUS says pre-arm checks pass (`None` until a SYS_STATUS arrives).
    pub prearm_ok: Option<bool>,
    /// SYS_STATUS battery_remaining in percent (`None` until heard, or when the
    /// autopilot reports -1, "unknown").
    pub battery_remaining_pct: Option<i8>,
    /// The latest STATUSTEXT: autopilots explain refusals there.
    pub last_status_text: Option<String>,
    /// The latest STATUSTEXT about pre-arm checks (ArduPilot's "PreArm: …", PX4's
    /// "Preflight Fail: …"): why the vehicle will not arm.
    pub prearm_reason: Option<String>,
    /// The latest STATUSTEXT about the geofence (ArduPilot's "Fence Breached…",
    /// PX4's "Geofence…"): why an autopilot took a vehicle over, when it was its
    /// fence.
    pub fence_text: Option<String>,
    /// GPS_GLOBAL_ORIGIN: the geodetic point where the vehicle's local frame is zero.
    pub gps_origin: Option<Geodetic>,
    /// HOME_POSITION's geodetic point (where the vehicle armed or booted).
    pub home: Option<Geodetic>,
    /// How many messages of each id the autopilot component sent (saturating):
    /// the periodic ones pre-flight turns off unless the budget keeps them.
    pub messages_seen: std::collections::BTreeMap<u32, u32>,
    /// Parameters the vehicle reported (PARAM_VALUE), by name.
    pub params: std::collections::BTreeMap<String, f32>,
    /// Every position sample received, for the flight log (when recording is on).
    pub track: Vec<PositionSample>,
    /// Append every position sample to `track` (on from arming, for the flight log).
    pub recording: bool,
}

impl VehicleState {
    /// Seconds since the last heartbeat, or `None` if none was ever heard.
    pub fn heartbeat_age_s(&self, now: Instant) -> Option<f64> {
        self.last_heartbeat
            .map(|t| now.saturating_duration_since(t).as_secs_f64())
    }

    /// Seconds since the last message of any kind from the vehicle, or `None` if
    /// none was ever heard.
    pub fn message_age_s(&self, now: Instant) -> Option<f64> {
        self.last_message
            .map(|t| now.saturating_duration_since(t).as_secs_f64())
    }

    /// On the ground according to EXTENDED_SYS_STATE (unknown counts as not landed).
    pub fn on_ground(&self) -> bool {
        self.landed_state == Some(MavLandedState::MAV_LANDED_STATE_ON_GROUND)
    }
}
