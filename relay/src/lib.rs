//! swarmctl past one ground machine: relays that own the vehicles' MAVLink
//! links, bridged to the controller over [Zenoh](https://zenoh.io).
//!
//! ```text
//!                       ┌── Zenoh (TCP; peers, or through zenohd routers) ──┐
//!  swarmctl fly --via zenoh                                  swarmctl relay --name north
//!   plan, schedule, TPG gating, contingencies ◄─────────────► MAVLink network 1 (≤ 254 vehicles)
//!   one Session per drone, over a carried link              swarmctl relay --name south
//!                                            ◄─────────────► MAVLink network 2 (≤ 254 vehicles)
//! ```
//!
//! What is central stays central: one plan, one Temporal Plan Graph, one
//! executor deciding every setpoint and command. What spreads is the link: a
//! relay moves MAVLink frames between Zenoh and its vehicles and decides
//! nothing. The key space is in [`keys`]; the controller's side is
//! [`RelayLinks`], the relay's [`Relay`]; [`truth`] carries the bundled
//! simulator's true states out of relay processes for tests and benchmarks.

#![forbid(missing_docs)]

pub mod endpoints;
pub mod error;
pub mod keys;
pub mod links;
pub mod relay;
pub mod truth;

pub use endpoints::{DEFAULT_CONTROLLER_ENDPOINT, Role, ZenohEndpoints};
pub use error::RelayError;
pub use keys::KeySpace;
pub use links::{RelayLinks, ServedDrone};
pub use relay::{CarriedFrames, Relay, RelaySpec, RelayedDrone};
/// The Zenoh this crate is built on, for callers that hold its sessions.
pub use zenoh;
