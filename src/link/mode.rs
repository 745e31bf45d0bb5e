//! A flight mode as MAV_CMD_DO_SET_MODE asks for it and HEARTBEAT confirms it.
//! Which numbers mean which mode is the autopilot's business: each flavour in
//! `fly::autopilot` builds its own.

/// A mode request as MAV_CMD_DO_SET_MODE parameters 2 and 3.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeRequest {
    /// DO_SET_MODE param2: PX4's main mode, or ArduPilot's mode number.
    pub param2: f32,
    /// DO_SET_MODE param3: PX4's sub mode (0 for ArduPilot).
    pub param3: f32,
    /// The HEARTBEAT custom_mode that confirms the vehicle is in this mode.
    pub custom_mode: u32,
}
