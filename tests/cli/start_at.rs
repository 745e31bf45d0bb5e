//! `fly --start-at` and what a flight says about keeping time (issue 32): plan
//! time 0 at the instant asked, measured from the flight log; a start that leaves
//! no time for takeoff refused before anybody arms; every event's lateness in the
//! log and the summary.

use assert_cmd::Command;
use std::path::Path;
use swarmctl::fly::FlightLog;

fn swarmctl() -> Command {
    let mut cmd = Command::cargo_bin("swarmctl").expect("binary built");
    cmd.current_dir(crate::support::repo_root());
    cmd
}

fn read_log(path: &Path) -> FlightLog {
    serde_json::from_str(&std::fs::read_to_string(path).expect("log written")).expect("a log")
}

/// The two-drone paper example started 12 s from now, taking off 6 s before:
/// the log's own clock puts plan time 0 within a setpoint period (50 ms) after
/// the instant, and every event every drone reached has its lateness recorded.
#[test]
fn the_plan_starts_at_the_instant_asked_and_every_event_is_timed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let log_path = dir.path().join("flight.json");
    let out = swarmctl()
        .args(["fly", "missions/paper-example.yaml", "--plain"])
        .args(["--start-at", "+12", "--takeoff-lead", "6", "--log"])
        .arg(&log_path)
        .timeout(std::time::Duration::from_secs(180))
        .output()
        .expect("run swarmctl");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let log = read_log(&log_path);
    let delay_s = swarmctl::fly::plan_start_delay_s(&log).expect("a start instant, and a start");
    assert!(
        (0.0..0.1).contains(&delay_s),
        "plan time 0 came {delay_s:.3} s after the instant"
    );
    // Armed no earlier than the lead before the instant (it waited on the ground).
    let (armed, at) = (log.armed_at_unix_s.unwrap(), log.start_at_unix_s.unwrap());
    assert!(
        at - armed <= 6.0 + 0.5,
        "armed {:.1} s before the start",
        at - armed
    );
    assert!(stdout.contains("start instant"), "{stdout}");
    let lateness = log.summary.lateness.as_ref().expect("lateness measured");
    let recorded: usize = log.drones.iter().map(|d| d.lateness.len()).sum();
    assert_eq!(lateness.events, recorded);
    assert!(log.drones.iter().all(|d| !d.lateness.is_empty()));
    assert!(stdout.contains("lateness             p50"), "{stdout}");
    assert!(
        stdout.contains("×)"),
        "the execution line gives the ratio: {stdout}"
    );
}

/// A start instant closer than the takeoff lead is refused before anybody arms,
/// saying how far away it is and what takeoff needs; a malformed one names the flag.
#[test]
fn a_start_too_soon_or_malformed_is_refused_before_takeoff() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = swarmctl()
        .args(["fly", "missions/paper-example.yaml", "--plain"])
        .args(["--start-at", "+2", "--takeoff-lead", "20", "--log"])
        .arg(dir.path().join("flight.json"))
        .timeout(std::time::Duration::from_secs(120))
        .output()
        .expect("run swarmctl");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("refused before takeoff")
            && stderr.contains("takeoff needs 20 s before it")
            && stderr.contains("nobody was armed"),
        "{stderr}"
    );
    let out = swarmctl()
        .args(["fly", "missions/paper-example.yaml", "--start-at", "noon"])
        .timeout(std::time::Duration::from_secs(60))
        .output()
        .expect("run swarmctl");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.contains("--start-at `noon`"), "{stderr}");
}
