//! Why a benchmark or fault-matrix run could not be carried out. A run that flies
//! and goes wrong is no error: its report lists the failures. These are the cases
//! where there is nothing to report, because the run never got going.

use crate::bundled_sitl::BundledSitlError;
use swarmctl::fly::faults::FaultError;
use swarmctl::mission::Problem;
use swarmctl::plan::PlanError;

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
    /// A scenario names a fault `--fault` would refuse.
    #[error(transparent)]
    Fault {
        /// The flag and what is wrong with it.
        #[from]
        source: FaultError,
    },
    /// The bundled SITL refused the configuration or did not start.
    #[error(transparent)]
    SitlStart {
        /// What the bundled SITL said.
        #[from]
        source: BundledSitlError,
    },
}
