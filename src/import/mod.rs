//! Instance formats the MAPF community already uses, read as missions.
//!
//! 2D instances become worlds one voxel high; every imported drone flies with the
//! default limits in [`default_limits`]. Each format sits in its own file.

mod build;
mod error;
mod libmrp;
mod movingai;
mod movingai3d;
mod one_group;

use crate::mission::{Mission, MissionError, MissionFile};
use std::path::Path;

pub use build::default_limits;
pub use error::ImportError;

pub use libmrp::parse_libmrp;
pub use movingai::{GridMap, ScenarioRow, parse_map, parse_scen};
pub use movingai3d::{parse_3dmap, parse_3dscen};
pub use one_group::{ONE_GROUP_NAME, as_one_group};

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
        named_by: None,
        source,
    })?;
    refuse_map(path)?;
    match detect_format(path, &text) {
        Format::Mission => Ok(crate::mission::from_yaml(&text, path)?),
        format => validated(path, &instance_from_text(path, &text, format, agents)?),
    }
}

/// Loads a community instance (not a mission) with all its agents in one group:
/// the unlabeled problem on the same file ([`as_one_group`]).
pub fn load_as_one_group(path: &Path, agents: Option<usize>) -> Result<Mission, ImportError> {
    let file = as_one_group(instance_file(path, agents)?, path)?;
    validated(path, &file)
}

/// The mission file an instance (not a mission) becomes, before validation: to
/// write out, or to change (e.g. to make its agents one team) before validating.
pub fn instance_file(path: &Path, agents: Option<usize>) -> Result<MissionFile, ImportError> {
    let text = std::fs::read_to_string(path).map_err(|source| ImportError::Read {
        file: path.to_path_buf(),
        named_by: None,
        source,
    })?;
    refuse_map(path)?;
    instance_from_text(path, &text, detect_format(path, &text), agents)
}

/// A MovingAI map given where an instance belongs, refused with a pointer to the
/// scenario format (a map alone has no agents).
fn refuse_map(path: &Path) -> Result<(), ImportError> {
    if let Some(ext @ ("map" | "3dmap")) = path.extension().and_then(|e| e.to_str()) {
        let scenario = if ext == "map" { "scen" } else { "3dscen" };
        return Err(ImportError::format(
            path,
            None,
            format!(
                "this is a MovingAI map, not an instance: pass a .{scenario} scenario instead (each of its rows names this map and gives one agent's start and goal)"
            ),
        ));
    }
    Ok(())
}

/// `text` (read from `path`) in `format` as a mission file.
fn instance_from_text(
    path: &Path,
    text: &str,
    format: Format,
    agents: Option<usize>,
) -> Result<MissionFile, ImportError> {
    match format {
        Format::Mission => Err(ImportError::format(
            path,
            None,
            "this is a mission file already, not a community instance",
        )),
        Format::LibMultiRobotPlanning => parse_libmrp(text, path),
        Format::MovingAiScen => movingai::load_scenario(path, text, agents),
        Format::MovingAi3dScen => movingai3d::load_scenario(path, text, agents),
    }
}

/// `file` (read from `path`) validated, its problems reported against `path`.
fn validated(path: &Path, file: &MissionFile) -> Result<Mission, ImportError> {
    crate::mission::validate(file).map_err(|problems| {
        ImportError::Mission(MissionError::Invalid {
            file: path.to_path_buf(),
            problems,
        })
    })
}
