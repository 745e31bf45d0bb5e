//! Every bad input a user can write is reported with its field path and reason.

use proptest::prelude::*;
use swarmctl::mission;

const BASE: &str = r#"
name: base
world:
  dimensions: [6, 4, 2]
  voxel_size_m: 1.0
  origin_m: [0.0, 0.0, 1.5]
  obstacles:
    - [3, 0, 0]
    - { min: [3, 2, 0], max: [3, 3, 1] }
limits: { max_speed_mps: 1.0, max_accel_mps2: 2.0, safety_distance_m: 0.3 }
link: { autopilot: px4, setpoint_rate_hz: 20 }
groups:
  - name: blue
    drones:
      - { id: b1, start: [0, 0, 0], system_id: 1 }
      - { id: b2, start: [0, 1, 0], system_id: 2 }
    goals: [[5, 0, 0], [5, 1, 0]]
  - name: red
    drones:
      - { id: r1, start: [5, 3, 0] }
    goals: [[0, 3, 0]]
"#;

/// (field path, message, line and column) of each problem found.
type Found = Vec<(String, String, Option<(usize, usize)>)>;

fn problems_of(yaml: &str) -> Found {
    match mission::from_yaml(yaml, "case.yaml".as_ref()) {
        Ok(_) => Vec::new(),
        Err(e) => {
            let rendered = e.to_string();
            assert!(
                rendered.starts_with("case.yaml"),
                "file not named: {rendered}"
            );
            e.problems()
                .iter()
                .map(|p| (p.path.clone(), p.message.clone(), p.line_column))
                .collect()
        }
    }
}

#[test]
fn base_mission_is_valid() {
    assert_eq!(problems_of(BASE), vec![]);
}

#[test]
fn signing_key_file_is_relative_to_the_mission() {
    let yaml = BASE.replace(
        "setpoint_rate_hz: 20 }",
        "setpoint_rate_hz: 20, signing: { key_file: keys/swarm.key } }",
    );
    let m = mission::from_yaml(&yaml, "missions/x/case.yaml".as_ref()).expect("valid");
    assert_eq!(
        m.link.signing,
        Some(mission::KeySource::File("missions/x/keys/swarm.key".into()))
    );
}

/// (what, replace this, with this, expected path, expected words in the reason, has line)
const CASES: &[(&str, &str, &str, &str, &str, bool)] = &[
    (
        "signing with no key source",
        "setpoint_rate_hz: 20 }",
        "setpoint_rate_hz: 20, signing: {} }",
        "link.signing",
        "needs key_file",
        false,
    ),
    (
        "signing with two key sources",
        "setpoint_rate_hz: 20 }",
        "setpoint_rate_hz: 20, signing: { key_file: k.key, key_env: K } }",
        "link.signing",
        "not both",
        false,
    ),
    (
        "signing key given inline",
        "setpoint_rate_hz: 20 }",
        "setpoint_rate_hz: 20, signing: { key: abcd } }",
        "link.signing",
        "unknown field",
        true,
    ),
    (
        "yaml syntax",
        "groups:\n",
        "groups: [\n",
        "",
        "did not find expected",
        true,
    ),
    (
        "type error",
        "max_speed_mps: 1.0",
        "max_speed_mps: fast",
        "limits.max_speed_mps",
        "invalid type",
        true,
    ),
    (
        "unknown field (typo)",
        "{ id: b1, start:",
        "{ id: b1, strat:",
        "groups[0].drones[0]",
        "unknown field `strat`",
        true,
    ),
    (
        "unknown top-level field",
        "name: base",
        "name: base\nspeed: 3",
        "",
        "unknown field `speed`",
        true,
    ),
    (
        "missing field",
        "voxel_size_m: 1.0\n",
        "\n",
        "world",
        "missing field `voxel_size_m`",
        true,
    ),
    (
        "zero dimension",
        "[6, 4, 2]",
        "[6, 0, 2]",
        "world.dimensions",
        "y extent 0",
        false,
    ),
    (
        "huge dimensions",
        "[6, 4, 2]",
        "[4096, 4096, 4096]",
        "world.dimensions",
        "at most",
        false,
    ),
    (
        "negative voxel size",
        "voxel_size_m: 1.0",
        "voxel_size_m: -0.5",
        "world.voxel_size_m",
        "positive",
        false,
    ),
    (
        "zero speed",
        "max_speed_mps: 1.0",
        "max_speed_mps: 0",
        "limits.max_speed_mps",
        "positive",
        false,
    ),
    (
        "zero acceleration",
        "max_accel_mps2: 2.0",
        "max_accel_mps2: 0.0",
        "limits.max_accel_mps2",
        "positive",
        false,
    ),
    (
        "negative jerk",
        "max_accel_mps2: 2.0",
        "max_accel_mps2: 2.0, max_jerk_mps3: -2.5",
        "limits.max_jerk_mps3",
        "positive",
        false,
    ),
    (
        "negative safety distance",
        "safety_distance_m: 0.3",
        "safety_distance_m: -1",
        "limits.safety_distance_m",
        "positive",
        false,
    ),
    (
        "setpoint rate too low",
        "setpoint_rate_hz: 20",
        "setpoint_rate_hz: 1",
        "link.setpoint_rate_hz",
        "outside",
        false,
    ),
    (
        "setpoint rate below PX4's measured floor",
        "setpoint_rate_hz: 20",
        "setpoint_rate_hz: 4",
        "link.setpoint_rate_hz",
        "below 5 Hz, the lowest rate px4 kept every guarantee at",
        false,
    ),
    (
        "setpoint rate below ArduPilot's measured floor",
        "autopilot: px4, setpoint_rate_hz: 20",
        "autopilot: ardupilot, setpoint_rate_hz: 5",
        "link.setpoint_rate_hz",
        "below 10 Hz, the lowest rate ardupilot kept every guarantee at",
        false,
    ),
    (
        "speed headroom above one",
        "setpoint_rate_hz: 20",
        "setpoint_rate_hz: 20, speed_headroom: 1.5",
        "link.speed_headroom",
        "fraction from 0 to 1",
        false,
    ),
    (
        "unknown autopilot",
        "autopilot: px4",
        "autopilot: betaflight",
        "link.autopilot",
        "unknown variant `betaflight`",
        true,
    ),
    (
        "obstacle out of bounds",
        "- [3, 0, 0]",
        "- [6, 0, 0]",
        "world.obstacles[0]",
        "outside the world",
        false,
    ),
    (
        "obstacle box out of bounds",
        "max: [3, 3, 1]",
        "max: [3, 4, 1]",
        "world.obstacles[1].max",
        "outside the world",
        false,
    ),
    (
        "obstacle box inverted",
        "min: [3, 2, 0], max: [3, 3, 1]",
        "min: [3, 3, 1], max: [3, 2, 0]",
        "world.obstacles[1]",
        "exceeds max",
        false,
    ),
    (
        "obstacle malformed",
        "- [3, 0, 0]",
        "- [3, 0]",
        "world.obstacles[0]",
        "expected an array of length 3",
        true,
    ),
    (
        "start out of bounds",
        "start: [0, 0, 0]",
        "start: [0, -1, 0]",
        "groups[0].drones[0].start",
        "outside the world",
        false,
    ),
    (
        "goal out of bounds",
        "[[5, 0, 0], [5, 1, 0]]",
        "[[5, 0, 9], [5, 1, 0]]",
        "groups[0].goals[0]",
        "outside the world",
        false,
    ),
    (
        "start in obstacle",
        "start: [0, 0, 0]",
        "start: [3, 0, 0]",
        "groups[0].drones[0].start",
        "inside an obstacle",
        false,
    ),
    (
        "goal in obstacle",
        "goals: [[0, 3, 0]]",
        "goals: [[3, 3, 1]]",
        "groups[1].goals[0]",
        "inside an obstacle",
        false,
    ),
    (
        "two drones on one start",
        "start: [0, 1, 0]",
        "start: [0, 0, 0]",
        "groups[0].drones[1].start",
        "already the start of groups[0].drones[0]",
        false,
    ),
    (
        "goal twice in a group",
        "[[5, 0, 0], [5, 1, 0]]",
        "[[5, 0, 0], [5, 0, 0]]",
        "groups[0].goals[1]",
        "already used by groups[0].goals[0]",
        false,
    ),
    (
        "goal twice across groups",
        "goals: [[0, 3, 0]]",
        "goals: [[5, 1, 0]]",
        "groups[1].goals[0]",
        "already used by groups[0].goals[1]",
        false,
    ),
    (
        "no goals",
        "[[5, 0, 0], [5, 1, 0]]",
        "[]",
        "groups[0].goals",
        "has no goals",
        false,
    ),
    (
        "a spare holding at one of its group's goals",
        "[[5, 0, 0], [5, 1, 0]]",
        "[[0, 1, 0]]",
        "groups[0].drones[1].start",
        "its last 1 are spares and hold at their starts, but [0, 1, 0] is one of its goals",
        false,
    ),
    (
        "duplicate drone id",
        "{ id: r1,",
        "{ id: b1,",
        "groups[1].drones[0].id",
        "already used by groups[0].drones[0]",
        false,
    ),
    (
        "bad drone id",
        "{ id: r1,",
        "{ id: \"r 1\",",
        "groups[1].drones[0].id",
        "contains ' '",
        false,
    ),
    (
        "duplicate system id",
        "system_id: 2",
        "system_id: 1",
        "groups[0].drones[1].system_id",
        "already used",
        false,
    ),
    (
        "system id out of range",
        "system_id: 2",
        "system_id: 255",
        "groups[0].drones[1].system_id",
        "not a vehicle system id",
        false,
    ),
    (
        "bad endpoint",
        "{ id: r1, start: [5, 3, 0] }",
        "{ id: r1, start: [5, 3, 0], endpoint: \"udp:1.2.3.4\" }",
        "groups[1].drones[0].endpoint",
        "unknown scheme",
        false,
    ),
    (
        "endpoint without port",
        "{ id: r1, start: [5, 3, 0] }",
        "{ id: r1, start: [5, 3, 0], endpoint: \"udpout:127.0.0.1\" }",
        "groups[1].drones[0].endpoint",
        "HOST:PORT",
        false,
    ),
    (
        "empty group",
        "drones:\n      - { id: r1, start: [5, 3, 0] }\n    goals: [[0, 3, 0]]",
        "drones: []\n    goals: []",
        "groups[1].drones",
        "has no drones",
        false,
    ),
    (
        "no groups",
        "groups:\n",
        "groups: []\nx_groups:\n",
        "",
        "unknown field `x_groups`",
        true,
    ),
    (
        "duplicate group name",
        "name: red",
        "name: blue",
        "groups[1].name",
        "already used by groups[0]",
        false,
    ),
    (
        "pads duplicated",
        "system_id: 1 }\n      - { id: b2, start: [0, 1, 0], system_id: 2 }",
        "system_id: 1, pad: [4, 4] }\n      - { id: b2, start: [0, 1, 0], system_id: 2, pad: [4, 4] }",
        "groups[0].drones[1].pad",
        "already the pad of groups[0].drones[0]",
        false,
    ),
    (
        "no room for the pad layer",
        "voxel_size_m: 1.0\n",
        "voxel_size_m: 1.0\n  pad_height_m: 1.3\n",
        "world.pad_height_m",
        "no room for the pad layer",
        false,
    ),
    (
        "pad under an obstacle standing on the ground",
        "{ id: r1, start: [5, 3, 0] }",
        "{ id: r1, start: [5, 3, 0], pad: [3, 0] }",
        "groups[1].drones[0].pad",
        "pad [3, 0] is under an obstacle that stands on the ground",
        false,
    ),
    (
        "overhead obstacle reaching into the pad layer",
        "{ min: [3, 2, 0], max: [3, 3, 1] }",
        "{ min: [3, 2, -1], max: [3, 3, 1], overhead: true }",
        "world.obstacles[1].overhead",
        "reaches down into the pad layer",
        false,
    ),
    (
        "pad-layer obstacle beyond the launch area",
        "- [3, 0, 0]",
        "- [3, 100, -1]",
        "world.obstacles[0]",
        "beyond the launch area",
        false,
    ),
    (
        "obstacle box beside the world above the pad layer",
        "{ min: [3, 2, 0], max: [3, 3, 1] }",
        "{ min: [-2, 2, -1], max: [3, 3, 1] }",
        "world.obstacles[1].min",
        "a box beside the world must lie in the pad layer",
        false,
    ),
    (
        "obstacle below the pad layer",
        "- [3, 0, 0]",
        "- [3, 0, -2]",
        "world.obstacles[0]",
        "or z = -1 for an obstacle in the pad layer",
        false,
    ),
    (
        "pad too far",
        "{ id: r1, start: [5, 3, 0] }",
        "{ id: r1, start: [5, 3, 0], pad: [500, 0] }",
        "groups[1].drones[0].pad",
        "too far from the world",
        false,
    ),
    (
        "neither start nor pad",
        "{ id: r1, start: [5, 3, 0] }",
        "{ id: r1 }",
        "groups[1].drones[0]",
        "neither a start nor a pad",
        false,
    ),
    (
        "starts for some drones of a group only",
        "{ id: b2, start: [0, 1, 0], system_id: 2 }",
        "{ id: b2, pad: [0, 1], system_id: 2 }",
        "groups[0].drones",
        "1 of its 2 drones have a start",
        false,
    ),
    (
        "unknown group in a stage",
        "    goals: [[0, 3, 0]]\n",
        "    goals: [[0, 3, 0]]\nstages:\n  - { name: s1, goals: { green: [[1, 1, 1]] } }\n",
        "stages[0].goals.green",
        "no group is named \"green\"",
        false,
    ),
    (
        "no goals in a stage",
        "    goals: [[0, 3, 0]]\n",
        "    goals: [[0, 3, 0]]\nstages:\n  - { name: s1, goals: { blue: [] } }\n",
        "stages[0].goals.blue",
        "has no goals in stage \"s1\"",
        false,
    ),
    (
        "a spare holding at a stage's goal",
        "    goals: [[0, 3, 0]]\n",
        "    goals: [[0, 3, 0]]\nstages:\n  - { name: s1, goals: { blue: [[0, 1, 0]] } }\n",
        "stages[0].goals.blue",
        "[0, 1, 0] is one of the stage's goals",
        false,
    ),
    (
        "a goal used twice in a stage",
        "    goals: [[0, 3, 0]]\n",
        "    goals: [[0, 3, 0]]\nstages:\n  - { name: s1, goals: { blue: [[1, 1, 1], [1, 2, 1]], red: [[1, 1, 1]] } }\n",
        "stages[0].goals.red[0]",
        "already used in this stage",
        false,
    ),
    (
        "below_goal with shared columns",
        "    goals: [[0, 3, 0]]\n",
        "    goals: [[0, 3, 0]]\nlanding: below_goal\nstages:\n  - { name: s1, goals: { blue: [[1, 1, 0], [1, 1, 1]] } }\n",
        "landing",
        "share column [1, 1]",
        false,
    ),
    (
        "below_goal over an obstacle",
        "    goals: [[0, 3, 0]]\n",
        "    goals: [[0, 3, 0]]\nlanding: below_goal\nstages:\n  - { name: s1, goals: { red: [[3, 0, 1]] } }\n",
        "landing",
        "obstacle [3, 0, 0] is below goal [3, 0, 1]",
        false,
    ),
];

#[test]
fn every_bad_input_is_reported_with_path_and_reason() {
    for &(what, from, to, path, reason, has_line) in CASES {
        assert!(BASE.contains(from), "{what}: base lacks {from:?}");
        let yaml = BASE.replacen(from, to, 1);
        let problems = problems_of(&yaml);
        let hit = problems
            .iter()
            .find(|(p, m, _)| p == path && m.contains(reason));
        let Some((_, _, line_column)) = hit else {
            panic!("{what}: expected `{path}: …{reason}…`, got {problems:#?}");
        };
        assert_eq!(
            line_column.is_some(),
            has_line,
            "{what}: line/column {line_column:?}"
        );
    }
}

/// The pad layer's cell `[x, y]` is free in the mission's airspace.
fn pad_cell_free(m: &swarmctl::mission::Mission, x: i32, y: i32) -> bool {
    m.airspace.is_free(swarmctl::world::Voxel::new(x, y, -1))
}

#[test]
fn obstacles_stand_on_the_ground_unless_overhead() {
    // [3, 0, 0] stands on the ground; the box [3, 2..3, 0..1] too; an overhead
    // lintel at [1, 1, 1] leaves [1, 1, 0] and the pad layer below free; a pillar
    // written at [2, 1, 1] reaches down to the ground.
    let yaml = BASE.replacen(
        "    - [3, 0, 0]\n",
        "    - [3, 0, 0]\n    - { min: [1, 1, 1], max: [1, 1, 1], overhead: true }\n    - [2, 1, 1]\n",
        1,
    );
    let m = mission::from_yaml(&yaml, "case.yaml".as_ref()).expect("valid");
    let v = swarmctl::world::Voxel::new;
    assert!(
        !pad_cell_free(&m, 3, 0),
        "under a wall standing on the ground"
    );
    assert!(!pad_cell_free(&m, 3, 2) && !pad_cell_free(&m, 3, 3));
    assert!(pad_cell_free(&m, 1, 1), "under an overhead obstacle");
    assert!(m.airspace.is_free(v(1, 1, 0)) && !m.airspace.is_free(v(1, 1, 1)));
    assert!(
        !m.airspace.is_free(v(2, 1, 0)),
        "a pillar stands on the ground"
    );
    assert!(!pad_cell_free(&m, 2, 1));
    assert!(pad_cell_free(&m, 2, 0), "free ground elsewhere");
}

#[test]
fn obstacles_may_stand_in_the_pad_layer_and_the_launch_area() {
    // A box in the pad layer under the world and a tent in the launch area beside
    // it: both accepted (once refused as "outside the world"), both blocked, and
    // no pad is assigned there.
    let yaml = BASE
        .replacen(
            "    - [3, 0, 0]\n",
            "    - [3, 0, 0]\n    - { min: [1, 0, -1], max: [1, 1, -1] }\n    - [-1, 0, -1]\n",
            1,
        )
        .replacen(
            "start: [0, 1, 0], system_id: 2",
            "start: [0, 0, 1], system_id: 2",
            1,
        );
    let m = mission::from_yaml(&yaml, "case.yaml".as_ref()).expect("valid");
    assert!(!pad_cell_free(&m, 1, 0) && !pad_cell_free(&m, 1, 1));
    assert!(m.airspace.is_free(swarmctl::world::Voxel::new(1, 0, 0)));
    let pads: Vec<[i32; 2]> = m.drones().map(|(_, d)| d.pad).collect();
    assert!(
        !pads.contains(&[-1, 0]) && !pads.contains(&[1, 0]),
        "{pads:?}"
    );
    for pad in pads {
        assert!(pad_cell_free(&m, pad[0], pad[1]), "pad {pad:?} is blocked");
    }
}

#[test]
fn a_mission_without_origin_gets_room_for_the_pad_layer() {
    let yaml = BASE.replacen("  origin_m: [0.0, 0.0, 1.5]\n", "", 1);
    let m = mission::from_yaml(&yaml, "case.yaml".as_ref()).expect("the default origin is valid");
    assert_eq!(m.world.origin_m(), [0.0, 0.0, 1.5]);
    assert!((m.pad_height_m() - 0.5).abs() < 1e-12);
    // Larger voxels: layer 0 still a voxel above a pad layer half a metre up.
    let yaml = yaml.replacen("voxel_size_m: 1.0", "voxel_size_m: 2.0", 1);
    let m = mission::from_yaml(&yaml, "case.yaml".as_ref()).expect("valid with 2 m voxels");
    assert_eq!(m.world.origin_m(), [0.0, 0.0, 2.5]);
    assert!((m.pad_height_m() - 0.5).abs() < 1e-12);
}

#[test]
fn an_oversized_safety_distance_is_named_first() {
    // 1.2 m in 1 m voxels: the separation is the cause; the pad layer is not blamed.
    for yaml in [
        BASE.replacen("safety_distance_m: 0.3", "safety_distance_m: 1.2", 1),
        BASE.replacen("safety_distance_m: 0.3", "safety_distance_m: 1.2", 1)
            .replacen("  origin_m: [0.0, 0.0, 1.5]\n", "", 1),
    ] {
        let problems = problems_of(&yaml);
        assert_eq!(problems.len(), 1, "{problems:#?}");
        let (path, message, _) = &problems[0];
        assert_eq!(path, "limits.safety_distance_m");
        assert!(message.contains("at most 0.980 m fits"), "{message}");
    }
}

#[test]
fn no_room_for_the_pad_layer_says_what_fits() {
    let yaml = BASE.replacen("origin_m: [0.0, 0.0, 1.5]", "origin_m: [0.0, 0.0, 0.0]", 1);
    let problems = problems_of(&yaml);
    let (path, message, _) = &problems[0];
    assert_eq!(path, "world.origin_m", "{problems:#?}");
    assert!(
        message.contains("raise world.origin_m z to at least 1.50 m"),
        "{message}"
    );
}

#[test]
fn walled_off_goals_are_named() {
    // Red's goal [0, 3, 1] in the top north-west corner, boxed in on its three open
    // sides: no pad reaches it, not even through the pad layer below the world.
    let yaml = BASE
        .replacen(
            "    - [3, 0, 0]\n",
            "    - [3, 0, 0]\n    - [1, 3, 1]\n    - [0, 2, 1]\n    - [0, 3, 0]\n",
            1,
        )
        .replacen("goals: [[0, 3, 0]]", "goals: [[0, 3, 1]]", 1);
    let problems = problems_of(&yaml);
    assert!(
        problems.iter().any(|(p, m, _)| p == "groups[1].goals"
            && m.contains("\"red\"")
            && m.contains("only 0 of these voxels can be reached from the pads")
            && m.contains("[0, 3, 1]")),
        "{problems:#?}"
    );
}

#[test]
fn spare_goals_are_allowed() {
    let yaml = BASE.replacen("goals: [[0, 3, 0]]", "goals: [[0, 3, 0], [0, 2, 0]]", 1);
    let m = mission::from_yaml(&yaml, "case.yaml".as_ref()).expect("valid");
    assert_eq!(m.groups[1].goals.len(), 2);
}

#[test]
fn stacked_starts_get_distinct_pads_nearby() {
    // b2 starts right above b1: b1 keeps the cell below, b2 gets the nearest free one.
    let yaml = BASE.replacen(
        "{ id: b2, start: [0, 1, 0], system_id: 2 }",
        "{ id: b2, start: [0, 0, 1], system_id: 2 }",
        1,
    );
    let m = mission::from_yaml(&yaml, "case.yaml".as_ref()).expect("valid");
    let pads: Vec<([i32; 2], mission::PadSource)> =
        m.drones().map(|(_, d)| (d.pad, d.pad_source)).collect();
    assert_eq!(pads[0], ([0, 0], mission::PadSource::BelowStart));
    assert_eq!(pads[1].1, mission::PadSource::Assigned);
    assert_ne!(pads[1].0, [0, 0]);
    let [x, y] = pads[1].0;
    assert!(x.abs() <= 1 && y.abs() <= 1, "{:?}", pads[1]);
    assert!((m.pad_height_m() - 0.5).abs() < 1e-12);
}

#[test]
fn missing_file_names_the_file() {
    let err = mission::load("no/such/mission.yaml".as_ref()).unwrap_err();
    assert!(
        err.to_string()
            .contains("no/such/mission.yaml: cannot read"),
        "{err}"
    );
}

/// Arbitrary YAML built from the schema's own vocabulary, so the fuzzer reaches deep fields.
fn yaml_value() -> impl Strategy<Value = yaml_serde::Value> {
    let key = prop::sample::select(vec![
        "name",
        "world",
        "dimensions",
        "voxel_size_m",
        "origin_m",
        "obstacles",
        "min",
        "max",
        "limits",
        "max_speed_mps",
        "max_accel_mps2",
        "safety_distance_m",
        "link",
        "autopilot",
        "setpoint_rate_hz",
        "groups",
        "drones",
        "goals",
        "id",
        "start",
        "endpoint",
        "system_id",
        "pad",
        "pad_height_m",
        "overhead",
        "formations_use_pad_layer",
        "stages",
        "hold_s",
        "landing",
        "blue",
    ]);
    let leaf = prop_oneof![
        any::<i64>().prop_map(|i| yaml_serde::Value::from(i % 20)),
        any::<i64>().prop_map(yaml_serde::Value::from),
        any::<f64>().prop_map(yaml_serde::Value::from),
        "[a-z0-9:. ]{0,12}".prop_map(yaml_serde::Value::from),
        prop::sample::select(vec!["group_pads", "own_pad", "below_goal"])
            .prop_map(yaml_serde::Value::from),
        Just(yaml_serde::Value::Null),
        any::<bool>().prop_map(yaml_serde::Value::from),
    ];
    leaf.prop_recursive(5, 64, 6, move |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..5).prop_map(yaml_serde::Value::Sequence),
            prop::collection::vec((key.clone(), inner), 0..6).prop_map(|pairs| {
                yaml_serde::Value::Mapping(
                    pairs
                        .into_iter()
                        .map(|(k, v)| (yaml_serde::Value::from(k), v))
                        .collect(),
                )
            }),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = mission::from_yaml(&text, "fuzz.yaml".as_ref());
    }

    #[test]
    fn arbitrary_yaml_never_panics(value in yaml_value()) {
        let text = yaml_serde::to_string(&value).unwrap_or_default();
        let _ = mission::from_yaml(&text, "fuzz.yaml".as_ref());
    }

    #[test]
    fn mutated_valid_missions_never_panic(edits in prop::collection::vec((0usize..BASE.len(), "[-0-9a-z\\[\\]{}:, ]{0,4}"), 1..4)) {
        let mut text = BASE.to_string();
        for (at, insert) in edits {
            let at = at.min(text.len());
            if text.is_char_boundary(at) {
                text.insert_str(at, &insert);
            }
        }
        let _ = mission::from_yaml(&text, "fuzz.yaml".as_ref());
    }
}

/// The tracking error defaults to the room the geometry leaves (here the pad
/// layer's 1.0 m gap and the 1.0 m voxels, minus the 0.3 m safety distance, halved,
/// less 1 cm), at most 0.30 m; a written one that does not fit is refused with the
/// numbers, and one that does is kept.
#[test]
fn tracking_error_defaults_to_the_room_and_is_refused_when_it_does_not_fit() {
    let m = mission::from_yaml(BASE, "case.yaml".as_ref()).expect("valid");
    assert!((m.limits.tracking_error_m - 0.34_f64.min(0.30)).abs() < 1e-9);
    assert!((m.limits.setpoint_separation_m() - 0.9).abs() < 1e-9);

    let big = BASE.replace(
        "safety_distance_m: 0.3 }",
        "safety_distance_m: 0.3, tracking_error_m: 0.4 }",
    );
    let found = problems_of(&big);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, "limits.tracking_error_m");
    assert!(
        found[0].1.contains("0.300 + 2 × 0.400 = 1.100 m")
            && found[0].1.contains("at most 0.340 m fits"),
        "{}",
        found[0].1
    );

    let fits = BASE.replace(
        "safety_distance_m: 0.3 }",
        "safety_distance_m: 0.3, tracking_error_m: 0.1 }",
    );
    let m = mission::from_yaml(&fits, "case.yaml".as_ref()).expect("valid");
    assert_eq!(m.limits.tracking_error_m, 0.1);
}

/// A geo origin must be a place on Earth.
#[test]
fn geo_origin_out_of_range_is_refused() {
    let yaml = BASE.replace(
        "origin_m: [0.0, 0.0, 1.5]",
        "origin_m: [0.0, 0.0, 1.5]\n  geo_origin: { lat_deg: 95.0, lon_deg: 8.5, alt_m: 488.0 }",
    );
    let found = problems_of(&yaml);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, "world.geo_origin.lat_deg");
}

/// `link.relays` and `link.zenoh`: every drone served by exactly one relay that
/// exists, endpoints Zenoh can use, and system ids unique within each relay's
/// own MAVLink network (not across relays).
#[test]
fn relays_serve_each_drone_once_and_scope_system_ids() {
    let with_link = |link: &str| {
        BASE.replace(
            "link: { autopilot: px4, setpoint_rate_hz: 20 }",
            &format!("link: {{ autopilot: px4, setpoint_rate_hz: 20, {link} }}"),
        )
    };
    let good = with_link(
        "relays: [{ name: north, drones: [b1] }, { name: south, drones: [b2, r1] }], zenoh: { listen: [tcp/127.0.0.1:7447] }",
    );
    let m = mission::from_yaml(&good, "case.yaml".as_ref()).expect("valid");
    assert_eq!(m.link.relays.len(), 2);
    assert_eq!(m.link.relays[1].drones, ["b2", "r1"]);

    let found = problems_of(&with_link(
        "relays: [{ name: north, drones: [b1, b2, x9] }, { name: north, drones: [b2] }], zenoh: { connect: [udp/1.2.3.4] }",
    ));
    let has = |path: &str, text: &str| found.iter().any(|(p, m, _)| p == path && m.contains(text));
    assert!(has("link.zenoh.connect[0]", "tcp/HOST:PORT"), "{found:#?}");
    assert!(
        has("link.relays[0].drones[2]", "no drone \"x9\""),
        "{found:#?}"
    );
    assert!(
        has("link.relays[1].name", "already link.relays[0]"),
        "{found:#?}"
    );
    assert!(
        has("link.relays[1].drones[0]", "already served by relay north"),
        "{found:#?}"
    );
    assert!(has("link.relays", "no relay serves r1"), "{found:#?}");

    // b1 and b2 both system 1: one network refuses it, two relays do not.
    let same_id = good.replace("system_id: 2", "system_id: 1");
    assert!(mission::from_yaml(&same_id, "case.yaml".as_ref()).is_ok());
    let one_relay = same_id.replace(
        "relays: [{ name: north, drones: [b1] }, { name: south, drones: [b2, r1] }]",
        "relays: [{ name: north, drones: [b1, b2, r1] }]",
    );
    let found = problems_of(&one_relay);
    assert!(
        found
            .iter()
            .any(|(p, m, _)| p == "groups[0].drones[1].system_id"
                && m.contains("in relay north's network")),
        "{found:#?}"
    );
}
