//! What an operator meets first: `check` agreeing with `plan` and `fly`, errors
//! that say what a file is and print each cause once, exit codes, help text, and
//! a refused flight leaving nothing behind (issue 19). Each test fails without
//! the behaviour it names.

use assert_cmd::Command;
use std::path::{Path, PathBuf};
use std::process::Output;

fn swarmctl() -> Command {
    let mut cmd = Command::cargo_bin("swarmctl").expect("binary built");
    cmd.current_dir(crate::support::repo_root());
    cmd
}

/// A two-drone mission with 1 m voxels and room for a tall pad layer, with
/// `limits` and the drones' extra fields spliced in.
fn mission(limits: &str, a_extra: &str, b_extra: &str) -> String {
    format!(
        "name: hop
world: {{ dimensions: [4, 2, 2], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 3.0], pad_height_m: 1.0 }}
limits: {{ max_speed_mps: 1.0, max_accel_mps2: 1.0, {limits} }}
groups:
  - name: solo
    drones:
      - {{ id: a, start: [0, 0, 0]{a_extra} }}
      - {{ id: b, start: [0, 1, 0]{b_extra} }}
    goals: [[3, 0, 0], [3, 1, 0]]
"
    )
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write file");
    path
}

fn run(args: &[&str], file: &Path) -> Output {
    swarmctl()
        .args(args)
        .arg(file)
        .timeout(std::time::Duration::from_secs(120))
        .output()
        .expect("run swarmctl")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Item 1: whatever `plan` or `fly` refuses for the mission's own content,
/// `check` refuses first, with the same message.
#[test]
fn check_refuses_what_plan_and_fly_would_refuse_with_the_same_message() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cases = [
        (
            mission("safety_distance_m: 1.4", "", ""),
            "limits.safety_distance_m: 1.400 m does not fit: neighbouring drones' setpoints are only the voxel size (1.000 m) apart",
        ),
        (
            mission("safety_distance_m: 1.0", "", ""),
            "limits.safety_distance_m: 1.000 m does not fit",
        ),
        (
            mission("separation: { horizontal_m: 1.0, vertical_m: 0.5 }", "", ""),
            "limits.separation.horizontal_m: 1.000 m does not fit",
        ),
        (
            mission(
                "safety_distance_m: 0.3",
                ", endpoint: \"udp:127.0.0.1:14541\"",
                "",
            ),
            "groups[0].drones[1].endpoint: drone \"b\" has no endpoint but 1 of the 2 drones have one: give all drones one, or none",
        ),
    ];
    for (i, (text, expected)) in cases.iter().enumerate() {
        let file = write(dir.path(), &format!("case{i}.yaml"), text);
        for command in [&["check"][..], &["plan"], &["fly", "--plain"]] {
            let out = run(command, &file);
            let err = stderr(&out);
            assert_eq!(out.status.code(), Some(1), "{command:?} case {i}: {err}");
            assert!(err.contains(expected), "{command:?} case {i}: {err}");
        }
    }
    // 0.98 m fits in 1 m voxels (a centimetre each side for tracking): it plans.
    let file = write(
        dir.path(),
        "fits.yaml",
        &mission("safety_distance_m: 0.98", "", ""),
    );
    let out = run(&["plan"], &file);
    assert!(out.status.success(), "{}", stderr(&out));
}

/// Item 4: `link.lost_after_s` is the one setting for LOST, and it cannot come
/// before the link timeout.
#[test]
fn lost_after_must_not_come_before_the_link_timeout() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = mission("safety_distance_m: 0.3", "", "") + "link: { link_timeout_s: 30 }\n";
    let out = run(&["check"], &write(dir.path(), "m.yaml", &text));
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("link.lost_after_s: 10 s is shorter than link.link_timeout_s (30 s)"),
        "{err}"
    );
    let text = mission("safety_distance_m: 0.3", "", "")
        + "link: { link_timeout_s: 30, lost_after_s: 40 }\n";
    let out = run(&["check"], &write(dir.path(), "ok.yaml", &text));
    assert!(out.status.success(), "{}", stderr(&out));
}

/// Item 10: files that are not missions are named for what they are.
#[test]
fn files_that_are_not_missions_are_called_what_they_are() {
    let dir = tempfile::tempdir().expect("temp dir");
    let plan_file = dir.path().join("plan.json");
    let out = swarmctl()
        .args(["plan", "missions/swap-corridor.yaml", "-o"])
        .arg(&plan_file)
        .output()
        .expect("plan");
    assert!(out.status.success(), "{}", stderr(&out));
    let cases: [(PathBuf, &str); 5] = [
        (write(dir.path(), "empty.yaml", ""), "the file is empty"),
        (
            write(dir.path(), "prose.yaml", "This is my swarm mission.\n"),
            "not a YAML mapping: the file is a line of text",
        ),
        (
            write(
                dir.path(),
                "bracket.yaml",
                &mission("safety_distance_m: 0.3", "", "")
                    .replace("[3, 0, 0], [3, 1, 0]]", "[3, 0, 0], [3, 1, 0]"),
            ),
            "not valid YAML: unclosed `[` opened at 9:12",
        ),
        (
            plan_file,
            "this is a plan file (written by `swarmctl plan -o`), not a mission: fly it with `swarmctl fly MISSION --plan PLAN.json`",
        ),
        (
            write(dir.path(), "notes.yaml", "todo: buy drones\n"),
            "not a mission: none of name, world, limits and groups at the top level (found \"todo\")",
        ),
    ];
    for (file, expected) in &cases {
        let out = run(&["check"], file);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(err.contains(expected), "{}: {err}", file.display());
        assert!(
            !err.contains("unknown field") && !err.contains("missing field"),
            "{err}"
        );
    }
}

/// Item 11: every cause is printed once, and exit codes are 0 success, 1 a
/// failed plan or flight, 2 a usage error (a bad `--fault` included).
#[test]
fn errors_print_each_cause_once_and_exit_codes_are_consistent() {
    for args in [
        &["check", "no-such-mission.yaml"][..],
        &["plan", "no-such-mission.yaml"],
        &["fly", "no-such-mission.yaml"],
        &["replay", "no-such-flight.json"],
        &[
            "fly",
            "missions/swap-corridor.yaml",
            "--plan",
            "no-such-plan.json",
        ],
    ] {
        let out = swarmctl().args(args).output().expect("run");
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(err.matches("os error 2").count(), 1, "{args:?}: {err}");
    }
    for args in [
        &["fly", "missions/swap-corridor.yaml", "--no-such-flag"][..],
        &["fly", "missions/swap-corridor.yaml", "--fault", "slow=b1:2"],
        &["fly", "missions/swap-corridor.yaml", "--fault", "wind=3"],
        &[
            "fly",
            "missions/swap-corridor.yaml",
            "--fault",
            "lose=zz@5s",
        ],
    ] {
        let out = swarmctl().args(args).output().expect("run");
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
    }
    // Item 5: a slow drone is never faster than commanded.
    let out = swarmctl()
        .args(["fly", "missions/swap-corridor.yaml", "--fault", "slow=b1:2"])
        .output()
        .expect("run");
    assert!(
        stderr(&out).contains("speed factor must be in (0, 1]"),
        "{}",
        stderr(&out)
    );
}

/// Item 7: `fly --help` lists every fault kind with its syntax.
#[test]
fn fly_help_lists_every_fault_kind() {
    let out = swarmctl().args(["fly", "--help"]).output().expect("run");
    let help = String::from_utf8_lossy(&out.stdout);
    for kind in [
        "loss=10%",
        "latency=50ms",
        "dup=5%",
        "reorder=10%",
        "slow=DRONE_ID:0.5",
        "drop=DRONE_ID@5s+3s",
        "lose=DRONE_ID@5s",
        "crash=DRONE_ID@5s",
        "refuse-arm=DRONE_ID",
        "low-battery=DRONE_ID@10s",
        "critical-battery=DRONE_ID@10s",
    ] {
        assert!(help.contains(kind), "`fly --help` lacks {kind}:\n{help}");
    }
}

/// Item 6: a flight refused before arming leaves no recording (and no log).
#[test]
fn a_refused_flight_leaves_no_recording() {
    let dir = tempfile::tempdir().expect("temp dir");
    let log = dir.path().join("flight.json");
    let out = swarmctl()
        .args([
            "fly",
            "missions/swap-corridor.yaml",
            "--plain",
            "--pad-tolerance",
            "0",
            "--log",
        ])
        .arg(&log)
        .output()
        .expect("run");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--pad-tolerance must be a positive number"),
        "{err}"
    );
    assert!(!err.contains("started the bundled simulator"), "{err}");
    let left: Vec<_> = std::fs::read_dir(dir.path()).expect("dir").collect();
    assert!(left.is_empty(), "a refused flight left {left:?}");
}

/// Item 9: `plan` without `-o` says nothing was written and how to keep the plan.
#[test]
fn plan_without_output_says_how_to_keep_the_plan() {
    let out = swarmctl()
        .args(["plan", "missions/swap-corridor.yaml"])
        .output()
        .expect("run");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        text.contains("plan file       none written: give -o PLAN.json"),
        "{text}"
    );
    assert!(
        !text.contains(" 1 nodes") && !text.contains(" 1 steps"),
        "{text}"
    );
}

/// Item 4: a silent drone loses its link after `link.link_timeout_s` and is LOST
/// after `link.lost_after_s` (not a fixed 10 s); status lines say LOST from then
/// on, and the summary says where it was last heard from.
#[test]
fn lost_comes_after_lost_after_s_and_the_summary_says_where_it_was() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = std::fs::read_to_string(crate::support::repo_path("missions/swap-corridor.yaml"))
        .expect("mission")
        + "link: { link_timeout_s: 2, lost_after_s: 5 }\n";
    let file = write(dir.path(), "swap.yaml", &text);
    let log = dir.path().join("flight.json");
    let out = swarmctl()
        .args(["fly", "--plain", "--fault", "lose=a@4s", "--log"])
        .arg(&log)
        .arg(&file)
        .timeout(std::time::Duration::from_secs(180))
        .output()
        .expect("run");
    let (stdout, err) = (String::from_utf8_lossy(&out.stdout), stderr(&out));
    assert!(out.status.code().is_some(), "{err}");
    let event_time = |needle: &str| -> f64 {
        let line = stdout
            .lines()
            .find(|l| l.contains("event") && l.contains(needle))
            .unwrap_or_else(|| panic!("no event {needle:?} in:\n{stdout}"));
        line.split_whitespace()
            .nth(1)
            .and_then(|t| t.parse().ok())
            .unwrap_or_else(|| panic!("no time in {line:?}"))
    };
    let link_lost_s = event_time("a: link lost");
    let lost_s = event_time("a: LOST: nothing heard for 5 s (link.lost_after_s)");
    // Silent for 2 s, then for 5 s: 3 s apart, give or take a tick and a message.
    assert!(
        (lost_s - link_lost_s - 3.0).abs() < 0.6,
        "link lost at {link_lost_s} s, LOST at {lost_s} s"
    );
    // Said once, on the line that counts the drones unaccounted for; a drone lost
    // in the air is never a success.
    assert!(
        stdout.contains("  unaccounted for      1 drone: LOST a (last position ("),
        "{stdout}"
    );
    assert_eq!(stdout.matches("LOST a").count(), 1, "{stdout}");
    assert_eq!(out.status.code(), Some(1), "{stdout}\n{err}");
    // Status lines after the loss say LOST, never LINK LOST again.
    let after: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("t=") && l.contains("LOST"))
        .skip_while(|l| !l.contains("1 LOST"))
        .collect();
    assert!(!after.is_empty(), "no status line says LOST:\n{err}");
    assert!(after.iter().all(|l| !l.contains("LINK LOST")), "{err}");
}

/// Issue 29, item 5: b1 is lost for good 8 s after takeoff, the survivors are
/// replanned without it and complete and land; that is no success while b1 is
/// armed in the air somewhere. The exit code says so, and the summary says once how
/// many drones are unaccounted for.
#[test]
fn a_lost_drone_fails_the_flight_even_when_the_survivors_complete() {
    let dir = tempfile::tempdir().expect("temp dir");
    let log = dir.path().join("flight.json");
    let out = swarmctl()
        .args(["fly", "--plain", "--fault", "lose=b1@8s", "--log"])
        .arg(&log)
        .arg("missions/formation-change.yaml")
        .timeout(std::time::Duration::from_secs(240))
        .output()
        .expect("run");
    let (stdout, err) = (String::from_utf8_lossy(&out.stdout), stderr(&out));
    assert!(
        stdout.contains("  replanned            at "),
        "the survivors were replanned:\n{stdout}\n{err}"
    );
    assert!(
        stdout.contains("  completed            survivors only: not every drone landed"),
        "{stdout}"
    );
    assert!(
        stdout.contains("  unaccounted for      1 drone: LOST b1 (last position ("),
        "{stdout}"
    );
    assert_eq!(stdout.matches("LOST b1").count(), 1, "{stdout}");
    assert_eq!(stdout.matches("unaccounted for").count(), 1, "{stdout}");
    assert_eq!(out.status.code(), Some(1), "{stdout}\n{err}");
    // The log keeps both: the survivors completed, b1 is unaccounted for.
    let text = std::fs::read_to_string(&log).expect("flight log");
    let log: swarmctl::fly::FlightLog = serde_json::from_str(&text).expect("log parses");
    assert!(log.summary.completed);
    assert!(!log.summary.succeeded());
    let ids: Vec<&str> = log
        .summary
        .unaccounted
        .iter()
        .map(|u| u.id.as_str())
        .collect();
    assert_eq!(ids, ["b1"]);
}

/// Item 1, the key `fly` would load: a signing key file that is missing is
/// `check`'s to report, as `fly` would.
#[test]
fn check_reports_a_signing_key_fly_could_not_load() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = mission("safety_distance_m: 0.3", "", "")
        + "link: { signing: { key_file: no-such.key } }\n";
    let file = write(dir.path(), "signed.yaml", &text);
    let log = dir.path().join("flights").join("f.json");
    let log = log.to_str().expect("utf-8 path");
    for command in [&["check"][..], &["fly", "--plain", "--log", log]] {
        let out = run(command, &file);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{command:?}: {err}");
        assert!(
            err.contains("signing key file") && err.contains("no-such.key"),
            "{command:?}: {err}"
        );
    }
    assert!(!dir.path().join("flights").join("f.rrd").exists());
}

/// `fly --dry-run` on the bundled simulator: every drone ready, the link budget
/// printed, exit 0, and no flight log or recording written (nothing flew).
#[test]
fn a_dry_run_reports_every_drone_ready_and_flies_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let log = dir.path().join("flight.json");
    let out = swarmctl()
        .args([
            "fly",
            "missions/formation-change.yaml",
            "--dry-run",
            "--log",
        ])
        .arg(&log)
        .output()
        .expect("run");
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}{}", stderr(&out));
    for id in ["b1", "b2", "b3", "b4", "r1", "r2", "r3", "r4"] {
        assert!(
            text.lines()
                .any(|l| l.trim_start().starts_with(id) && l.contains("ready      px4")),
            "{id} not reported ready:\n{text}"
        );
    }
    assert!(text.contains("per drone at 20 Hz"), "{text}");
    assert!(
        text.contains("the swarm would fly (8 of 8 ready)"),
        "{text}"
    );
    let left: Vec<_> = std::fs::read_dir(dir.path()).expect("dir").collect();
    assert!(left.is_empty(), "a dry run wrote {left:?}");
}

/// A vehicle failing its pre-arm checks makes the dry run exit 1 naming it with
/// the autopilot's reason, while the others are reported ready.
#[test]
fn a_dry_run_names_the_vehicle_that_would_not_fly() {
    let out = swarmctl()
        .args([
            "fly",
            "missions/formation-change.yaml",
            "--dry-run",
            "--fault",
            "refuse-arm=r2",
        ])
        .output()
        .expect("run");
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}{}", stderr(&out));
    assert!(
        text.lines().any(|l| l.contains("r2")
            && l.contains("NOT READY")
            && l.contains("pre-arm checks fail")),
        "{text}"
    );
    assert!(text.contains("1 of 8 not ready (r2)"), "{text}");
}
