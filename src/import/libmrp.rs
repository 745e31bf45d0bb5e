//! The YAML instances of libMultiRobotPlanning, CBS-TA and ITA-CBS.
//!
//! `map: {dimensions: [W, H], obstacles: [[x, y], …]}` and `agents: [{name, start,
//! goal}]`, or `potentialGoals: [[x, y], …]` instead of `goal`: agents that share the
//! same set of potential goals form one group.

use super::build::{mission_file, world_spec};
use super::error::ImportError;
use crate::mission::MissionFile;
use crate::mission::schema::{DroneSpec, GroupSpec, ObstacleSpec};
use serde::Deserialize;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Instance {
    map: Map,
    agents: Vec<Agent>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Map {
    dimensions: [i64; 2],
    #[serde(default)]
    obstacles: Vec<[i64; 2]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "camelCase")]
struct Agent {
    name: String,
    start: [i64; 2],
    goal: Option<[i64; 2]>,
    potential_goals: Option<Vec<[i64; 2]>>,
}

/// Converts a libMultiRobotPlanning instance into a mission file (not yet validated).
///
/// ```
/// let yaml = "
/// map: { dimensions: [3, 1], obstacles: [] }
/// agents:
///   - { name: a, start: [0, 0], potentialGoals: [[2, 0], [1, 0]] }
///   - { name: b, start: [1, 0], potentialGoals: [[2, 0], [1, 0]] }
/// ";
/// let file = swarmctl::import::parse_libmrp(yaml, "x.yaml".as_ref()).unwrap();
/// assert_eq!(file.groups.len(), 1); // a and b share their goals: one group
/// ```
pub fn parse_libmrp(text: &str, file: &Path) -> Result<MissionFile, ImportError> {
    let instance: Instance = yaml_serde::from_str(text)
        .map_err(|e| ImportError::format(file, e.location().map(|l| l.line()), e.to_string()))?;
    let obstacles = instance
        .map
        .obstacles
        .iter()
        .map(|&[x, y]| ObstacleSpec::Cell([x, y, 0]))
        .collect();
    let mut groups: Vec<GroupSpec> = Vec::new();
    // The goal set each group was formed from, to find the group of the next agent.
    let mut group_goals: Vec<Vec<[i64; 2]>> = Vec::new();
    for agent in instance.agents {
        let drone = DroneSpec {
            id: agent.name.clone(),
            start: Some([agent.start[0], agent.start[1], 0]),
            pad: None,
            endpoint: None,
            system_id: None,
        };
        let goals = match (agent.goal, agent.potential_goals) {
            (Some(goal), None) => vec![goal],
            (None, Some(goals)) if !goals.is_empty() => {
                let mut goals = goals;
                goals.sort_unstable();
                goals
            }
            (None, Some(_)) => {
                return Err(ImportError::format(
                    file,
                    None,
                    format!(
                        "agent {:?} has no potential goals; swarmctl plans every drone to a goal",
                        agent.name
                    ),
                ));
            }
            _ => {
                return Err(ImportError::format(
                    file,
                    None,
                    format!(
                        "agent {:?} needs exactly one of `goal` and `potentialGoals`",
                        agent.name
                    ),
                ));
            }
        };
        match group_goals.iter().position(|g| *g == goals) {
            Some(i) => groups[i].drones.push(drone),
            None => {
                group_goals.push(goals.clone());
                groups.push(GroupSpec {
                    name: if goals.len() == 1 {
                        agent.name.clone()
                    } else {
                        format!("group{}", groups.len() + 1)
                    },
                    drones: vec![drone],
                    goals: goals.iter().map(|&[x, y]| [x, y, 0]).collect(),
                });
            }
        }
    }
    let [w, h] = instance.map.dimensions;
    let name = file.file_stem().map_or_else(
        || "imported".to_string(),
        |s| s.to_string_lossy().into_owned(),
    );
    Ok(mission_file(
        name,
        file,
        world_spec([w, h, 1], obstacles),
        groups,
    ))
}
