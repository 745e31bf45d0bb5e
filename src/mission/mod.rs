//! Mission files: the schema users write, its validation and a commented template.

mod error;
mod load;
pub mod schema;
mod template;
mod types;
mod validate;
mod write;

pub use error::{MissionError, Problem};
pub use load::{from_yaml, load, parse_yaml};
pub use schema::{Autopilot, MissionFile, SigningSpec};
pub use template::TEMPLATE;
pub use types::{Drone, Group, KeySource, Limits, LinkSettings, Mission};
pub use validate::{MAX_DIMENSION, MAX_VOXELS, validate};
pub use write::to_yaml;
