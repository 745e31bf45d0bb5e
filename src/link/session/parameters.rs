//! The parameter client: writes and reads the autopilot's parameters
//! (PARAM_SET, PARAM_REQUEST_READ, answered by PARAM_VALUE), retried like commands.

use super::Session;
use crate::link::error::LinkError;
use crate::link::messages::AUTOPILOT_COMPONENT_ID;
use mavlink::dialects::common::{
    MavMessage, MavParamType, PARAM_REQUEST_READ_DATA, PARAM_SET_DATA,
};
use std::time::{Duration, Instant};

/// A parameter's value as the autopilot keeps it.
///
/// The parameter protocol carries every value in a `float` field. ArduPilot
/// (C-cast encoding) puts integers there as floats, so its integer parameters
/// are [`ParamValue::Real`] on the wire. PX4 (byte-wise encoding) puts an
/// `INT32`'s bits there unchanged: 5 travels as the float whose bits are 5, and
/// only a bit-for-bit comparison tells 5 from 4 ([`ParamValue::Int32`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParamValue {
    /// A float, or an integer sent as a float (ArduPilot).
    Real(f32),
    /// A PX4 `INT32` parameter, its bits in the float field.
    Int32(i32),
}

impl ParamValue {
    /// The `param_value` field that carries it.
    fn wire(self) -> f32 {
        match self {
            ParamValue::Real(v) => v,
            ParamValue::Int32(v) => f32::from_bits(v as u32),
        }
    }

    /// The `param_type` it is sent with.
    fn param_type(self) -> MavParamType {
        match self {
            ParamValue::Real(_) => MavParamType::MAV_PARAM_TYPE_REAL32,
            ParamValue::Int32(_) => MavParamType::MAV_PARAM_TYPE_INT32,
        }
    }

    /// Whether a `param_value` read back is this value: a float within REAL32
    /// rounding, an integer bit for bit.
    pub fn matches(self, wire: f32) -> bool {
        match self {
            ParamValue::Real(v) => (wire - v).abs() <= 1e-3 * v.abs().max(1.0),
            ParamValue::Int32(v) => wire.to_bits() == v as u32,
        }
    }

    /// A `param_value` read back, decoded like this value.
    pub fn decode_like(self, wire: f32) -> ParamValue {
        match self {
            ParamValue::Real(_) => ParamValue::Real(wire),
            ParamValue::Int32(_) => ParamValue::Int32(wire.to_bits() as i32),
        }
    }
}

impl std::fmt::Display for ParamValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParamValue::Real(v) => write!(f, "{v}"),
            ParamValue::Int32(v) => write!(f, "{v}"),
        }
    }
}

impl Session {
    /// Sets parameter `name` (REAL32, as both autopilots take these) and waits for
    /// the vehicle's PARAM_VALUE to read back `value`, retrying like a command.
    /// Returns the value read back; a vehicle that keeps another is an error.
    pub async fn set_param(&self, name: &str, value: f32) -> Result<f32, LinkError> {
        self.set_param_value(name, ParamValue::Real(value)).await
    }

    /// Sets parameter `name` to `value`, sent with its type, and waits for the
    /// vehicle's PARAM_VALUE to read it back ([`ParamValue::matches`]), retrying like
    /// a command. Returns the `param_value` read back.
    pub async fn set_param_value(&self, name: &str, value: ParamValue) -> Result<f32, LinkError> {
        let mut attempt: u8 = 0;
        while self.keeps_trying(attempt) {
            attempt = attempt.saturating_add(1);
            self.send(&MavMessage::PARAM_SET(PARAM_SET_DATA {
                param_value: value.wire(),
                target_system: self.system_id,
                target_component: AUTOPILOT_COMPONENT_ID,
                param_id: name.into(),
                param_type: value.param_type(),
            }))
            .await?;
            let asked = Instant::now();
            while asked.elapsed() < self.policy.ack_timeout {
                if let Some(v) = self.state().params.get(name).copied()
                    && value.matches(v)
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
                    .map_or("nothing".to_string(), |v| value.decode_like(*v).to_string())
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
