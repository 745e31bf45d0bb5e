//! Why a flight did not start or could not continue.

use crate::compiled::CompileError;
use crate::link::LinkError;

/// A failure before takeoff: nothing flew (anyone armed has been disarmed again).
#[derive(Debug, thiserror::Error)]
pub enum FlyError {
    /// The plan cannot be scheduled, or its trajectories fail the independent
    /// checker: refused before any vehicle was contacted.
    #[error("refused before arming: {0}")]
    Refused(#[from] CompileError),
    /// The checked plan was compiled (and checked) for another mission.
    #[error("the plan was compiled and checked for mission {plan:?}, not {mission:?}")]
    OtherMission {
        /// The mission the plan was compiled for.
        plan: String,
        /// The mission being flown.
        mission: String,
    },
    /// One vehicle is needed per planned drone.
    #[error("the plan has {plan} drones but {vehicles} vehicles were given")]
    VehicleCount {
        /// Drones in the plan.
        plan: usize,
        /// Vehicles in the fly options.
        vehicles: usize,
    },
    /// A vehicle's MAVLink connection could not be opened.
    #[error("drone {drone}: {source}")]
    Link {
        /// The drone's mission id.
        drone: String,
        /// What the link reported.
        #[source]
        source: LinkError,
    },
    /// A radio of `link.radios` cannot carry its drones' traffic (see
    /// `link::budget`); one line per radio with the numbers and the fixes.
    #[error("refused before connecting: the link budget does not fit:\n{}", .0.join("\n"))]
    LinkBudget(Vec<String>),
    /// Some vehicles failed pre-flight; one line per problem, naming the drone.
    #[error("pre-flight checks failed, nobody was armed:\n{}", .0.join("\n"))]
    Preflight(Vec<String>),
    /// `fly --start-at`: the start instant leaves less than the takeoff lead (from
    /// the start, or once pre-flight had passed): nobody was armed.
    #[error(
        "refused before takeoff: the start instant is {} and takeoff needs {takeoff_lead_s:.0} s before it{}; nobody was armed",
        if *start_in_s >= 0.0 { format!("{start_in_s:.1} s away") } else { format!("{:.1} s past", -start_in_s) },
        if *after_preflight { " (pre-flight took until then)" } else { "" }
    )]
    StartTooSoon {
        /// Seconds from the refusal to the start instant (negative: passed).
        start_in_s: f64,
        /// Seconds the swarm needs from arming to above its pads.
        takeoff_lead_s: f64,
        /// Pre-flight had passed: it was pre-flight that took too long.
        after_preflight: bool,
    },
    /// Aborted while waiting on the ground for the start instant: nobody was armed.
    #[error("aborted before takeoff while waiting for the start instant; nobody was armed")]
    AbortedBeforeTakeoff,
    /// Some vehicles would not arm; one line per drone, refusals and disarms.
    #[error("arming failed, every armed drone was disarmed again:\n{}", .0.join("\n"))]
    Arming(Vec<String>),
}
