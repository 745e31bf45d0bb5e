//! A mission's world, groups and drones as a `viz::Scene` (no plan yet).

use swarmctl::mission::Mission;
use swarmctl::world::Voxel;
use swarmctl_viz::{Bounds, Drone, Group, ObstacleBox, Scene};

/// The static part of a recording: world box, obstacles (down to the ground where
/// they stand on it), groups, the
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
        obstacles: obstacle_boxes(mission),
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

/// Every obstacle as drawn: a voxel box, reaching down to the ground for layer 0's
/// obstacles that stand on it (the pad-layer cell below them is blocked), and a box
/// from the ground up to layer 0 for obstacles in the pad layer alone.
fn obstacle_boxes(mission: &Mission) -> Vec<ObstacleBox> {
    let world = &mission.world;
    let airspace = &mission.airspace;
    let s = world.voxel_size_m();
    let layer0_bottom_m = world.origin_m()[2] - 0.5 * s;
    let grounded = |x: i32, y: i32| airspace.is_blocked(Voxel::new(x, y, -1));
    let column = |v: Voxel, bottom_m: f64, top_m: f64| {
        let c = airspace.center_m(v);
        ObstacleBox {
            center_m: [c.x, c.y, 0.5 * (bottom_m + top_m)],
            size_m: [s, s, top_m - bottom_m],
        }
    };
    let voxels = world.obstacles().map(|v| {
        let c = world.center_m(v);
        let top_m = c.z + 0.5 * s;
        let bottom_m = if v.z == 0 && grounded(v.x, v.y) {
            0.0
        } else {
            c.z - 0.5 * s
        };
        column(v, bottom_m, top_m)
    });
    let pad_layer = airspace
        .obstacles()
        .filter(|v| v.z == -1 && !world.is_blocked(Voxel::new(v.x, v.y, 0)))
        .map(|v| column(v, 0.0, layer0_bottom_m));
    voxels.chain(pad_layer).collect()
}
