//! A mission's world, groups and drones as a `viz::Scene` (no plan yet).

use swarmctl::mission::Mission;
use swarmctl_viz::{Bounds, Drone, Group, ObstacleBox, Scene};

/// The static part of a recording: world box, obstacle voxels, groups, the
/// separation (sphere or ellipsoid) drawn around every drone, and each drone's
/// pad on the ground (its start marker: every flight begins there). Goals
/// are those of the mission's groups in file order until a plan assigns them.
pub fn mission_scene(mission: &Mission) -> Scene {
    let world = &mission.world;
    let s = world.voxel_size_m();
    let origin = world.origin_m();
    let dims = world.dimensions();
    let bounds = Bounds {
        min_m: [0, 1, 2].map(|i| origin[i] - 0.5 * s),
        max_m: [0, 1, 2].map(|i| origin[i] + s * (f64::from(dims[i]) - 0.5)),
    };
    let center = |v| {
        let p = world.center_m(v);
        [p.x, p.y, p.z]
    };
    let drones = mission
        .groups
        .iter()
        .enumerate()
        .flat_map(|(g, group)| {
            group
                .drones
                .iter()
                .enumerate()
                .map(move |(i, d)| (g, group, i, d))
        })
        .map(|(g, group, i, d)| Drone {
            id: d.id.clone(),
            group: g,
            start_m: mission.pad_ground_m(d),
            goal_m: group
                .goals
                .get(i)
                .map_or(mission.pad_ground_m(d), |v| center(*v)),
            ..Drone::default()
        })
        .collect();
    Scene {
        name: mission.name.clone(),
        bounds,
        voxel_size_m: s,
        obstacles: world
            .obstacles()
            .map(|v| ObstacleBox {
                center_m: center(v),
                size_m: [s; 3],
            })
            .collect(),
        groups: mission
            .groups
            .iter()
            .enumerate()
            .map(|(i, g)| Group {
                name: g.name.clone(),
                color_rgb: Group::palette(i),
            })
            .collect(),
        drones,
        safety_distance_m: mission.limits.safety_distance_m,
        vertical_separation_m: mission.limits.vertical_separation_m,
        events: Vec::new(),
    }
}
