//! What the vehicle sends us unasked: the telemetry streams' rates, and single
//! messages requested once.

use super::Session;
use crate::link::error::LinkError;
use mavlink::dialects::common::MavCmd;

/// MAVLink message ids we ask the vehicle to stream.
const LOCAL_POSITION_NED_ID: f32 = 32.0;
const EXTENDED_SYS_STATE_ID: f32 = 245.0;
const SYS_STATUS_ID: f32 = 1.0;

impl Session {
    /// Asks for position at `position_hz`, landed state at 5 Hz and health at 1 Hz.
    pub async fn request_rates(&self, position_hz: f64) -> Result<(), LinkError> {
        for (id, hz) in [
            (LOCAL_POSITION_NED_ID, position_hz),
            (EXTENDED_SYS_STATE_ID, 5.0),
            (SYS_STATUS_ID, 1.0),
        ] {
            let interval_us = (1e6 / hz.max(0.1)) as f32;
            self.command(
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                [id, interval_us, 0.0, 0.0, 0.0, 0.0, 0.0],
            )
            .await?;
        }
        Ok(())
    }

    /// Asks the vehicle to send message `message_id` once (MAV_CMD_REQUEST_MESSAGE).
    pub async fn request_message(&self, message_id: u32) -> Result<(), LinkError> {
        self.command(
            MavCmd::MAV_CMD_REQUEST_MESSAGE,
            [message_id as f32, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await
    }
}
