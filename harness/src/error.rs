//! Why a benchmark or fault-matrix run could not be carried out. A run that flies
//! and goes wrong is no error: its report lists the failures. These are the cases
//! where there is nothing to report, because the run never got going.

use swarmctl::mission::Problem;
use swarmctl::plan::PlanError;
use swarmctl_bundled::BundledSitlError;
use swarmctl_sitl::faults::FaultError;

/// What stopped a harness run before it produced a report.
#[derive(Debug, thiserror::Error)]
pub enum HarnessError {
    /// The load benchmark was asked for a swarm the bundled SITL cannot fly (it
    /// gives each vehicle one of the system ids 1–254).
    #[error("the load mission has 1–5000 drones ({vehicles} asked)")]
    LoadVehicles {
        /// Vehicles asked for.
        vehicles: usize,
    },
    /// A mission the harness generated itself failed validation: a harness bug,
    /// not a user's mistake.
    #[error("the generated load mission is invalid: {problems:?}")]
    MissionInvalid {
        /// Name of the generated mission.
        mission: String,
        /// What validation found.
        problems: Vec<Problem>,
    },
    /// The planner returned no plan.
    #[error("planning {mission}")]
    Planning {
        /// Name of the mission being planned.
        mission: String,
        /// Why the planner gave up.
        #[source]
        source: PlanError,
    },
    /// A tokio runtime could not be built (threads or the I/O driver).
    #[error("starting the {runtime} runtime")]
    RuntimeStart {
        /// Which runtime: "SITL" or "controller".
        runtime: &'static str,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },
    /// The thread sampling true positions and resources could not be spawned.
    #[error("starting the watcher")]
    WatcherStart {
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },
    /// The thread sampling true positions and resources panicked, so the run has
    /// no separation or resource figures.
    #[error("the watcher panicked")]
    WatcherPanicked,
    /// Something still holds the simulated swarm after the flight, so it cannot
    /// be shut down (and its sockets would outlive the run).
    #[error("the swarm is still shared after the flight")]
    SwarmStillShared,
    /// A timing flight did not finish within its limit: there is no execution to time.
    #[error("{mission}: the flight did not finish within {limit_s:.0} s")]
    FlightUnfinished {
        /// The mission flown.
        mission: String,
        /// The limit it was given, seconds.
        limit_s: f64,
    },
    /// A scenario names a fault `--fault` would refuse.
    #[error(transparent)]
    Fault {
        /// The flag and what is wrong with it.
        #[from]
        source: FaultError,
    },
    /// The relay load benchmark was asked to put more vehicles in one relay than
    /// one MAVLink network holds (or to use no relay).
    #[error(
        "{vehicles} drones in {relays} relays is more than 254 per relay (one MAVLink network each): give --relays {needed} or more"
    )]
    RelayShares {
        /// Vehicles asked for.
        vehicles: usize,
        /// Relays asked for.
        relays: usize,
        /// The fewest relays that hold them.
        needed: usize,
    },
    /// A file, socket or process the relay load benchmark needs could not be
    /// made or reached.
    #[error("{what}")]
    Io {
        /// What was being done, with the path.
        what: String,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },
    /// A relay process did not stop after SIGTERM (it was killed).
    #[error("a relay did not stop within {timeout:?} of SIGTERM")]
    RelayDidNotStop {
        /// How long it was given.
        timeout: std::time::Duration,
    },
    /// A relay's `--report` file is not the report a relay writes.
    #[error("the relay's report {} is not valid", path.display())]
    RelayReport {
        /// The report file.
        path: std::path::PathBuf,
        /// What the JSON parser said.
        #[source]
        source: serde_json::Error,
    },
    /// The controller's Zenoh side (links to the relays, the truth watch) failed.
    #[error(transparent)]
    Relay {
        /// What the relay crate said.
        #[from]
        source: swarmctl_relay::RelayError,
    },
    /// A flight (through relays, or timed) failed before takeoff.
    #[error(transparent)]
    Flight {
        /// Why the flight was refused.
        #[from]
        source: swarmctl::fly::FlyError,
    },
    /// A map given to the peers benchmark could not be read as a MovingAI map.
    #[error(transparent)]
    PeerMap {
        /// What the importer said, naming the file and line.
        #[from]
        source: swarmctl::import::ImportError,
    },
    /// A map cannot hold the instance asked of it, or cannot be given to a peer.
    #[error("{}: {problem}", map.display())]
    PeerInstance {
        /// The map file.
        map: std::path::PathBuf,
        /// What is wrong.
        problem: String,
    },
    /// The bundled SITL refused the configuration or did not start.
    #[error(transparent)]
    SitlStart {
        /// What the bundled SITL said.
        #[from]
        source: BundledSitlError,
    },
}
