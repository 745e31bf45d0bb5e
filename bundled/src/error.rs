//! Why the bundled simulator could not be set up for a mission.

/// Why the bundled SITL could not be set up for a mission.
#[derive(Debug, thiserror::Error)]
pub enum BundledSitlError {
    /// A `--fault` flag targets a drone the plan does not fly.
    #[error("--fault names drone {drone:?}, which is not in the mission (drones: {known})")]
    UnknownDrone {
        /// The drone id the fault names.
        drone: String,
        /// The plan's drone ids, comma-separated, to show what was meant.
        known: String,
    },
    /// A relay was given a drone the mission does not have.
    #[error("no drone {drone:?} in the mission (drones: {known})")]
    NotInMission {
        /// The drone id given.
        drone: String,
        /// The mission's drone ids, comma-separated.
        known: String,
    },
    /// More drones than MAVLink system ids the SITL hands out (1–254); the field
    /// is how many the plan has.
    #[error("the bundled SITL gives system ids 1–254, so at most 254 drones ({0} given)")]
    TooManyDrones(usize),
    /// The vehicles could not be spawned (a socket could not be bound).
    #[error("cannot start the bundled SITL: {0}")]
    Spawn(#[from] swarmctl_sitl::SitlError),
}
