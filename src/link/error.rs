//! What can go wrong talking to one vehicle, in terms a caller can act on.

use mavlink::dialects::common::{MavCmd, MavResult};

#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    #[error("cannot open MAVLink connection {endpoint}: {source}")]
    Connect {
        endpoint: String,
        source: std::io::Error,
    },
    #[error("no HEARTBEAT from system {system_id} within {waited_s:.1} s")]
    NoHeartbeat { system_id: u8, waited_s: f64 },
    #[error("system {system_id} is not a PX4 or ArduPilot autopilot ({autopilot})")]
    UnknownAutopilot { system_id: u8, autopilot: String },
    #[error("{command:?} was not acknowledged after {attempts} attempts")]
    NoAck { command: MavCmd, attempts: u8 },
    #[error("{command:?} refused ({result:?}){}", reason.as_deref().map(|r| format!(": {r}")).unwrap_or_default())]
    Refused {
        command: MavCmd,
        result: MavResult,
        reason: Option<String>,
    },
    #[error("{what} not confirmed by telemetry within {waited_s:.1} s")]
    NotConfirmed { what: String, waited_s: f64 },
    #[error("sending to the vehicle failed: {0}")]
    Send(String),
}
