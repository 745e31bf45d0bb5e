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
