//! Mission files: the schema users write, its validation and a commented template.

mod autopilot;
mod contest;
mod error;
mod fence;
mod legs;
mod load;
pub mod schema;
mod shape;
mod template;
mod types;
mod validate;
mod write;

pub use contest::{Contest, contested};
pub use error::{MissionError, Problem};
pub use legs::{Leg, LegKind, Targets};
pub use load::{from_yaml, load, parse_yaml};
pub use schema::{
    Autopilot, FenceAction, FenceSpec, Landing, MissionFile, RadioSpec, RelaySpec, SigningSpec,
    ZenohSpec,
};
pub use template::TEMPLATE;
pub use types::{
    DEFAULT_MAX_JERK_MPS3, DEFAULT_TRACKING_ERROR_M, Drone, Geodetic, Group, KeySource, Limits,
    LinkSettings, Mission, PadSource, Stage,
};
pub use validate::{MAX_DIMENSION, MAX_VERTICAL_LAYERS, MAX_VOXELS, SETPOINT_RATES_HZ, validate};
pub use write::to_yaml;
