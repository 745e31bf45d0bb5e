//! What can go wrong setting up relays and the links through them.

/// A relay or controller-side failure, naming what to fix.
#[derive(Debug, thiserror::Error)]
pub enum RelayError {
    /// A Zenoh endpoint that does not parse.
    #[error(
        "Zenoh endpoint {endpoint:?} is not valid ({reason}); write it like tcp/127.0.0.1:7447"
    )]
    Endpoint {
        /// The endpoint as given.
        endpoint: String,
        /// What Zenoh said.
        reason: String,
    },
    /// A Zenoh configuration key refused its value.
    #[error("Zenoh configuration {key}: {reason}")]
    Config {
        /// The configuration key.
        key: String,
        /// What Zenoh said.
        reason: String,
    },
    /// The Zenoh session did not open (a port in use, an address not local).
    #[error("cannot open the Zenoh session ({endpoints}): {reason}")]
    Open {
        /// The endpoints asked for.
        endpoints: String,
        /// What Zenoh said.
        reason: String,
    },
    /// Declaring a publisher, subscriber or token failed.
    #[error("Zenoh {what}: {reason}")]
    Declare {
        /// What was declared, with its key.
        what: String,
        /// What Zenoh said.
        reason: String,
    },
    /// A drone's vehicle link could not be opened by the relay.
    #[error("drone {drone}: cannot open MAVLink connection {endpoint}: {reason}")]
    Vehicle {
        /// The mission's drone id.
        drone: String,
        /// The rust-mavlink address.
        endpoint: String,
        /// What the operating system said.
        reason: String,
    },
    /// Some drones had no relay announcing them in time.
    #[error(
        "no relay serves {missing} of the {total} drones after {waited_s:.0} s: {names}{seen}",
        missing = missing.len(),
        names = list(missing),
        seen = if relays.is_empty() { " (no relay seen at all: is one running, and connected to this controller?)".to_string() } else { format!(" (relays seen: {})", relays.join(", ")) }
    )]
    Unserved {
        /// Drones nobody serves.
        missing: Vec<String>,
        /// Drones in the flight.
        total: usize,
        /// Relays that did announce themselves.
        relays: Vec<String>,
        /// How long the controller waited, seconds.
        waited_s: f64,
    },
    /// Two relays claim one drone.
    #[error(
        "drone {drone} is served by two relays, {first} and {second}: give each drone to one relay"
    )]
    ServedTwice {
        /// The mission's drone id.
        drone: String,
        /// One relay.
        first: String,
        /// The other.
        second: String,
    },
}

/// At most eight names, then how many more.
fn list(names: &[String]) -> String {
    let shown: Vec<&str> = names.iter().take(8).map(String::as_str).collect();
    match names.len().saturating_sub(8) {
        0 => shown.join(", "),
        more => format!("{} and {more} more", shown.join(", ")),
    }
}
