//! A takeoff as the drone's phase machine runs it: one [`Takeoff`] per armed
//! vehicle, stepped once per tick with what the drone knows ([`TakeoffTick`]),
//! answering with what it needs ([`TakeoffStep`]). The takeoff owns its own
//! state (which command is in flight, where a climb started); the drone owns
//! telemetry, the setpoint it streams and the commands it sends.

use crate::fly::command::{Command, CommandError, Request};
use crate::fly::follower::Setpoint;
use crate::fly::settings::LoopSettings;
use mavlink::dialects::common::MavLandedState;
use std::time::Instant;

/// One autopilot's way from armed on the pad to hovering at the start voxel.
pub trait Takeoff: std::fmt::Debug + Send {
    /// One tick of the takeoff.
    fn step(&mut self, tick: &mut TakeoffTick<'_>) -> TakeoffStep;

    /// The command result this takeoff waits for, if `command` is one it sent.
    fn waiting_for(&mut self, command: Command) -> Option<&mut Request>;

    /// Whether our setpoint stream goes out now (`has_setpoint`: the drone has a
    /// setpoint to stream).
    fn streams(&self, has_setpoint: bool) -> bool;

    /// The phase's name in the status view.
    fn name(&self) -> &'static str;
}

/// What a takeoff sees and may change in one tick.
pub struct TakeoffTick<'a> {
    /// Now, for the takeoff's own timing.
    pub now: Instant,
    /// The flight's settings (kinematic limits, settle tolerance).
    pub settings: &'a LoopSettings,
    /// Where the route begins: the start voxel above the pad, ENU metres.
    pub start_m: [f64; 3],
    /// Latest telemetry position, ENU metres.
    pub position_m: Option<[f64; 3]>,
    /// The landed state the vehicle reports (EXTENDED_SYS_STATE), if it does.
    pub landed_state: Option<MavLandedState>,
    /// The setpoint streamed to the vehicle (held between ticks).
    pub setpoint: &'a mut Option<Setpoint>,
    /// Whether telemetry shows the drone settled at a point: within a tolerance,
    /// at rest, for a moment (see the drone's `settle`).
    pub settled_at: &'a mut dyn FnMut([f64; 3], f64) -> bool,
}

/// What the takeoff needs after a tick.
#[derive(Debug)]
pub enum TakeoffStep {
    /// Still on its way; nothing to send.
    Continue,
    /// Send this command; its result comes back through [`Takeoff::waiting_for`].
    Send(Command),
    /// Hovering at the start voxel.
    AtStart,
    /// The autopilot refused a step of the takeoff: give up on the drone.
    Refused {
        /// The step, as the autopilot's ground station names it.
        step: &'static str,
        /// What the vehicle answered.
        error: CommandError,
    },
}

impl TakeoffStep {
    /// The autopilot refused `step` (named in the log, as its ground station
    /// names it) with `error`.
    pub fn refused(step: &'static str, error: CommandError) -> Self {
        TakeoffStep::Refused { step, error }
    }
}
