//! The world model in plans: obstacles stand on the ground (no path passes under
//! one unless the file declares it overhead), and an imported instance is planned
//! as exactly that instance (its formation leg on the map's own cells, never
//! below the map's optimum).
//!
//! "Under an obstacle" is read here from the mission *file* (each obstacle's
//! voxels and whether it is written `overhead`), not from the validated world, so
//! the check shares nothing with how validation blocks columns.

use std::collections::HashSet;
use std::path::Path;
use swarmctl::generate::{self, GenerateOptions};
use swarmctl::mission::schema::{MissionFile, ObstacleSpec};
use swarmctl::mission::{self, LegKind, Mission};
use swarmctl::plan::{self, DiscretePlan, PlanOptions, TapfGroup};
use swarmctl::world::Voxel;

/// Every `[x, y, z]` an obstacle of `file` that stands on the ground occupies as
/// written (its own voxels; what lies below them is what the check asks about).
fn standing_voxels(file: &MissionFile) -> Vec<[i64; 3]> {
    let mut out = Vec::new();
    for obstacle in &file.world.obstacles {
        match obstacle {
            ObstacleSpec::Cell(v) => out.push(*v),
            ObstacleSpec::Box(b) if !b.overhead => {
                for z in b.min[2]..=b.max[2] {
                    for y in b.min[1]..=b.max[1] {
                        for x in b.min[0]..=b.max[0] {
                            out.push([x, y, z]);
                        }
                    }
                }
            }
            ObstacleSpec::Box(_) => {}
        }
    }
    out
}

/// The first path cell (drone, step, voxel) at or below an obstacle standing on
/// the ground, in that obstacle's column.
fn first_cell_under_an_obstacle(
    file: &MissionFile,
    plan: &DiscretePlan,
) -> Option<(String, usize, Voxel)> {
    let mut top_of_column: std::collections::HashMap<[i64; 2], i64> = Default::default();
    for [x, y, z] in standing_voxels(file) {
        let top = top_of_column.entry([x, y]).or_insert(z);
        *top = (*top).max(z);
    }
    plan.drones.iter().find_map(|d| {
        d.path.iter().enumerate().find_map(|(step, v)| {
            let top = top_of_column.get(&[i64::from(v.x), i64::from(v.y)])?;
            (i64::from(v.z) <= *top).then(|| (d.id.clone(), step, *v))
        })
    })
}

fn plan_of(m: &Mission) -> DiscretePlan {
    let solution =
        plan::solve(m, &PlanOptions::default()).unwrap_or_else(|e| panic!("{}: {e}", m.name));
    if let Err(v) = plan::validate_plan(m, &solution.plan) {
        panic!("{}: {v:#?}", m.name);
    }
    solution.plan
}

fn parse(yaml: &str, name: &str) -> (MissionFile, Mission) {
    let file = mission::parse_yaml(yaml).unwrap_or_else(|e| panic!("{name}: {e:?}"));
    let m = mission::from_yaml(yaml, Path::new(name)).unwrap_or_else(|e| panic!("{e}"));
    (file, m)
}

#[test]
fn no_example_mission_flies_under_an_obstacle() {
    let mut names: Vec<String> = std::fs::read_dir(crate::support::repo_path("missions"))
        .expect("missions/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "yaml"))
        .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    names.sort();
    // The large load mission is covered by its own benchmark, and has no obstacles.
    names.retain(|n| n != "load-200.yaml");
    assert!(names.len() >= 8, "{names:?}");
    let mut cases: Vec<(String, String)> = names
        .iter()
        .map(|n| {
            let path = crate::support::repo_path(&format!("missions/{n}"));
            (n.clone(), std::fs::read_to_string(path).expect("readable"))
        })
        .collect();
    cases.push(("template".into(), mission::TEMPLATE.to_string()));
    for (name, yaml) in cases {
        let (file, m) = parse(&yaml, &name);
        let plan = plan_of(&m);
        assert_eq!(
            first_cell_under_an_obstacle(&file, &plan),
            None,
            "{name}: a drone passes under an obstacle standing on the ground"
        );
    }
}

#[test]
fn random_missions_never_fly_under_their_ground_obstacles() {
    for seed in 1..=6 {
        let file = generate::generate(&GenerateOptions {
            dimensions: [8, 8, 3],
            obstacles: 40,
            drones: 12,
            groups: 3,
            seed,
            ..GenerateOptions::default()
        })
        .expect("generated");
        let yaml = mission::to_yaml(&file);
        let (file, m) = parse(&yaml, "gen.yaml");
        let plan = plan_of(&m);
        assert_eq!(
            first_cell_under_an_obstacle(&file, &plan),
            None,
            "seed {seed}: a drone passes under an obstacle standing on the ground"
        );
    }
}

#[test]
fn the_swap_corridor_never_passes_below_its_floor() {
    let (file, m) = parse(
        &std::fs::read_to_string(crate::support::repo_path("missions/swap-corridor.yaml"))
            .expect("readable"),
        "swap-corridor.yaml",
    );
    let plan = plan_of(&m);
    for d in &plan.drones {
        for v in &d.path {
            // The floor is [1..=5, 1, 0]; below it is rock down to the ground.
            assert!(
                !(v.y == 1 && (1..=5).contains(&v.x) && v.z < 1),
                "{} passes below the corridor floor at {v}",
                d.id
            );
        }
    }
    assert_eq!(first_cell_under_an_obstacle(&file, &plan), None);
}

/// Twelve drones cross a wall that stands on the ground, with a 2×2 window in it.
const WALL_WITH_WINDOW: &str = r"
name: wall-with-window
world:
  dimensions: [9, 6, 4]
  voxel_size_m: 1.0
  obstacles:
    # A wall at x = 4 standing on the ground, with a window at y 2..3, z 1..2:
    # solid beside the window, solid below it, and a lintel above it.
    - { min: [4, 0, 0], max: [4, 1, 3] }
    - { min: [4, 4, 0], max: [4, 5, 3] }
    - { min: [4, 2, 0], max: [4, 3, 0] }
    - { min: [4, 2, 3], max: [4, 3, 3], overhead: true }
limits: { max_speed_mps: 1.0, max_accel_mps2: 2.0, safety_distance_m: 0.4 }
groups:
  - name: west
    drones:
      - { id: w1, start: [1, 0, 0] }
      - { id: w2, start: [1, 1, 0] }
      - { id: w3, start: [1, 2, 0] }
      - { id: w4, start: [1, 3, 0] }
      - { id: w5, start: [1, 4, 0] }
      - { id: w6, start: [1, 5, 0] }
    goals: [[7, 0, 1], [7, 1, 1], [7, 2, 1], [7, 3, 1], [7, 4, 1], [7, 5, 1]]
  - name: east
    drones:
      - { id: e1, start: [7, 0, 3] }
      - { id: e2, start: [7, 1, 3] }
      - { id: e3, start: [7, 2, 3] }
      - { id: e4, start: [7, 3, 3] }
      - { id: e5, start: [7, 4, 3] }
      - { id: e6, start: [7, 5, 3] }
    goals: [[1, 0, 2], [1, 1, 2], [1, 2, 2], [1, 3, 2], [1, 4, 2], [1, 5, 2]]
";

#[test]
fn twelve_drones_cross_a_wall_through_its_window_not_under_it() {
    let (file, m) = parse(WALL_WITH_WINDOW, "wall.yaml");
    let plan = plan_of(&m);
    assert_eq!(first_cell_under_an_obstacle(&file, &plan), None);
    let window: HashSet<Voxel> = [(2, 1), (3, 1), (2, 2), (3, 2)]
        .into_iter()
        .map(|(y, z)| Voxel::new(4, y, z))
        .collect();
    for d in &plan.drones {
        let crossed: Vec<&Voxel> = d.path.iter().filter(|v| v.x == 4).collect();
        assert!(!crossed.is_empty(), "{} never crosses x = 4", d.id);
        for v in crossed {
            assert!(
                window.contains(v),
                "{} crosses the wall at {v}, not the window",
                d.id
            );
        }
    }
}

/// The formation leg's paths and makespan of a planned flight.
fn formation_leg(plan: &DiscretePlan) -> (std::ops::RangeInclusive<usize>, u32) {
    let k = plan
        .legs
        .iter()
        .position(|l| l.kind == LegKind::Formation)
        .expect("a formation leg");
    let start = if k == 0 {
        0
    } else {
        plan.legs[k - 1].end_step as usize
    };
    (
        start..=plan.legs[k].end_step as usize,
        plan.legs[k].makespan_steps,
    )
}

/// The instance's own formation (starts to goals) on its own map, no pad layer.
fn instance_groups(m: &Mission) -> Vec<TapfGroup> {
    m.groups
        .iter()
        .map(|g| TapfGroup {
            starts: g.drones.iter().filter_map(|d| d.start).collect(),
            goals: g.goals.clone(),
        })
        .collect()
}

fn movingai(agents: usize) -> MissionFile {
    let scen = crate::support::repo_path("tests/data/movingai/random-32-32-10-random-1.scen");
    swarmctl::import::instance_file(&scen, Some(agents)).expect("imported")
}

/// Checks a planned imported flight: the formation leg on the map's layer, its
/// makespan the instance's own optimum and never below the map's lower bound.
fn assert_planned_as_the_instance(file: &MissionFile, what: &str) {
    let yaml = mission::to_yaml(file);
    let (_, m) = parse(&yaml, "imported.yaml");
    assert!(
        !m.formations_use_pad_layer,
        "{what}: imports keep formations on the map"
    );
    let plan = plan_of(&m);
    let (steps, makespan) = formation_leg(&plan);
    for d in &plan.drones {
        for step in steps.clone() {
            assert_eq!(
                d.path[step].z, 0,
                "{what}: {} leaves the map at step {step}",
                d.id
            );
        }
    }
    // The instance alone, on the map's own grid (one layer, no pads).
    let groups = instance_groups(&m);
    let alone = plan::solve_tapf(&m.world, &groups, &PlanOptions::default()).expect("solved");
    assert_eq!(
        makespan, alone.makespan_steps,
        "{what}: the instance's own optimum"
    );
    let bound = groups
        .iter()
        .filter_map(|g| plan::group_lower_bound(&m.world, &g.starts, &g.goals))
        .max()
        .expect("a bound");
    assert!(
        makespan >= bound,
        "{what}: {makespan} below the map's lower bound {bound}"
    );
}

#[test]
fn an_imported_map_is_planned_as_the_instance() {
    // Plain MAPF: one agent per group, as the scenario is.
    assert_planned_as_the_instance(&movingai(40), "40 agents, one per group");
    // One team: every agent may take any goal (anonymous MAPF), the case where
    // the pad layer once gave a makespan below the map's optimum.
    let mut one_team = movingai(120);
    let goals: Vec<[i64; 3]> = one_team
        .groups
        .iter()
        .flat_map(|g| g.goals.clone())
        .collect();
    let drones = one_team
        .groups
        .iter()
        .flat_map(|g| g.drones.clone())
        .collect();
    one_team.groups.truncate(1);
    one_team.groups[0].drones = drones;
    one_team.groups[0].goals = goals;
    assert_planned_as_the_instance(&one_team, "120 agents in one team");
}
