//! Recordings made by `swarmctl` checked with the real Rerun CLI from `.venv`
//! (created by `bash .ci/install-peers`): `rerun rrd verify` must accept them and
//! `rerun rrd print` must list the entity paths a user looks for. A missing CLI
//! is a failure, not a skip, except for the tests that start a headless viewer
//! (`--connect`, `--spawn`), which say why they skip.
//!
//! A swarm is a few entities holding every drone as an instance labelled with its
//! id (`/world/plan/drones`, `/metrics/flight/speed_mps`, ...), not one entity per
//! drone: see `viz/src/paths.rs`.

use assert_cmd::Command;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};
use swarmctl::compiled::CompiledPlan;
use swarmctl::fly::{DroneLog, FlightLog, LogEvent, Summary};

const MISSION: &str = "missions/swap-corridor.yaml";
/// An ellipsoid mission: horizontal radius 0.25 m, vertical 0.75 m.
const DOWNWASH: &str = "missions/paper-scale-downwash.yaml";

fn repo_root() -> PathBuf {
    crate::support::repo_root()
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
    chunk_paths(&out.stdout)
}

fn chunk_paths(printed: &[u8]) -> BTreeSet<String> {
    String::from_utf8_lossy(printed)
        .lines()
        .filter(|l| l.starts_with("Chunk("))
        .filter_map(|l| l.split(" - ").nth(1))
        .map(|p| p.trim().to_string())
        .collect()
}

/// What `rerun rrd print -vvv` shows of one entity (its data as tables).
fn entity_dump(rrd: &Path, entity: &str) -> String {
    let out = std::process::Command::new(rerun_cli())
        .args(["rrd", "print", "-vvv", "--entity", entity])
        .arg(rrd)
        .output()
        .expect("run rerun rrd print");
    assert!(out.status.success(), "rerun rrd print -vvv failed");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Every drone of the plan is an instance of `entity`, labelled with its id.
fn assert_labelled(rrd: &Path, entity: &str, plan: &CompiledPlan) {
    let dump = entity_dump(rrd, entity);
    for d in &plan.drones {
        assert!(
            dump.contains(&d.id),
            "{entity} has no label {:?}:\n{dump}",
            d.id
        );
    }
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
    plan_mission(dir, MISSION)
}

/// Plans `mission`, writing the plan and its recording into `dir`.
fn plan_mission(dir: &Path, mission: &str) -> (PathBuf, CompiledPlan) {
    let (json, rrd) = (dir.join("plan.json"), dir.join("plan.rrd"));
    swarmctl()
        .args(["plan", mission, "-o"])
        .arg(&json)
        .arg("--rrd")
        .arg(&rrd)
        .assert()
        .success();
    let plan = serde_json::from_str(&std::fs::read_to_string(&json).expect("plan written"))
        .expect("plan parses");
    (rrd, plan)
}

fn plan_paths() -> Vec<String> {
    [
        "/world/bounds",
        "/world/obstacles",
        "/world/plan/drones",
        "/world/plan/safety",
        "/world/plan/paths",
        "/metrics/plan/speed_mps",
        "/metrics/plan/min_separation_m",
        "/metrics/plan/safety_distance_m",
        "/events/plan",
    ]
    .map(String::from)
    .to_vec()
}

fn flight_paths() -> Vec<String> {
    [
        "/world/flight/drones",
        "/world/flight/safety",
        "/world/flight/paths",
        "/metrics/flight/speed_mps",
        "/metrics/flight/min_separation_m",
        "/metrics/flight/safety_distance_m",
        "/events/flight",
    ]
    .map(String::from)
    .to_vec()
}

#[test]
fn plan_recording_verifies_and_lists_the_plan() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (rrd, plan) = plan(dir.path());
    verify(&rrd);
    assert_has(&entity_paths(&rrd), &plan_paths());
    assert_labelled(&rrd, "/world/plan/drones", &plan);
    assert_labelled(&rrd, "/metrics/plan/speed_mps", &plan);
    // The stage timeline: one event per leg, as the last drone is in place.
    let events = entity_dump(&rrd, "/events/plan");
    for leg in ["takeoff", "formation", "landing"] {
        assert!(
            events.contains(&format!("leg \"{leg}\" done")),
            "no event for leg {leg}:\n{events}"
        );
    }
}

/// The separation shapes of `entity` have half sizes `half` (half the
/// separation's radii: touching shapes mean a breach) and no other. `rrd print`
/// cuts long lists short, so this reads the shape, not one entry per drone.
fn assert_half_sizes(rrd: &Path, entity: &str, half: [f32; 3]) {
    let dump = entity_dump(rrd, entity);
    let shown = |h: [f32; 3]| dump.contains(&format!("[{}, {}, {}]", h[0], h[1], h[2]));
    assert!(shown(half), "{entity} has no half sizes {half:?}:\n{dump}");
    let (sphere, ellipsoid) = ([0.125; 3], [0.125, 0.125, 0.375]);
    let other = if half == sphere { ellipsoid } else { sphere };
    assert!(!shown(other), "{entity} has half sizes {other:?}:\n{dump}");
}

/// Paths only an ellipsoid mission's recording has, for `kind` (`plan`, `flight`).
fn scaled_paths(kind: &str) -> Vec<String> {
    vec![
        format!("/metrics/{kind}/min_scaled_separation"),
        format!("/metrics/{kind}/scaled_limit"),
    ]
}

/// Under an ellipsoid the plan recording draws each drone's ellipsoid (half
/// sizes H/2, H/2, V/2), plots the scaled separation and states the checker's
/// bound; a sphere mission's recording has no scaled plot.
#[test]
fn plan_recording_draws_the_ellipsoid_and_the_scaled_separation() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (rrd, plan) = plan_mission(dir.path(), DOWNWASH);
    verify(&rrd);
    let mut expected = plan_paths();
    expected.extend(scaled_paths("plan"));
    assert_has(&entity_paths(&rrd), &expected);
    assert_half_sizes(&rrd, "/world/plan/safety", [0.125, 0.125, 0.375]);
    let bound = plan
        .check
        .scaled
        .as_ref()
        .expect("an ellipsoid mission")
        .min_bound;
    let events = entity_dump(&rrd, "/events/plan");
    let line = format!("checker: min scaled separation of setpoints ≥ {bound:.3} (held");
    assert!(events.contains(&line), "no {line:?} in:\n{events}");

    let sphere = tempfile::tempdir().expect("temp dir");
    let (rrd, _) = plan_mission(sphere.path(), MISSION);
    assert_half_sizes(&rrd, "/world/plan/safety", [0.125; 3]);
    let paths = entity_paths(&rrd);
    let scaled: Vec<String> = scaled_paths("plan")
        .into_iter()
        .filter(|p| paths.contains(p))
        .collect();
    assert!(scaled.is_empty(), "a sphere mission has {scaled:?}");
}

/// Plans the corridor swap into `dir` and writes a flight log that flew it
/// exactly, `dir/flight.json`.
fn planned_flight_log(dir: &Path) -> (CompiledPlan, PathBuf) {
    let (_, plan) = plan(dir);
    let log = dir.join("flight.json");
    std::fs::write(
        &log,
        serde_json::to_string(&synthetic_flight(&plan)).expect("json"),
    )
    .expect("write log");
    (plan, log)
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
        vertical_separation_m: None,
        min_scaled_separation: None,
        closest_scaled_pair: None,
        safety_held: true,
        safety_distance_m: 0.25,
        max_speed_mps: plan.check.max_speed_mps,
        fastest: None,
        speed_held: true,
        speed_limit_mps: 1.0,
        gating_waits: 0,
        gating_wait_s: 0.0,
        longest_gating_wait: None,
        lateness: None,
        max_final_distance_to_goal_m: 0.0,
        worst_tracking: None,
        tracking_bound_m: 0.3,
        tracking_held: true,
        tracking_holds: 0,
        tracking_hold_s: 0.0,
        lost: Vec::new(),
        lost_last_known: Vec::new(),
        retired: Vec::new(),
        handed_over: Vec::new(),
        replans: Vec::new(),
        check: None,
        unaccounted: Vec::new(),
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
            longest_gating_wait_s: 0.0,
            lateness: Vec::new(),
            link_losses: 0,
            tracking_error: None,
            tracking_holds: 0,
            tracking_hold_s: 0.0,
            frame: swarmctl::fly::FrameFix::Shared,
            local_origin_enu_m: [0.0; 3],
            link_traffic: None,
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
            message: swarmctl::fly::PLAN_STARTED.into(),
        }],
        armed_at_unix_s: None,
        start_at_unix_s: None,
    }
}

#[test]
fn replay_recording_has_flight_beside_plan() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (plan, log) = planned_flight_log(dir.path());
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
    let mut expected = plan_paths();
    expected.extend(flight_paths());
    assert_has(&entity_paths(&rrd), &expected);
    assert_labelled(&rrd, "/world/flight/drones", &plan);
}

#[test]
fn replay_without_mission_writes_a_recording_beside_the_log() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (plan, log) = planned_flight_log(dir.path());
    // The live recording `fly` leaves beside its log is never replaced.
    let live = dir.path().join("flight.rrd");
    std::fs::write(&live, b"the live recording").expect("write live recording");
    let out = swarmctl()
        .arg("replay")
        .arg(&log)
        .output()
        .expect("run replay");
    assert!(out.status.success(), "{out:?}");
    let rrd = dir.path().join("flight.replay.rrd");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(&rrd.display().to_string()), "{stdout}");
    assert_eq!(std::fs::read(&live).expect("live"), b"the live recording");
    verify(&rrd);
    assert_has(&entity_paths(&rrd), &flight_paths());
    assert_labelled(&rrd, "/world/flight/drones", &plan);
    // A second replay replaces the first, and says so.
    let out = swarmctl()
        .arg("replay")
        .arg(&log)
        .output()
        .expect("run replay");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("(replaced the file that was there)"),
        "{stdout}"
    );
}

/// A log, a mission and a plan that do not belong together are refused, naming
/// what differs, as `fly --plan` refuses a plan of another mission.
#[test]
fn replay_refuses_a_mission_or_plan_the_log_was_not_flown_from() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (_, log) = planned_flight_log(dir.path());
    let out = swarmctl()
        .arg("replay")
        .arg(&log)
        .args(["--mission", "missions/formation-change.yaml"])
        .output()
        .expect("run replay");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("was not flown from missions/formation-change.yaml")
            && stderr.contains("the log is of mission"),
        "{stderr}"
    );
    // The right mission with another mission's plan.
    let other = dir.path().join("other");
    std::fs::create_dir(&other).expect("dir");
    plan_mission(&other, "missions/formation-change.yaml");
    let out = swarmctl()
        .arg("replay")
        .arg(&log)
        .args(["--mission", MISSION, "--plan"])
        .arg(other.join("plan.json"))
        .output()
        .expect("run replay");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("is not a valid plan for mission"),
        "{stderr}"
    );
    assert!(!dir.path().join("flight.replay.rrd").exists());
}

/// A replayed ellipsoid flight draws the flown drones' ellipsoids and plots their
/// scaled separation, with the summary's figure as an event: from the mission
/// when given, from the log's summary when not.
#[test]
fn replay_of_an_ellipsoid_flight_draws_ellipsoids_and_the_scaled_separation() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (_, plan) = plan_mission(dir.path(), DOWNWASH);
    let mut flight = synthetic_flight(&plan);
    flight.summary.vertical_separation_m = Some(0.75);
    flight.summary.min_scaled_separation = Some(1.304);
    let (a, b) = (plan.drones[0].id.clone(), plan.drones[1].id.clone());
    flight.summary.closest_scaled_pair = Some((a.clone(), b.clone(), 12.5));
    let log = dir.path().join("flight.json");
    std::fs::write(&log, serde_json::to_string(&flight).expect("json")).expect("write log");
    let with_mission = dir.path().join("replay.rrd");
    swarmctl()
        .arg("replay")
        .arg(&log)
        .args(["--mission", DOWNWASH, "--plan"])
        .arg(dir.path().join("plan.json"))
        .arg("--rrd")
        .arg(&with_mission)
        .assert()
        .success();
    swarmctl().arg("replay").arg(&log).assert().success();
    let without_mission = dir.path().join("flight.replay.rrd");
    let half = [0.125, 0.125, 0.375];
    for rrd in [&with_mission, &without_mission] {
        verify(rrd);
        let mut expected = flight_paths();
        expected.extend(scaled_paths("flight"));
        assert_has(&entity_paths(rrd), &expected);
        assert_half_sizes(rrd, "/world/flight/safety", half);
        let events = entity_dump(rrd, "/events/flight");
        let line =
            format!("summary: min scaled separation from telemetry 1.304, {a} and {b} (held");
        assert!(events.contains(&line), "no {line:?} in:\n{events}");
    }
    assert_half_sizes(&with_mission, "/world/plan/safety", half);
}

/// `swarmctl fly` records live while it flies the bundled SITL: the recording
/// beside the log has the plan and the flown drones, and the report counts the
/// samples taken live.
#[test]
fn fly_records_live_beside_the_log() {
    let dir = tempfile::tempdir().expect("temp dir");
    let log = dir.path().join("flight.json");
    let out = swarmctl()
        .args(["fly", MISSION, "--plain", "--log"])
        .arg(&log)
        .timeout(Duration::from_secs(180))
        .output()
        .expect("run swarmctl fly");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "swarmctl fly failed:\n{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("recording"))
        .unwrap_or_else(|| panic!("no recording line in:\n{stdout}"));
    assert!(line.contains("samples live, 0 dropped"), "{line}");
    let rrd = dir.path().join("flight.rrd");
    verify(&rrd);
    let mut expected = plan_paths();
    expected.extend(flight_paths());
    assert_has(&entity_paths(&rrd), &expected);
    // The plan is on the flight timeline too (logged when execution began).
    let dump = entity_dump(&rrd, "/world/plan/drones");
    assert!(dump.contains("flight_time"), "plan not on flight_time");
}

// --- A real viewer: `--connect` and `--spawn` against a headless `rerun` ---

/// The venv's `rerun`, or `None` (with the reason on stderr) to skip a viewer test.
fn rerun_or_skip(test: &str) -> Option<PathBuf> {
    let rerun = repo_root().join(".venv/bin/rerun");
    if rerun.exists() {
        Some(rerun)
    } else {
        eprintln!(
            "SKIPPED {test}: {} is missing (run `bash .ci/install-peers`)",
            rerun.display()
        );
        None
    }
}

/// A port on 127.0.0.1 that was free a moment ago.
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("bind 127.0.0.1:0")
        .port()
}

fn listening(port: u16) -> bool {
    let addr = std::net::SocketAddr::from(([127, 0, 0, 1], port));
    std::net::TcpStream::connect_timeout(&addr, Duration::from_millis(200)).is_ok()
}

fn wait_until(limit: Duration, mut ready: impl FnMut() -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if ready() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    ready()
}

/// A process group killed when dropped: the venv's `rerun` is a Python launcher
/// that starts the real viewer as its child, so killing the launcher alone would
/// leave the viewer running.
struct Group(u32, Option<std::process::Child>);

impl Group {
    fn spawn(cmd: &mut std::process::Command) -> Self {
        use std::os::unix::process::CommandExt;
        let child = cmd
            .process_group(0)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start rerun");
        Self(child.id(), Some(child))
    }
}

impl Drop for Group {
    fn drop(&mut self) {
        let Ok(pgid) = i32::try_from(self.0) else {
            return;
        };
        // SAFETY: signals only the process group we started (its id is its leader's pid).
        unsafe {
            libc::kill(-pgid, libc::SIGTERM);
        }
        if let Some(mut child) = self.1.take() {
            let _ = child.wait();
        }
    }
}

/// Subscribes to the viewer's gRPC server at `port` with a second `rerun` that
/// saves what it receives, and waits until the file lists every `expected` path.
fn read_back(rerun: &Path, port: u16, dir: &Path, expected: &[String]) {
    let saved = dir.join("from-viewer.rrd");
    let saver_port = free_port();
    let _saver = Group::spawn(
        std::process::Command::new(rerun)
            .arg("--save")
            .arg(&saved)
            .args(["--bind", "127.0.0.1", "--port", &saver_port.to_string()])
            .arg(format!("rerun+http://127.0.0.1:{port}/proxy")),
    );
    let mut found = BTreeSet::new();
    let complete = wait_until(Duration::from_secs(60), || {
        if saved.exists() {
            let out = std::process::Command::new(rerun)
                .args(["rrd", "print", "--continue-on-error=true"])
                .arg(&saved)
                .output()
                .expect("run rerun rrd print");
            found = chunk_paths(&out.stdout);
        }
        expected.iter().all(|e| found.contains(e))
    });
    assert!(
        complete,
        "the viewer on port {port} did not get {:?}; it has {found:#?}",
        expected
            .iter()
            .filter(|e| !found.contains(*e))
            .collect::<Vec<_>>()
    );
}

/// `swarmctl plan --connect` streams to a running (headless) viewer.
#[test]
fn plan_streams_to_a_running_viewer_with_connect() {
    let Some(rerun) = rerun_or_skip("plan_streams_to_a_running_viewer_with_connect") else {
        return;
    };
    let dir = tempfile::tempdir().expect("temp dir");
    let port = free_port();
    let _viewer = Group::spawn(
        std::process::Command::new(&rerun)
            .args(["--headless", "--hide-welcome-screen", "--bind", "127.0.0.1"])
            .args(["--port", &port.to_string()]),
    );
    assert!(
        wait_until(Duration::from_secs(60), || listening(port)),
        "headless rerun viewer did not listen on 127.0.0.1:{port}"
    );
    swarmctl()
        .args(["plan", MISSION, "-o"])
        .arg(dir.path().join("plan.json"))
        .args(["--connect", &format!("127.0.0.1:{port}")])
        .timeout(Duration::from_secs(120))
        .assert()
        .success();
    read_back(&rerun, port, dir.path(), &plan_paths());
}

/// `swarmctl plan --spawn` starts `rerun` from PATH (here a wrapper that makes it
/// headless and local) and streams to it. The SDK spawns on rerun's default port
/// 9876, so the test skips if something already listens there.
#[test]
fn plan_streams_to_a_spawned_viewer() {
    const DEFAULT_PORT: u16 = 9876;
    let Some(rerun) = rerun_or_skip("plan_streams_to_a_spawned_viewer") else {
        return;
    };
    if listening(DEFAULT_PORT) {
        eprintln!(
            "SKIPPED plan_streams_to_a_spawned_viewer: port {DEFAULT_PORT} is in use, \
             and --spawn would stream to whatever listens there"
        );
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).expect("bin dir");
    let pid_file = dir.path().join("viewer.pid");
    let wrapper = bin.join("rerun");
    std::fs::write(
        &wrapper,
        format!(
            "#!/bin/sh\n\
             if [ \"$1\" = --version ]; then exec '{rerun}' \"$@\"; fi\n\
             echo $$ > '{pid}'\n\
             exec '{rerun}' --headless --hide-welcome-screen --bind 127.0.0.1 \"$@\" >/dev/null 2>&1\n",
            rerun = rerun.display(),
            pid = pid_file.display()
        ),
    )
    .expect("write wrapper");
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&wrapper, std::fs::Permissions::from_mode(0o755))
            .expect("chmod wrapper");
    }
    let path = std::env::join_paths(std::iter::once(bin.clone()).chain(std::env::split_paths(
        &std::env::var_os("PATH").unwrap_or_default(),
    )))
    .expect("PATH");
    let result = swarmctl()
        .args(["plan", MISSION, "-o"])
        .arg(dir.path().join("plan.json"))
        .arg("--spawn")
        .env("PATH", path)
        .env_remove("CI")
        .timeout(Duration::from_secs(120))
        .output()
        .expect("run swarmctl plan --spawn");
    // The spawned viewer leads its own session (process group): stop it whatever happened.
    let viewer = std::fs::read_to_string(&pid_file)
        .ok()
        .and_then(|s| s.trim().parse().ok())
        .map(|pid| Group(pid, None));
    assert!(
        result.status.success(),
        "swarmctl plan --spawn failed:\n{}{}",
        String::from_utf8_lossy(&result.stdout),
        String::from_utf8_lossy(&result.stderr)
    );
    assert!(viewer.is_some(), "--spawn did not run the rerun on PATH");
    read_back(&rerun, DEFAULT_PORT, dir.path(), &plan_paths());
    drop(viewer);
}
