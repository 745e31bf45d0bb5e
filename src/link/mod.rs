//! MAVLink sessions with PX4 and ArduPilot vehicles (rust-mavlink, tokio).
//!
//! One [`Session`] per vehicle: a reader task keeps the vehicle's state current,
//! a heartbeat task announces us as a ground station (system 255) once a second,
//! and commands are retried with MAVLink's confirmation counter until
//! acknowledged. [`frames`] is the only place the mission's ENU meets each vehicle's
//! own local NED.

pub mod budget;
mod error;
pub mod frames;
mod messages;
mod mode;
mod receive;
mod session;
mod signing;
mod telemetry;
mod transport;

pub use error::LinkError;
pub use frames::VehicleFrame;
pub use mode::ModeRequest;
pub use session::{CommandPolicy, ParamValue, Quieted, Session};
pub use signing::{SigningKey, SigningKeyError};
pub use telemetry::{PositionSample, VehicleState};
pub use transport::{CarriedLink, Carrier, CarrierInbox, LinkBytes, carried};

/// The link's wire-level pieces, public for the simulator's fuzz tests and the
/// relays, which speak the same frames: the receive fold every message goes
/// through, and the framing of MAVLink carried over another transport.
pub mod wire {
    pub use super::receive::{REBOOT_BACKSTEP_MS, fold};
    pub use super::transport::{CARRIED_QUEUE_FRAMES, decode_frame, encode_frame};
}
