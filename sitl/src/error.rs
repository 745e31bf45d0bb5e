//! Errors the SITL reports to its callers.

use std::net::SocketAddr;

/// Everything that can stop a swarm from starting.
///
/// Runtime trouble (garbage packets, unreachable peers) is never an error:
/// a mock autopilot must keep flying whatever arrives on the wire, exactly
/// like a real one, so such events are only counted in [`crate::LinkStats`].
#[derive(Debug, thiserror::Error)]
pub enum SitlError {
    /// A vehicle's UDP port could not be bound (in use, no permission...).
    #[error("cannot bind vehicle {system_id} to {address}: {source}")]
    Bind {
        /// System id of the vehicle that failed.
        system_id: u8,
        /// Address we tried to bind.
        address: SocketAddr,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// Two vehicles were given the same MAVLink system id.
    #[error("system id {0} is used by more than one vehicle")]
    DuplicateSystemId(u8),
    /// System id 0 is the broadcast address and cannot name a vehicle.
    #[error("system id 0 is reserved for broadcast")]
    ZeroSystemId,
    /// A rate or limit was zero, negative or not a number.
    #[error("invalid {what}: {value} (must be finite and > 0)")]
    InvalidRate {
        /// Which setting was wrong.
        what: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// A fault knob was out of range.
    #[error("invalid fault for vehicle {system_id}: {reason}")]
    InvalidFault {
        /// System id of the vehicle with the bad fault.
        system_id: u8,
        /// What was wrong.
        reason: String,
    },
}
