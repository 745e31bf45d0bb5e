//! The parameter client: writes and reads the autopilot's parameters
//! (PARAM_SET, PARAM_REQUEST_READ, answered by PARAM_VALUE), retried like commands.

use super::Session;
use crate::link::error::LinkError;
use crate::link::messages::AUTOPILOT_COMPONENT_ID;
use mavlink::dialects::common::{
    MavMessage, MavParamType, PARAM_REQUEST_READ_DATA, PARAM_SET_DATA,
};
use std::time::{Duration, Instant};

impl Session {
    /// Sets parameter `name` (REAL32, as both autopilots take these) and waits for
    /// the vehicle's PARAM_VALUE to read back `value`, retrying like a command.
    /// Returns the value read back; a vehicle that keeps another is an error.
    pub async fn set_param(&self, name: &str, value: f32) -> Result<f32, LinkError> {
        let close = |v: f32| (v - value).abs() <= 1e-3 * value.abs().max(1.0);
        let mut attempt: u8 = 0;
        while self.keeps_trying(attempt) {
            attempt = attempt.saturating_add(1);
            self.send(&MavMessage::PARAM_SET(PARAM_SET_DATA {
                param_value: value,
                target_system: self.system_id,
                target_component: AUTOPILOT_COMPONENT_ID,
                param_id: name.into(),
                param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
            }))
            .await?;
            let asked = Instant::now();
            while asked.elapsed() < self.policy.ack_timeout {
                if let Some(v) = self.state().params.get(name).copied()
                    && close(v)
                {
                    return Ok(v);
                }
                tokio::time::sleep(Duration::from_millis(20)).await;
            }
        }
        Err(LinkError::NotConfirmed {
            what: format!(
                "parameter {name} = {value} (reads back {})",
                self.state()
                    .params
                    .get(name)
                    .map_or("nothing".to_string(), |v| v.to_string())
            ),
            waited_s: self.policy.ack_timeout.as_secs_f64() * f64::from(attempt),
        })
    }

    /// Reads parameter `name` (PARAM_REQUEST_READ, answered by PARAM_VALUE), retrying
    /// like a command; a vehicle that never answers (no such parameter) is an error.
    pub async fn read_param(&self, name: &str) -> Result<f32, LinkError> {
        self.state().params.remove(name);
        let mut attempt: u8 = 0;
        while self.keeps_trying(attempt) {
            attempt = attempt.saturating_add(1);
            self.send(&MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
                param_index: -1,
                target_system: self.system_id,
                target_component: AUTOPILOT_COMPONENT_ID,
                param_id: name.into(),
            }))
            .await?;
            let asked = Instant::now();
            while asked.elapsed() < self.policy.ack_timeout {
                if let Some(v) = self.state().params.get(name).copied() {
                    return Ok(v);
                }
                tokio::time::sleep(Duration::from_millis(20)).await;
            }
        }
        Err(LinkError::NotConfirmed {
            what: format!("parameter {name} (no PARAM_VALUE)"),
            waited_s: self.policy.ack_timeout.as_secs_f64() * f64::from(attempt),
        })
    }
}
