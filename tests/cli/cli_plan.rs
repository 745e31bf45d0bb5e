//! `swarmctl plan` end to end: example missions and community instance formats.

use assert_cmd::Command;
use predicates::str::contains;
use std::path::{Path, PathBuf};
use swarmctl::plan::DiscretePlan;

fn swarmctl() -> Command {
    Command::cargo_bin("swarmctl").expect("binary built")
}

fn repo(path: &str) -> PathBuf {
    crate::support::repo_root().join(path)
}

/// Plans `input` (with extra args) into a temporary file, validates it independently
/// against the mission swarmctl would load, and returns it.
fn plan_file(input: &Path, extra: &[&str]) -> DiscretePlan {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("plan.json");
    swarmctl()
        .arg("plan")
        .arg(input)
        .args(extra)
        .arg("-o")
        .arg(&out)
        .assert()
        .success()
        .stdout(contains("makespan"))
        .stdout(contains("conflict tree"));
    let text = std::fs::read_to_string(&out).expect("plan written");
    let json: serde_json::Value = serde_json::from_str(&text).expect("json");
    for field in [
        "makespan_steps",
        "sum_of_costs_steps",
        "makespan_s",
        "legs",
        "drones",
        "execution",
    ] {
        assert!(json.get(field).is_some(), "plan file lacks {field}");
    }
    for field in ["id", "group", "pad", "goal", "path"] {
        assert!(
            json["drones"][0].get(field).is_some(),
            "drone entry lacks {field}"
        );
    }
    let plan: DiscretePlan = serde_json::from_str(&text).expect("plan schema");
    let agents = extra
        .iter()
        .position(|&a| a == "--agents")
        .and_then(|i| extra.get(i + 1))
        .and_then(|n| n.parse().ok());
    let mission = swarmctl::import::load_any(input, agents).expect("loads");
    if let Err(v) = swarmctl::plan::validate_plan(&mission, &plan) {
        panic!("{}: {v:#?}", input.display());
    }
    plan
}

/// The first formation's leg (starts to goals): (makespan, sum of costs), steps.
fn formation_leg(plan: &DiscretePlan) -> (u32, u64) {
    let k = plan
        .legs
        .iter()
        .position(|l| l.name == "formation")
        .expect("a formation leg");
    let begin = if k == 0 { 0 } else { plan.legs[k - 1].end_step } as usize;
    let end = plan.legs[k].end_step as usize;
    let cost = plan
        .drones
        .iter()
        .map(|d| {
            let window = &d.path[begin..=end];
            let arrived = window.iter().rposition(|v| *v != window[window.len() - 1]);
            arrived.map_or(0, |i| i as u64 + 1)
        })
        .sum();
    (plan.legs[k].makespan_steps, cost)
}

#[test]
fn plans_every_example_mission() {
    let expected = [
        ("missions/paper-example.yaml", Some(4)),
        ("missions/swap-corridor.yaml", Some(8)),
        ("missions/formation-change.yaml", None),
        ("missions/paper-scale.yaml", None),
        ("missions/small-show.yaml", None),
    ];
    for (file, makespan) in expected {
        let plan = plan_file(&repo(file), &[]);
        if let Some(makespan) = makespan {
            assert_eq!(formation_leg(&plan).0, makespan, "{file}");
        }
        assert_eq!(
            plan.legs.last().map(|l| l.end_step),
            Some(plan.makespan_steps)
        );
    }
}

#[test]
fn imports_lib_multi_robot_planning_instances() {
    let plan = plan_file(
        &repo("tests/data/libMultiRobotPlanning/map_8by8_obst12_agents5_ex1.yaml"),
        &[],
    );
    assert_eq!(plan.drones.len(), 5);
    // Target assignment: both agents share two potential goals; that project's
    // tests give 6 as the optimal sum of costs, and the makespan optimum is 3.
    let plan = plan_file(
        &repo("tests/data/libMultiRobotPlanning/mapfta_simple1_a1.yaml"),
        &[],
    );
    assert_eq!(formation_leg(&plan), (3, 6));
    assert_eq!(plan.drones[0].group, plan.drones[1].group);
}

#[test]
fn rejects_agents_without_goals_clearly() {
    swarmctl()
        .arg("plan")
        .arg(repo(
            "tests/data/libMultiRobotPlanning/mapfta_simple1_a2.yaml",
        ))
        .assert()
        .failure()
        .stderr(contains("mapfta_simple1_a2.yaml"))
        .stderr(contains("agent \"agent1\" has no potential goals"));
}

#[test]
fn imports_moving_ai_maps_and_scenarios() {
    let scen = repo("tests/data/movingai/random-32-32-10-random-1.scen");
    let plan = plan_file(&scen, &["--agents", "20"]);
    assert_eq!(plan.drones.len(), 20);
    // --scen is the same as the positional form.
    swarmctl()
        .args(["plan", "--agents", "5", "--scen"])
        .arg(&scen)
        .assert()
        .success();
    swarmctl()
        .args(["plan", "--agents", "5000"])
        .arg(&scen)
        .assert()
        .failure()
        .stderr(contains("asked for 5000 agents"));
}

#[test]
fn imports_moving_ai_3d_voxel_maps() {
    let plan = plan_file(
        &repo("tests/data/movingai3d/tiny-8-6-4.3dscen"),
        &["--agents", "6"],
    );
    assert_eq!(plan.drones.len(), 6);
    assert!(plan.drones.iter().any(|d| d.path.iter().any(|v| v.z > 0)));
}

#[test]
fn deadline_error_names_the_lower_bound() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mission = dir.path().join("big.yaml");
    swarmctl()
        .args([
            "gen",
            "--size",
            "8x8x2",
            "--obstacles",
            "20",
            "--drones",
            "60",
            "--groups",
            "12",
            "--seed",
            "3",
            "-o",
        ])
        .arg(&mission)
        .assert()
        .success();
    let out = swarmctl()
        .arg("plan")
        .arg(&mission)
        .args(["--deadline", "0.000001"])
        .output()
        .expect("runs");
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("no plan within the deadline"), "{stderr}");
        assert!(stderr.contains("optimal makespan is at least"), "{stderr}");
    }
}

/// `swarmctl fly --plan` refuses a plan file that does not fit the mission, names
/// the file and the problem, and starts nothing (no simulator, no flight log):
/// a teleporting path, a truncated file, a path through the corridor's floor (the
/// plan validator) and a trajectory sample moved by hand (the file no longer holds
/// what its plan composes to, so what was checked would not be what flies).
#[test]
fn fly_refuses_a_broken_plan_before_starting_anything() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mission = repo("missions/swap-corridor.yaml");
    let good = dir.path().join("plan.json");
    swarmctl()
        .arg("plan")
        .arg(&mission)
        .arg("-o")
        .arg(&good)
        .assert()
        .success();
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&good).expect("plan written")).expect("json");
    // Teleport drone "a" two voxels along the corridor at step 1.
    let voxel = &mut json["drones"][0]["path"][1];
    voxel[0] = serde_json::json!(voxel[0].as_u64().expect("x") + 2);
    let broken = dir.path().join("broken-plan.json");
    std::fs::write(&broken, serde_json::to_string(&json).expect("json")).expect("write");
    let truncated = dir.path().join("truncated-plan.json");
    let text = std::fs::read_to_string(&good).expect("plan");
    std::fs::write(&truncated, &text[..text.len() / 2]).expect("write");
    let original: serde_json::Value = serde_json::from_str(&text).expect("json");

    // Drone "a" dips into the corridor's floor (rock at z = 0 for x = 1..=5)
    // where it flies along the corridor.
    let mut json = original.clone();
    let path = json["drones"][0]["path"].as_array_mut().expect("path");
    let step = path
        .iter()
        .position(|v| v[2] == 1 && (1..=5).contains(&v[0].as_i64().expect("x")))
        .expect("a flies along the corridor");
    path[step][2] = serde_json::json!(0);
    let through_rock = dir.path().join("through-rock-plan.json");
    std::fs::write(&through_rock, serde_json::to_string(&json).expect("json")).expect("write");

    // One trajectory sample of drone "a" moved 0.3 m north, nothing else changed.
    let mut json = original;
    let samples = json["drones"][0]["trajectory"]
        .as_array_mut()
        .expect("trajectory");
    let k = samples.len() / 2;
    let y_m = samples[k][2].as_f64().expect("y");
    samples[k][2] = serde_json::json!(y_m + 0.3);
    let moved = dir.path().join("moved-sample-plan.json");
    std::fs::write(&moved, serde_json::to_string(&json).expect("json")).expect("write");
    let moved_field = format!("drones[0].trajectory[{k}][2]");

    for (plan, expected) in [
        (&broken, "jumps from"),
        (&truncated, "is not valid JSON"),
        (&through_rock, "inside an obstacle"),
        (&moved, "does not hold what its plan composes to"),
        (&moved, moved_field.as_str()),
    ] {
        let log = dir.path().join("flight.json");
        let out = swarmctl()
            .arg("fly")
            .arg(&mission)
            .arg("--plan")
            .arg(plan)
            .arg("--log")
            .arg(&log)
            .timeout(std::time::Duration::from_secs(60))
            .output()
            .expect("runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{stderr}");
        assert!(stderr.contains(&plan.display().to_string()), "{stderr}");
        assert!(stderr.contains(expected), "{stderr}");
        assert!(
            !stderr.contains("started the bundled simulator"),
            "{stderr}"
        );
        assert!(!log.exists(), "a flight log was written");
    }
}

/// The plan says how good it is: each leg's line and the flight's state the bound
/// proven against the makespan, and the plan file keeps it per leg. With time
/// enough the paper-scale mission is optimal leg by leg; `--optimal` demands it
/// and, on a deadline far too short, fails naming the bound instead of
/// returning a plan above it.
#[test]
fn plan_states_its_bound_and_gap() {
    let mission = repo("missions/paper-scale.yaml");
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("plan.json");
    let run = swarmctl()
        .arg("plan")
        .arg(&mission)
        .arg("-o")
        .arg(&out)
        .output()
        .expect("runs");
    assert!(run.status.success());
    let stdout = String::from_utf8_lossy(&run.stdout);
    let legs: Vec<&str> = stdout.lines().filter(|l| l.starts_with("  leg ")).collect();
    assert_eq!(legs.len(), 3, "{stdout}");
    for line in &legs {
        assert!(line.contains("optimal by"), "{line}");
    }
    let plan: DiscretePlan =
        serde_json::from_str(&std::fs::read_to_string(&out).expect("written")).expect("plan");
    for leg in &plan.legs {
        assert_eq!(
            leg.proven_bound_steps,
            Some(leg.makespan_steps),
            "{}",
            leg.name
        );
        assert_eq!(leg.gap_steps(), 0);
    }
    let demanding = swarmctl()
        .arg("plan")
        .arg(&mission)
        .args(["--optimal", "--deadline", "0.000001"])
        .output()
        .expect("runs");
    assert!(!demanding.status.success());
    let stderr = String::from_utf8_lossy(&demanding.stderr);
    assert!(stderr.contains("optimal makespan is at least"), "{stderr}");
}

#[test]
fn plans_a_scenario_as_one_group_and_writes_its_figures() {
    let scen = repo("tests/data/movingai/random-32-32-10-random-1.scen");
    let dir = tempfile::tempdir().expect("temp dir");
    let (out, stats) = (dir.path().join("plan.json"), dir.path().join("stats.json"));
    swarmctl()
        .arg("plan")
        .arg(&scen)
        .args(["--agents", "30", "--one-group", "-o"])
        .arg(&out)
        .arg("--stats")
        .arg(&stats)
        .assert()
        .success()
        .stdout(contains("planned 30 drones in 1 group\n"));
    let plan: DiscretePlan =
        serde_json::from_str(&std::fs::read_to_string(&out).expect("plan")).expect("plan schema");
    let mission = swarmctl::import::load_as_one_group(&scen, Some(30)).expect("loads");
    if let Err(v) = swarmctl::plan::validate_plan(&mission, &plan) {
        panic!("{v:#?}");
    }
    assert!(
        plan.drones
            .iter()
            .all(|d| d.group == swarmctl::import::ONE_GROUP_NAME)
    );
    // Any agent may take any goal: never longer than each agent to its own goal.
    let labeled = plan_file(&scen, &["--agents", "30"]);
    let (one_group, own_goals) = (formation_leg(&plan).0, formation_leg(&labeled).0);
    assert!(
        one_group <= own_goals,
        "one group {one_group} > labeled {own_goals}"
    );

    let figures: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).expect("stats")).expect("json");
    let legs = figures["legs"].as_array().expect("legs");
    let formation = legs
        .iter()
        .find(|l| l["name"] == "formation")
        .expect("a formation leg");
    assert_eq!(formation["makespan_steps"], u64::from(one_group));
    let proven = formation["proven_bound_steps"].as_u64().expect("bound");
    assert!(proven <= u64::from(one_group));
    assert!(formation["time_s"].as_f64().is_some_and(|t| t >= 0.0));
    assert_eq!(legs.len(), plan.legs.len());
}

#[test]
fn one_group_is_refused_for_a_mission_file() {
    swarmctl()
        .args(["plan", "--one-group"])
        .arg(repo("missions/paper-example.yaml"))
        .assert()
        .failure()
        .stderr(contains("paper-example.yaml"))
        .stderr(contains("this is a mission file already"));
}
