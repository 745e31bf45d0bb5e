//! What can go wrong talking to one vehicle, in terms a caller can act on.

use mavlink::dialects::common::{MavCmd, MavResult};

/// A failed exchange with one vehicle.
#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    /// The address is malformed or the socket cannot be opened.
    #[error("cannot open MAVLink connection {endpoint}: {source}")]
    Connect {
        /// The rust-mavlink address.
        endpoint: String,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// Nobody answers as that system id (wrong address, wrong id, vehicle down).
    #[error("no HEARTBEAT from system {system_id} within {waited_s:.1} s")]
    NoHeartbeat {
        /// The system id waited for.
        system_id: u8,
        /// How long we waited, seconds.
        waited_s: f64,
    },
    /// Every try of a command went unanswered (a silent or very lossy link).
    #[error("{command:?} was not acknowledged after {attempts} attempts")]
    NoAck {
        /// The command sent.
        command: MavCmd,
        /// How many times it was sent.
        attempts: u8,
    },
    /// The vehicle answered no.
    #[error("{command:?} refused ({result:?}){}", reason.as_deref().map(|r| format!(": {r}")).unwrap_or_default())]
    Refused {
        /// The command sent.
        command: MavCmd,
        /// The COMMAND_ACK result.
        result: MavResult,
        /// The vehicle's latest STATUSTEXT, which usually says why.
        reason: Option<String>,
    },
    /// The command was accepted but telemetry never showed its effect.
    #[error("{what} not confirmed by telemetry within {waited_s:.1} s")]
    NotConfirmed {
        /// The state waited for, e.g. `armed state` or `mode 0x60000`.
        what: String,
        /// How long we waited, seconds.
        waited_s: f64,
    },
    /// The socket refused the message.
    #[error("sending to the vehicle failed: {0}")]
    Send(String),
}
