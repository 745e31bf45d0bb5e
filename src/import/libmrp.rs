//! The YAML instances of libMultiRobotPlanning, CBS-TA and ITA-CBS.
//!
//! `map: {dimensions: [W, H], obstacles: [[x, y], …]}` and `agents: [{name, start,
//! goal}]`, or `potentialGoals: [[x, y], …]` instead of `goal`: agents that share the
//! same set of potential goals form one group (a team may list more goals than it
//! has agents: spare goals). Every agent with its own `goal` is its own group, and
//! no two agents may share one. Sets that overlap without being equal are outside
//! target assignment (TAPF: teams of interchangeable agents with disjoint goal
//! sets): refused, naming the agents.

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
    // Whether each group is a team (`potentialGoals`) or one agent with its `goal`.
    let mut group_is_team: Vec<bool> = Vec::new();
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
        let team = agent.goal.is_none();
        let same = group_goals
            .iter()
            .zip(&group_is_team)
            .position(|(g, &is_team)| team && is_team && *g == goals);
        if let Some(i) = same {
            groups[i].drones.push(drone);
            continue;
        }
        if let Some((i, shared)) = group_goals
            .iter()
            .enumerate()
            .find_map(|(i, g)| g.iter().find(|c| goals.contains(c)).map(|&c| (i, c)))
        {
            let other = &groups[i].drones[0].id;
            let message = if !team && !group_is_team[i] {
                format!(
                    "agents {other:?} and {:?} share goal {shared:?}: in plain MAPF every agent has a goal of its own (give them a team's `potentialGoals` to let them share)",
                    agent.name
                )
            } else {
                format!(
                    "agents {other:?} and {:?} have different goal sets that overlap at {shared:?}: swarmctl plans teams of interchangeable agents (TAPF), so agents with `potentialGoals` must list exactly the same set as their teammates and none of another team's or agent's goals",
                    agent.name
                )
            };
            return Err(ImportError::format(file, None, message));
        }
        {
            group_is_team.push(team);
            group_goals.push(goals.clone());
            groups.push(GroupSpec {
                name: if team {
                    format!("team{}", groups.len() + 1)
                } else {
                    agent.name.clone()
                },
                drones: vec![drone],
                goals: goals.iter().map(|&[x, y]| [x, y, 0]).collect(),
            });
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
