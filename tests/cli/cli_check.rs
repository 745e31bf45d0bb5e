//! `swarmctl check`, `gen` and `template` as a user runs them.

use assert_cmd::Command;
use predicates::str::contains;

fn swarmctl() -> Command {
    Command::cargo_bin("swarmctl").expect("binary built")
}

#[test]
fn every_example_mission_passes_check() {
    let missions = crate::support::repo_root().join("missions");
    let mut count = 0;
    for entry in std::fs::read_dir(&missions).expect("missions/ exists") {
        let path = entry.expect("readable entry").path();
        if path.extension().is_some_and(|e| e == "yaml") {
            swarmctl()
                .arg("check")
                .arg(&path)
                .assert()
                .success()
                .stdout(contains("valid mission"))
                .stdout(contains("formation  ≥"));
            count += 1;
        }
    }
    assert!(
        count >= 4,
        "expected the four example missions, found {count}"
    );
}

#[test]
fn generated_paper_scale_missions_pass_check_for_seeds_1_to_20() {
    let dir = tempfile::tempdir().expect("temp dir");
    for seed in 1..=20 {
        let file = dir.path().join(format!("gen-{seed}.yaml"));
        swarmctl()
            .args([
                "gen",
                "--size",
                "10x10x5",
                "--obstacles",
                "150",
                "--drones",
                "100",
            ])
            .args(["--groups", "5", "--seed", &seed.to_string(), "-o"])
            .arg(&file)
            .assert()
            .success();
        swarmctl()
            .arg("check")
            .arg(&file)
            .assert()
            .success()
            .stdout(contains("350 free"))
            .stdout(contains("drones     100"));
    }
}

#[test]
fn gen_is_deterministic_for_a_seed() {
    let run = |seed: &str| {
        swarmctl()
            .args(["gen", "--drones", "30", "--groups", "3", "--seed", seed])
            .output()
            .expect("runs")
            .stdout
    };
    assert_eq!(run("7"), run("7"));
    assert_ne!(run("7"), run("8"));
}

#[test]
fn gen_rejects_impossible_requests() {
    swarmctl()
        .args([
            "gen",
            "--size",
            "2x2x2",
            "--obstacles",
            "5",
            "--drones",
            "4",
            "--groups",
            "2",
        ])
        .assert()
        .failure()
        .stderr(contains("do not fit"));
    swarmctl()
        .args(["gen", "--size", "10x0x5"])
        .assert()
        .failure()
        .stderr(contains("three positive integers"));
}

#[test]
fn check_fails_with_file_path_and_reason() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("bad.yaml");
    let template = swarmctl().arg("template").output().expect("runs").stdout;
    let text = String::from_utf8(template).expect("utf-8");
    std::fs::write(&file, text.replace("start: [0, 1, 0]", "start: [0, 9, 0]")).expect("write");
    swarmctl()
        .arg("check")
        .arg(&file)
        .assert()
        .failure()
        .stderr(contains("bad.yaml"))
        .stderr(contains(
            "groups[0].drones[1].start: [0, 9, 0] is outside the world",
        ));
}

#[test]
fn template_is_valid_and_commented() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("t.yaml");
    swarmctl()
        .args(["template", "-o"])
        .arg(&file)
        .assert()
        .success();
    let text = std::fs::read_to_string(&file).expect("written");
    assert!(text.lines().filter(|l| l.contains('#')).count() > 20);
    swarmctl().arg("check").arg(&file).assert().success();
}

/// The formation-change mission with its eight drones on the radios given.
fn formation_change_on(radios: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let text =
        std::fs::read_to_string(crate::support::repo_root().join("missions/formation-change.yaml"))
            .expect("mission");
    let text = text.replacen(
        "  setpoint_rate_hz: 20\n",
        &format!("  setpoint_rate_hz: 20\n  radios:\n{radios}"),
        1,
    );
    assert!(text.contains("radios:"), "the mission's link section moved");
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("radios.yaml");
    std::fs::write(&path, text).expect("write mission");
    (dir, path)
}

#[test]
fn check_prints_the_link_budget_per_drone_and_per_radio() {
    let (_dir, path) = formation_change_on(
        "    - { name: west, drones: [b1, b2, b3], capacity_kbps: 64 }\n    - { name: east, drones: [r1, r2, r3], capacity_kbps: 64 }\n",
    );
    swarmctl()
        .arg("check")
        .arg(&path)
        .assert()
        .success()
        // 65 B setpoints × 20 Hz + a 21 B heartbeat = 10.6 kbit/s up.
        .stdout(contains(
            "per drone 10.6 kbit/s up + 7.6 kbit/s down = 18.1 kbit/s",
        ))
        .stdout(contains("SET_POSITION_TARGET_LOCAL_NED 65 B × 20 Hz"))
        .stdout(contains("west: 3 drones, 54.4 of 57.6 kbit/s usable"))
        .stdout(contains("own links  2 drones on no radio"));
}

/// The formation change's airspace is x −0.5…7.5 m, y −0.5…5.5 m, up to 4 m (its
/// top layer's centre 3.5 m): from a pad at y 1 or 4 (x 0 or 7) the farthest corner
/// is 7.5 m across and 4.5 m along, a circle of √(7.5² + 4.5²) + 2 = 10.7 m; from
/// y 2 or 3 it is 3.5 m along, √(7.5² + 3.5²) + 2 = 10.3 m. Each ceiling is
/// 4 + 2 = 6 m.
#[test]
fn check_prints_the_fence_each_autopilot_gets_and_refuses_a_bad_margin() {
    let mission = crate::support::repo_path("missions/formation-change.yaml");
    swarmctl()
        .arg("check")
        .arg(&mission)
        .assert()
        .success()
        .stdout(contains(
            "fence      airspace + 2.0 m: 10.3–10.7 m around each pad, 6.0 m above it; on a breach the autopilot does: land",
        ));
    let text = std::fs::read_to_string(&mission).expect("mission");
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("fence.yaml");
    std::fs::write(
        &path,
        format!("{text}\nfence: {{ margin_m: 0.1, action: report }}\n"),
    )
    .expect("write");
    swarmctl()
        .arg("check")
        .arg(&path)
        .assert()
        .failure()
        .stderr(contains("fence.yaml"))
        .stderr(contains("fence.margin_m: must be 0.5 to 100 m"));
    std::fs::write(&path, format!("{text}\nfence: {{ enabled: false }}\n")).expect("write");
    swarmctl()
        .arg("check")
        .arg(&path)
        .assert()
        .success()
        .stdout(contains("fence      off (fence.enabled: false)"));
}

#[test]
fn an_over_full_radio_is_refused_with_the_numbers_and_the_fixes() {
    let (_dir, path) = formation_change_on(
        "    - { name: r1, drones: [b1, b2, b3, b4, r1, r2, r3, r4], capacity_kbps: 64 }\n",
    );
    swarmctl()
        .arg("check")
        .arg(&path)
        .assert()
        .failure()
        .stderr(contains(
            "radio r1: 8 drones × 18.1 kbit/s = 145.1 kbit/s > 57.6 kbit/s usable (90 % of 64 kbit/s): lower link.setpoint_rate_hz to 6, or split r1 into 3 radios of at most 3 drones",
        ));
}

#[test]
fn radios_naming_unknown_or_shared_drones_are_invalid() {
    let (_dir, path) = formation_change_on(
        "    - { name: a, drones: [b1, b2], capacity_kbps: 64 }\n    - { name: a, drones: [b2, x9], capacity_kbps: 0 }\n",
    );
    swarmctl()
        .arg("check")
        .arg(&path)
        .assert()
        .failure()
        .stderr(contains(
            "link.radios[1].name: radio \"a\" is already link.radios[0]",
        ))
        .stderr(contains(
            "link.radios[1].capacity_kbps: must be a positive number",
        ))
        .stderr(contains(
            "link.radios[1].drones[0]: drone b2 is already on radio a",
        ))
        .stderr(contains("link.radios[1].drones[1]: no drone \"x9\""));
}
