//! An instance's agents as one team: any agent may take any agent's goal.
//!
//! A MovingAI scenario gives each agent its own goal (plain MAPF). The same files
//! are also the standard benchmark of the unlabeled problem, where agents are
//! interchangeable and only the set of goals matters (TSWAP and the max-flow
//! optimum of Yu & LaValle are measured on them so): `swarmctl plan FILE.scen
//! --one-group` plans that problem, one group holding every agent and every goal.

use super::error::ImportError;
use crate::mission::MissionFile;
use crate::mission::schema::GroupSpec;
use std::path::Path;

/// The name of the one group an instance's agents become.
pub const ONE_GROUP_NAME: &str = "team";

/// `file` with every group's drones and goals in one group, in file order, so
/// drone `k` keeps its id and goal `k` its voxel. Refuses a file with no drones,
/// and one with stages (their formations are given per group).
///
/// ```
/// use swarmctl::import::{as_one_group, parse_libmrp};
/// let yaml = "map:\n  dimensions: [3, 1]\n  obstacles: []\nagents:\n  - {name: a, start: [0, 0], goal: [2, 0]}\n  - {name: b, start: [2, 0], goal: [0, 0]}\n";
/// let file = parse_libmrp(yaml, "swap.yaml".as_ref()).unwrap();
/// assert_eq!(file.groups.len(), 2);
/// let team = as_one_group(file, "swap.yaml".as_ref()).unwrap();
/// assert_eq!(team.groups.len(), 1);
/// assert_eq!(team.groups[0].drones.len(), 2);
/// assert_eq!(team.groups[0].goals.len(), 2);
/// ```
pub fn as_one_group(mut file: MissionFile, path: &Path) -> Result<MissionFile, ImportError> {
    if !file.stages.is_empty() {
        return Err(ImportError::format(
            path,
            None,
            "its stages give formations per group, which one group would not match",
        ));
    }
    let groups = std::mem::take(&mut file.groups);
    let team = GroupSpec {
        name: ONE_GROUP_NAME.to_string(),
        drones: groups
            .iter()
            .flat_map(|g| g.drones.iter().cloned())
            .collect(),
        goals: groups
            .iter()
            .flat_map(|g| g.goals.iter().copied())
            .collect(),
    };
    if team.drones.is_empty() {
        return Err(ImportError::format(
            path,
            None,
            "the instance has no agents",
        ));
    }
    file.groups = vec![team];
    Ok(file)
}
