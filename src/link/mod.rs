//! MAVLink sessions with PX4 and ArduPilot vehicles (rust-mavlink, tokio).
//!
//! One [`Session`] per vehicle: a reader task keeps the vehicle's state current,
//! a heartbeat task announces us as a ground station (system 255) once a second,
//! and commands are retried with MAVLink's confirmation counter until
//! acknowledged. [`frames`] is the only place the mission's ENU meets each vehicle's
//! own local NED.

pub mod error;
pub mod flavour;
pub mod frames;
pub mod messages;
pub mod receive;
pub mod session;
pub mod signing;
pub mod telemetry;
pub mod transport;

pub use error::LinkError;
pub use flavour::{Flavour, ModeRequest};
pub use frames::VehicleFrame;
pub use session::{CommandPolicy, Session};
pub use signing::{SigningKey, SigningKeyError};
pub use telemetry::{PositionSample, VehicleState};
pub use transport::{CarriedLink, Carrier, CarrierInbox, carried};
