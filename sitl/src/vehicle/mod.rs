//! One mock autopilot: armed state, flight mode, failsafes and the fixed-step
//! update that turns the mode into a setpoint for the dynamics.
//!
//! The vehicle is pure state: it never touches a socket. Incoming messages go
//! through [`Vehicle::handle`] and everything it wants to say lands in its
//! outbox ([`Vehicle::take_outbox`]), so the whole state machine is
//! unit-testable without I/O.
//!
//! The state and its fixed step live here; the time-driven mode transitions and
//! failsafes in `transitions`, the setpoint each mode tracks in `guidance`.
//! Handling incoming messages is in `commands` and `setpoints`, building
//! telemetry in `telemetry`.

use crate::config::{Flavour, VehicleConfig};
use crate::dynamics::{Body, Limits, Setpoint};
use crate::geo::GeoPoint;
use crate::mode::FlightMode;
use crate::params::Params;
use crate::streams::Streams;
use mavlink::dialects::common::{MavMessage, MavSeverity, STATUSTEXT_DATA};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::collections::VecDeque;
use std::time::Duration;

mod fence;
mod guidance;
mod transitions;

/// Setpoints must have arrived within this window, at least
/// [`OFFBOARD_MIN_SETPOINTS`] of them, for OFFBOARD to be accepted (> 2 Hz).
const OFFBOARD_STREAM_WINDOW_S: f64 = 1.0;
/// Setpoints needed inside the window: three in one second is "more than 2 Hz".
const OFFBOARD_MIN_SETPOINTS: usize = 3;
/// PX4's COM_OF_LOSS_T default: no setpoint for this long is offboard loss.
pub const OFFBOARD_LOSS_TIMEOUT_S: f64 = 1.0;
/// Height above which the vehicle is airborne, metres.
const AIRBORNE_HEIGHT_M: f32 = 0.1;
/// Battery drain while armed, percent per second (a ~30 minute pack).
const BATTERY_DRAIN_PCT_PER_S: f32 = 0.05;
/// Charge reported (at most) once the low-battery fault fires, percent.
pub const LOW_BATTERY_PCT: f32 = 25.0;
/// Charge reported (at most) once the critical-battery fault fires, percent.
pub const CRITICAL_BATTERY_PCT: f32 = 8.0;

/// A fault or timeout duration in seconds; [`Duration::MAX`] means never
/// (+∞), not "in 584 billion years". No `Instant` arithmetic is involved, so
/// nothing can overflow.
fn seconds_or_never(duration: Duration) -> f64 {
    if duration == Duration::MAX {
        f64::INFINITY
    } else {
        duration.as_secs_f64()
    }
}

/// A position/velocity target received over MAVLink, with its arrival time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExternalTarget {
    /// The decoded setpoint, already in the shared local NED frame.
    pub setpoint: Setpoint,
    /// Simulation time it arrived, seconds.
    pub received_s: f64,
}

/// One mock autopilot's complete state. `Clone` and `PartialEq` let tests
/// check that a message left the state exactly as it was.
#[derive(Debug, Clone, PartialEq)]
pub struct Vehicle {
    /// MAVLink system id.
    pub(crate) system_id: u8,
    /// Autopilot imitated.
    pub(crate) flavour: Flavour,
    /// Start position on the ground, shared NED frame.
    pub(crate) initial_position_ned_m: [f32; 3],
    /// Geodetic position of the start point.
    pub(crate) home: GeoPoint,
    /// Zero of the vehicle's local frame, shared NED frame.
    pub(crate) local_origin_ned_m: [f32; 3],
    /// Kinematic limits including the speed-factor fault.
    pub(crate) limits: Limits,
    /// The configuration it was built from (faults, timeouts).
    pub(crate) config: VehicleConfig,
    /// True physical state.
    pub(crate) body: Body,
    /// Motors armed.
    pub(crate) armed: bool,
    /// Current flight mode.
    pub(crate) mode: FlightMode,
    /// Simulation time since boot, seconds.
    pub(crate) time_s: f64,
    /// Total time spent armed, seconds (drives the low-battery fault).
    pub(crate) armed_time_s: f64,
    /// When the vehicle first left the ground (drives the link-drop fault).
    pub(crate) first_airborne_s: Option<f64>,
    /// Since when it has been resting on the ground while armed.
    resting_since_s: Option<f64>,
    /// Position held in Hold/Manual/Guided-without-target.
    hold: Setpoint,
    /// Takeoff in progress: target height above ground, metres.
    pub(crate) takeoff_height_m: Option<f32>,
    /// RTL has reached home and is descending.
    rtl_descending: bool,
    /// Last external setpoint (SET_POSITION_TARGET_*).
    pub(crate) external: Option<ExternalTarget>,
    /// Arrival times of recent setpoints, for the > 2 Hz offboard rule.
    setpoint_times_s: VecDeque<f64>,
    /// PX4 offboard-loss failsafe active since this time (holding, then landing).
    offboard_lost_since_s: Option<f64>,
    /// ArduPilot: the velocity target timed out and was replaced by a stop.
    velocity_timed_out: bool,
    /// Battery state of charge, percent.
    pub(crate) battery_pct: f32,
    /// The low-battery warning fired (also set by a critical battery).
    pub(crate) battery_low: bool,
    /// The critical-battery failsafe fired.
    pub(crate) battery_critical: bool,
    /// Parameter table.
    pub(crate) params: Params,
    /// Where it armed: home, from which its fence is measured (shared NED, m).
    pub(crate) home_ned_m: [f32; 3],
    /// Its fence was breached in this flight (acted on once).
    pub(crate) fence_breached: bool,
    /// Telemetry stream schedule.
    pub(crate) streams: Streams,
    /// Messages waiting to be sent.
    pub(crate) outbox: Vec<MavMessage>,
    /// Sensor-noise generator (deterministic from the seed).
    pub(crate) noise: ChaCha8Rng,
}

impl Vehicle {
    /// A disarmed vehicle resting at its start position.
    pub fn new(config: VehicleConfig, telemetry_rate_hz: f64) -> Self {
        let speed_factor = config.faults.speed_factor as f32;
        let mode = config.flavour.imitation().boot_mode();
        let body = Body::on_ground(config.initial_position_ned_m);
        Self {
            system_id: config.system_id,
            flavour: config.flavour,
            initial_position_ned_m: config.initial_position_ned_m,
            home: config.home,
            local_origin_ned_m: config.local_origin_ned_m,
            limits: Limits {
                max_speed_mps: config.max_speed_mps * speed_factor,
                max_accel_mps2: config.max_accel_mps2,
            },
            body,
            armed: false,
            mode,
            time_s: 0.0,
            armed_time_s: 0.0,
            first_airborne_s: None,
            resting_since_s: None,
            hold: Setpoint::hold(config.initial_position_ned_m),
            takeoff_height_m: None,
            rtl_descending: false,
            external: None,
            setpoint_times_s: VecDeque::new(),
            offboard_lost_since_s: None,
            velocity_timed_out: false,
            battery_pct: 100.0,
            battery_low: false,
            battery_critical: false,
            params: Params::for_vehicle(&config),
            home_ned_m: config.initial_position_ned_m,
            fence_breached: false,
            streams: Streams::new(config.seed, telemetry_rate_hz),
            outbox: Vec::new(),
            noise: ChaCha8Rng::seed_from_u64(config.seed),
            config,
        }
    }

    /// True position, shared local NED frame, metres.
    pub fn position_ned_m(&self) -> [f32; 3] {
        self.body.position_ned_m
    }

    /// True velocity, NED, m/s.
    pub fn velocity_ned_mps(&self) -> [f32; 3] {
        self.body.velocity_ned_mps
    }

    /// Heading, radians from north.
    pub fn yaw_rad(&self) -> f32 {
        self.body.yaw_rad
    }

    /// Motors armed.
    pub fn armed(&self) -> bool {
        self.armed
    }

    /// Current flight mode.
    pub fn mode(&self) -> FlightMode {
        self.mode
    }

    /// Simulated time since boot, seconds.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    /// Battery charge, percent.
    pub fn battery_pct(&self) -> f32 {
        self.battery_pct
    }

    /// Whether every number of the physical state is finite (position,
    /// velocity, acceleration, yaw, battery, time).
    pub fn state_is_finite(&self) -> bool {
        let b = &self.body;
        b.position_ned_m
            .iter()
            .chain(&b.velocity_ned_mps)
            .chain(&b.accel_ned_mps2)
            .chain([&b.yaw_rad, &b.ground_down_m, &self.battery_pct])
            .all(|v| v.is_finite())
            && self.time_s.is_finite()
    }

    /// Takes the messages the vehicle wants to send (replies and telemetry).
    pub fn take_outbox(&mut self) -> Vec<MavMessage> {
        std::mem::take(&mut self.outbox)
    }

    /// Whether the vehicle is resting on the ground (landed detection).
    pub fn landed(&self) -> bool {
        self.body.is_resting()
    }

    /// Whether the vehicle is clearly off the ground.
    pub fn airborne(&self) -> bool {
        self.body.height_m() > AIRBORNE_HEIGHT_M
    }

    /// Whether an injected crash has happened: motors off, falling or fallen.
    pub fn crashed(&self) -> bool {
        self.fault_started(self.config.faults.crash_after_takeoff)
    }

    /// Whether a fault set to start `after` takeoff has started (never before
    /// the vehicle first left the ground).
    fn fault_started(&self, after: Option<Duration>) -> bool {
        match (after, self.first_airborne_s) {
            (Some(after), Some(airborne_s)) => self.time_s >= airborne_s + seconds_or_never(after),
            _ => false,
        }
    }

    /// Whether an injected rogue ground station is streaming the vehicle away.
    pub fn rogue_active(&self) -> bool {
        self.fault_started(self.config.faults.rogue_after_takeoff)
    }

    /// Whether an injected link drop (or a crash) is cutting the link right now.
    pub fn link_down(&self) -> bool {
        if self.crashed() {
            return true;
        }
        match (self.config.faults.link_drop, self.first_airborne_s) {
            (Some(drop), Some(airborne_s)) => {
                let start_s = airborne_s + seconds_or_never(drop.after_takeoff);
                let end_s = start_s + seconds_or_never(drop.duration);
                (start_s..end_s).contains(&self.time_s)
            }
            _ => false,
        }
    }

    /// HEARTBEAT custom_mode of the current mode.
    pub fn custom_mode(&self) -> u32 {
        self.flavour.imitation().custom_mode(self.mode)
    }

    /// Advances simulation time by one fixed step.
    pub fn step(&mut self, dt_s: f64) {
        self.time_s += dt_s;
        if self.armed {
            self.armed_time_s += dt_s;
            self.battery_pct = (self.battery_pct - BATTERY_DRAIN_PCT_PER_S * dt_s as f32).max(0.0);
        }
        self.check_battery();
        self.update_mode();
        self.check_fence();
        let setpoint = self.current_setpoint();
        let limits = self.mode_limits();
        let thrust = self.armed && !self.crashed();
        self.body.step(dt_s as f32, &setpoint, &limits, thrust);
        if self.first_airborne_s.is_none() && self.airborne() {
            self.first_airborne_s = Some(self.time_s);
        }
        self.check_auto_disarm();
    }

    /// Switches mode, capturing the current position as the hold point.
    pub(crate) fn set_mode(&mut self, mode: FlightMode) {
        if mode != self.mode {
            tracing::debug!(system_id = self.system_id, ?mode, "mode change");
        }
        self.mode = mode;
        self.hold = Setpoint::hold(self.hold_position());
        self.rtl_descending = false;
        self.offboard_lost_since_s = None;
        if !matches!(mode, FlightMode::Takeoff | FlightMode::Guided) {
            self.takeoff_height_m = None;
        }
        if mode == FlightMode::Guided {
            // Entering GUIDED holds position until a new target arrives, as
            // on Copter; an old target must not pull the vehicle back.
            self.external = None;
        }
        if mode == FlightMode::Takeoff && self.takeoff_height_m.is_none() {
            self.takeoff_height_m = Some(self.params.takeoff_alt_m());
        }
    }

    /// Where to hold: here, or on the ground if resting there.
    fn hold_position(&self) -> [f32; 3] {
        let mut p = self.body.position_ned_m;
        if self.body.in_ground_contact() {
            p[2] = self.body.ground_down_m;
        }
        p
    }

    /// Arms or disarms, resetting per-flight state.
    pub(crate) fn set_armed(&mut self, armed: bool) {
        if armed && !self.armed {
            self.home_ned_m = self.hold_position();
            self.fence_breached = false;
        }
        self.armed = armed;
        self.resting_since_s = None;
        self.hold = Setpoint::hold(self.hold_position());
        if !armed {
            self.takeoff_height_m = None;
        }
    }

    /// Records a setpoint from the wire (whether or not the mode uses it).
    pub(crate) fn record_setpoint(&mut self, setpoint: Setpoint) {
        self.setpoint_times_s.push_back(self.time_s);
        while self.setpoint_times_s.len() > 16 {
            self.setpoint_times_s.pop_front();
        }
        self.external = Some(ExternalTarget {
            setpoint,
            received_s: self.time_s,
        });
        self.velocity_timed_out = false;
    }

    /// PX4's condition to enter OFFBOARD: a live stream of more than 2 Hz.
    pub(crate) fn setpoint_stream_ok(&self) -> bool {
        let recent = self
            .setpoint_times_s
            .iter()
            .filter(|t| self.time_s - **t <= OFFBOARD_STREAM_WINDOW_S)
            .count();
        recent >= OFFBOARD_MIN_SETPOINTS
            && self
                .external
                .is_some_and(|e| self.time_s - e.received_s < OFFBOARD_LOSS_TIMEOUT_S / 2.0)
    }

    /// Queues a STATUSTEXT, as autopilots explain refusals and failsafes.
    pub(crate) fn status_text(&mut self, severity: MavSeverity, text: &str) {
        tracing::info!(system_id = self.system_id, "{text}");
        self.outbox.push(MavMessage::STATUSTEXT(STATUSTEXT_DATA {
            severity,
            text: text.into(),
            id: 0,
            chunk_seq: 0,
        }));
    }
}
