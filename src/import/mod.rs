//! Instance formats the MAPF community already uses, read as missions.
//!
//! 2D instances become worlds one voxel high; every imported drone flies with the
//! default limits in [`default_limits`]. Each format sits in its own file.

mod libmrp;
mod movingai;
mod movingai3d;

use crate::mission::schema::{LimitsSpec, LinkSpec, WorldSpec};
use crate::mission::{Mission, MissionError, MissionFile};
use std::path::{Path, PathBuf};

pub use libmrp::parse_libmrp;
pub use movingai::{parse_map, parse_scen};
pub use movingai3d::{parse_3dmap, parse_3dscen};

/// Why an instance file could not be imported.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// The instance file (or the map it names) could not be read.
    #[error("{}: cannot read: {source}", file.display())]
    Read {
        /// The file as the user (or the scenario) named it.
        file: PathBuf,
        /// Why the operating system refused.
        #[source]
        source: std::io::Error,
    },
    /// The file is not in the format it claims, or asks for something swarmctl
    /// cannot plan.
    #[error("{}{}: {message}", file.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
    Format {
        /// The file as the user (or the scenario) named it.
        file: PathBuf,
        /// 1-based line of the problem, when it is known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The file was read as a mission but the mission is invalid.
    #[error(transparent)]
    Mission(#[from] MissionError),
}

impl ImportError {
    pub(crate) fn format(file: &Path, line: Option<usize>, message: impl Into<String>) -> Self {
        ImportError::Format {
            file: file.to_path_buf(),
            line,
            message: message.into(),
        }
    }
}

/// Which format a file is in, from its name and (for YAML) its top-level keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// A swarmctl mission file (YAML).
    Mission,
    /// A libMultiRobotPlanning, CBS-TA or ITA-CBS instance (YAML with `agents:`).
    LibMultiRobotPlanning,
    /// A MovingAI 2D scenario (`.scen`) with the `.map` it names.
    MovingAiScen,
    /// A MovingAI 3D scenario (`.3dscen`) with the `.3dmap` it names.
    MovingAi3dScen,
}

/// Guesses the format of `path`; YAML files are told apart by their `agents:` key.
pub fn detect_format(path: &Path, text: &str) -> Format {
    match path.extension().and_then(|e| e.to_str()) {
        Some("scen") => Format::MovingAiScen,
        Some("3dscen") => Format::MovingAi3dScen,
        _ if text.lines().any(|l| l.starts_with("agents:")) => Format::LibMultiRobotPlanning,
        _ => Format::Mission,
    }
}

/// Loads a mission or any supported instance file. `agents` picks how many scenario
/// rows to use from MovingAI scenarios (all of them when `None`).
pub fn load_any(path: &Path, agents: Option<usize>) -> Result<Mission, ImportError> {
    let text = std::fs::read_to_string(path).map_err(|source| ImportError::Read {
        file: path.to_path_buf(),
        source,
    })?;
    let file = match detect_format(path, &text) {
        Format::Mission => return Ok(crate::mission::from_yaml(&text, path)?),
        Format::LibMultiRobotPlanning => parse_libmrp(&text, path)?,
        Format::MovingAiScen => movingai::load_scenario(path, &text, agents)?,
        Format::MovingAi3dScen => movingai3d::load_scenario(path, &text, agents)?,
    };
    crate::mission::validate(&file).map_err(|problems| {
        ImportError::Mission(MissionError::Invalid {
            file: path.to_path_buf(),
            problems,
        })
    })
}

/// Limits given to imported instances, which carry none of their own: 1 m voxels,
/// 1 m/s, 2 m/s², 0.3 m safety distance.
pub fn default_limits() -> LimitsSpec {
    LimitsSpec {
        max_speed_mps: 1.0,
        max_accel_mps2: 2.0,
        safety_distance_m: 0.3,
    }
}

/// A mission file around an imported world and groups.
pub(crate) fn mission_file(
    name: String,
    source: &Path,
    world: WorldSpec,
    groups: Vec<crate::mission::schema::GroupSpec>,
) -> MissionFile {
    MissionFile {
        name,
        description: Some(format!("Imported from {}", source.display())),
        world,
        limits: default_limits(),
        link: LinkSpec::default(),
        groups,
    }
}

/// A 1 m voxel world lifted 1 m off the ground.
pub(crate) fn world_spec(
    dimensions: [i64; 3],
    obstacles: Vec<crate::mission::schema::ObstacleSpec>,
) -> WorldSpec {
    WorldSpec {
        dimensions,
        voxel_size_m: 1.0,
        origin_m: [0.0, 0.0, 1.0],
        obstacles,
    }
}
