//! Flight actions, each a command whose effect telemetry must then confirm:
//! arming, disarming, switching modes, taking off, running pre-arm checks.

use super::Session;
use crate::link::error::LinkError;
use crate::link::mode::ModeRequest;
use mavlink::dialects::common::{MavCmd, MavModeFlag};
use std::time::Duration;

/// How long telemetry gets to confirm a command's effect. Heartbeats come at
/// 1 Hz; at 30 % loss three in a row go missing with p ≈ 3 %, six with p ≈ 0.07 %.
const CONFIRM_WITHIN: Duration = Duration::from_secs(6);

impl Session {
    /// Arms and waits until the heartbeat shows SAFETY_ARMED.
    pub async fn arm(&self) -> Result<(), LinkError> {
        self.command(
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await?;
        self.confirm("armed state", CONFIRM_WITHIN, |s| s.armed)
            .await
    }

    /// Disarms; `force` (param2 = 21196) also in the air — only for emergencies.
    pub async fn disarm(&self, force: bool) -> Result<(), LinkError> {
        let magic = if force { 21196.0 } else { 0.0 };
        self.command(
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            [0.0, magic, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await?;
        self.confirm("disarmed state", CONFIRM_WITHIN, |s| !s.armed)
            .await
    }

    /// Switches mode and waits for the heartbeat to show it.
    pub async fn set_mode(&self, mode: ModeRequest) -> Result<(), LinkError> {
        let base = f32::from(MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED.bits());
        self.command(
            MavCmd::MAV_CMD_DO_SET_MODE,
            [base, mode.param2, mode.param3, 0.0, 0.0, 0.0, 0.0],
        )
        .await?;
        self.confirm(
            &format!("mode {:#x}", mode.custom_mode),
            CONFIRM_WITHIN,
            |s| s.custom_mode == mode.custom_mode,
        )
        .await
    }

    /// ArduPilot-style takeoff: param7 is the height above home in metres.
    pub async fn takeoff(&self, height_m: f32) -> Result<(), LinkError> {
        self.command(
            MavCmd::MAV_CMD_NAV_TAKEOFF,
            [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, height_m],
        )
        .await
    }

    /// Asks the autopilot to run its pre-arm checks now, which makes it repeat why
    /// they fail in STATUSTEXT (ArduPilot; PX4 answers unsupported, and says why on
    /// its own).
    pub async fn run_prearm_checks(&self) -> Result<(), LinkError> {
        self.command(MavCmd::MAV_CMD_RUN_PREARM_CHECKS, [0.0; 7])
            .await
    }
}
