//! What the vehicle sends us unasked: the telemetry streams' rates, and single
//! messages requested once.

use super::Session;
use crate::link::budget;
use crate::link::error::LinkError;
use mavlink::MessageData;
use mavlink::dialects::common::{
    AUTOPILOT_VERSION_DATA, COMMAND_ACK_DATA, MavCmd, PARAM_VALUE_DATA, STATUSTEXT_DATA,
    TIMESYNC_DATA,
};

/// Messages a vehicle sends in answer to us or as part of a protocol, not as
/// telemetry: never turned off. ArduCopter refuses to stop TIMESYNC (its clock
/// exchange with the ground station, a 28-byte frame now and then).
const NOT_STREAMS: [u32; 5] = [
    COMMAND_ACK_DATA::ID,
    PARAM_VALUE_DATA::ID,
    STATUSTEXT_DATA::ID,
    AUTOPILOT_VERSION_DATA::ID,
    TIMESYNC_DATA::ID,
];

/// What [`Session::quiet_other_streams`] did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Quieted {
    /// Message ids turned off.
    pub off: Vec<u32>,
    /// Message ids the vehicle would not turn off: they still spend the link.
    pub still_on: Vec<u32>,
}

/// A message seen this often is taken for a periodic one.
const PERIODIC_AFTER: u32 = 2;

/// MAV_CMD_SET_MESSAGE_INTERVAL's interval that turns a message off, µs.
const INTERVAL_OFF_US: f32 = -1.0;

impl Session {
    /// Asks for the telemetry of the link budget ([`budget::telemetry_streams`]):
    /// position at `position_hz`, landed state and health.
    pub async fn request_rates(&self, position_hz: f64) -> Result<(), LinkError> {
        for (id, hz) in budget::telemetry_streams(position_hz) {
            let interval_us = (1e6 / hz.max(0.1)) as f32;
            self.set_message_interval(id, interval_us).await?;
        }
        Ok(())
    }

    /// Turns off every periodic message the vehicle has sent that the link
    /// budget does not keep ([`budget::kept_message_ids`]): an autopilot streams
    /// much by default (attitude, global position, battery …) that would spend
    /// a radio's capacity. Says which it turned off and which the vehicle
    /// would not turn off (refused, or never acknowledged).
    pub async fn quiet_other_streams(&self) -> Quieted {
        let kept = budget::kept_message_ids();
        let periodic: Vec<u32> = self
            .state()
            .messages_seen
            .iter()
            .filter(|(id, count)| {
                **count >= PERIODIC_AFTER && !kept.contains(id) && !NOT_STREAMS.contains(id)
            })
            .map(|(id, _)| *id)
            .collect();
        let mut quieted = Quieted::default();
        for id in periodic {
            match self.set_message_interval(id, INTERVAL_OFF_US).await {
                Ok(()) => quieted.off.push(id),
                Err(_) => quieted.still_on.push(id),
            }
        }
        quieted
    }

    async fn set_message_interval(
        &self,
        message_id: u32,
        interval_us: f32,
    ) -> Result<(), LinkError> {
        self.command(
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
            [message_id as f32, interval_us, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await
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
