//! Recordings made by `swarmctl` checked with the real Rerun CLI from `.venv`
//! (created by `bash .ci/install-peers`): `rerun rrd verify` must accept them and
//! `rerun rrd print` must list the entity paths a user looks for. A missing CLI
//! is a failure, not a skip.

use assert_cmd::Command;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use swarmctl::compiled::CompiledPlan;
use swarmctl::fly::{DroneLog, FlightLog, Summary, log::LogEvent};

const MISSION: &str = "missions/swap-corridor.yaml";

fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn rerun_cli() -> PathBuf {
    let rerun = repo_root().join(".venv/bin/rerun");
    assert!(
        rerun.exists(),
        "{} is missing: run `bash .ci/install-peers` first",
        rerun.display()
    );
    rerun
}

fn swarmctl() -> Command {
    let mut cmd = Command::cargo_bin("swarmctl").expect("binary built");
    cmd.current_dir(repo_root());
    cmd
}

/// `rerun rrd verify FILE` succeeds.
fn verify(rrd: &Path) {
    let out = std::process::Command::new(rerun_cli())
        .args(["rrd", "verify"])
        .arg(rrd)
        .output()
        .expect("run rerun rrd verify");
    assert!(
        out.status.success(),
        "rerun rrd verify {} failed:\n{}{}",
        rrd.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Entity paths of every chunk `rerun rrd print FILE` lists.
fn entity_paths(rrd: &Path) -> BTreeSet<String> {
    let out = std::process::Command::new(rerun_cli())
        .args(["rrd", "print"])
        .arg(rrd)
        .output()
        .expect("run rerun rrd print");
    assert!(out.status.success(), "rerun rrd print failed");
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter(|l| l.starts_with("Chunk("))
        .filter_map(|l| l.split(" - ").nth(1))
        .map(str::to_string)
        .collect()
}

fn assert_has(paths: &BTreeSet<String>, expected: &[String]) {
    let missing: Vec<&String> = expected.iter().filter(|e| !paths.contains(*e)).collect();
    assert!(
        missing.is_empty(),
        "missing entity paths {missing:?} in {paths:#?}"
    );
}

/// Plans the corridor mission, writing the plan and its recording into `dir`.
fn plan(dir: &Path) -> (PathBuf, CompiledPlan) {
    let (json, rrd) = (dir.join("plan.json"), dir.join("plan.rrd"));
    swarmctl()
        .args(["plan", MISSION, "-o"])
        .arg(&json)
        .arg("--rrd")
        .arg(&rrd)
        .assert()
        .success();
    let plan = serde_json::from_str(&std::fs::read_to_string(&json).expect("plan written"))
        .expect("plan parses");
    (rrd, plan)
}

fn plan_paths(plan: &CompiledPlan) -> Vec<String> {
    let mut expected: Vec<String> = [
        "/world/bounds",
        "/world/obstacles",
        "/metrics/plan/min_separation_m",
        "/metrics/plan/safety_distance_m",
        "/events/plan",
    ]
    .map(String::from)
    .to_vec();
    for d in &plan.drones {
        for kind in ["drones", "paths", "safety"] {
            expected.push(format!("/world/plan/{kind}/{}", d.id));
        }
        expected.push(format!("/metrics/plan/speed_mps/{}", d.id));
    }
    expected
}

#[test]
fn plan_recording_verifies_and_lists_the_plan() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (rrd, plan) = plan(dir.path());
    verify(&rrd);
    assert_has(&entity_paths(&rrd), &plan_paths(&plan));
}

/// A flight log that flew the plan exactly, 2 s after arming, plus one event.
fn synthetic_flight(plan: &CompiledPlan) -> FlightLog {
    let offset_s = 2.0;
    let summary = Summary {
        completed: true,
        duration_s: plan.makespan_s + 2.0 * offset_s,
        planned_makespan_s: plan.makespan_s,
        executed_makespan_s: Some(plan.makespan_s),
        min_separation_m: plan.check.min_separation_bound_m,
        closest_pair: None,
        min_separation_takeoff_landing_m: 1.0,
        safety_distance_m: 0.25,
        max_speed_mps: plan.check.max_speed_mps,
        speed_limit_mps: 1.0,
        gating_waits: 0,
        gating_wait_s: 0.0,
        max_final_distance_to_goal_m: 0.0,
    };
    let drones = plan
        .drones
        .iter()
        .enumerate()
        .map(|(i, d)| DroneLog {
            id: d.id.clone(),
            system_id: i as u8 + 1,
            endpoint: "127.0.0.1:0".into(),
            autopilot: None,
            goal_m: d.trajectory.last().map_or([0.0; 3], |s| [s[1], s[2], s[3]]),
            final_distance_to_goal_m: Some(0.0),
            gating_waits: 0,
            gating_wait_s: 0.0,
            link_losses: 0,
            samples: d
                .trajectory
                .iter()
                .map(|s| [s[0] + offset_s, s[1], s[2], s[3]])
                .collect(),
        })
        .collect();
    FlightLog {
        mission: plan.mission.clone(),
        summary,
        drones,
        events: vec![LogEvent {
            t_s: offset_s,
            drone: None,
            message: "all drones at their start: executing the plan".into(),
        }],
    }
}

#[test]
fn replay_recording_has_flight_beside_plan() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (_, plan) = plan(dir.path());
    let log = dir.path().join("flight.json");
    std::fs::write(
        &log,
        serde_json::to_string(&synthetic_flight(&plan)).expect("json"),
    )
    .expect("write log");
    let rrd = dir.path().join("replay.rrd");
    swarmctl()
        .arg("replay")
        .arg(&log)
        .args(["--mission", MISSION, "--plan"])
        .arg(dir.path().join("plan.json"))
        .arg("--rrd")
        .arg(&rrd)
        .assert()
        .success();
    verify(&rrd);
    let mut expected = plan_paths(&plan);
    expected.extend(
        [
            "/metrics/flight/min_separation_m",
            "/metrics/flight/safety_distance_m",
            "/events/flight",
        ]
        .map(String::from),
    );
    for d in &plan.drones {
        for kind in ["drones", "paths", "safety"] {
            expected.push(format!("/world/flight/{kind}/{}", d.id));
        }
        expected.push(format!("/metrics/flight/speed_mps/{}", d.id));
    }
    assert_has(&entity_paths(&rrd), &expected);
}

#[test]
fn replay_without_mission_writes_a_recording_beside_the_log() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (_, plan) = plan(dir.path());
    let log = dir.path().join("flight.json");
    std::fs::write(
        &log,
        serde_json::to_string(&synthetic_flight(&plan)).expect("json"),
    )
    .expect("write log");
    swarmctl().arg("replay").arg(&log).assert().success();
    let rrd = dir.path().join("flight.rrd");
    verify(&rrd);
    let expected: Vec<String> = plan
        .drones
        .iter()
        .map(|d| format!("/world/flight/drones/{}", d.id))
        .collect();
    assert_has(&entity_paths(&rrd), &expected);
}
