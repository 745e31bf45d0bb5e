//! Why a flight did not start or could not continue.

use crate::link::LinkError;
use crate::schedule::ScheduleError;

#[derive(Debug, thiserror::Error)]
pub enum FlyError {
    #[error("cannot schedule the plan: {0}")]
    Schedule(#[from] ScheduleError),
    #[error("the plan has {plan} drones but {vehicles} vehicles were given")]
    VehicleCount { plan: usize, vehicles: usize },
    #[error("drone {drone}: {source}")]
    Link {
        drone: String,
        #[source]
        source: LinkError,
    },
    #[error("pre-flight checks failed, nobody was armed:\n{}", .0.join("\n"))]
    Preflight(Vec<String>),
    #[error("arming failed, every armed drone was disarmed again:\n{}", .0.join("\n"))]
    Arming(Vec<String>),
}
