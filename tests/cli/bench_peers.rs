//! `swarmctl bench peers` as a user runs it before building any peer: swarmctl
//! alone on seeded MovingAI instances, the table, the files it leaves, and a
//! peer binary that is not there. (The peers themselves are built by users from
//! their own repositories, never by this project, so CI has none; their result
//! files are read by the adapters' unit tests from real samples.)

use assert_cmd::Command;
use predicates::str::contains;

fn swarmctl() -> Command {
    Command::cargo_bin("swarmctl").expect("binary built")
}

fn map() -> std::path::PathBuf {
    crate::support::repo_root().join("tests/data/movingai/random-32-32-10.map")
}

#[test]
fn swarmctl_alone_answers_every_instance_in_the_table() {
    let dir = tempfile::tempdir().expect("temp dir");
    let output = swarmctl()
        .args(["bench", "peers", "--map"])
        .arg(map())
        .args([
            "--agents",
            "12,20",
            "--seeds",
            "2",
            "--limit",
            "30",
            "--work-dir",
        ])
        .arg(dir.path())
        .timeout(std::time::Duration::from_secs(300))
        .assert()
        .success()
        .stderr(contains("no peer given"))
        .get_output()
        .stdout
        .clone();
    let table = String::from_utf8(output).expect("utf-8");
    for agents in [12, 20] {
        for problem in ["per-agent", "one-group"] {
            let row = format!("| random-32-32-10.map | {agents} | {problem} | swarmctl | 2/2");
            assert!(table.contains(&row), "no row {row:?} in\n{table}");
        }
        for seed in [1, 2] {
            let scen = dir
                .path()
                .join(format!("random-32-32-10-{agents}-{seed}.scen"));
            let rows = swarmctl::import::parse_scen(
                &std::fs::read_to_string(&scen).expect("scenario written"),
                &scen,
            )
            .expect("a MovingAI scenario");
            assert_eq!(rows.len(), agents);
        }
    }
    assert_eq!(table.lines().count(), 2 + 4, "{table}");
}

#[test]
fn a_peer_binary_that_is_not_there_is_named() {
    let dir = tempfile::tempdir().expect("temp dir");
    swarmctl()
        .args([
            "bench",
            "peers",
            "--problem",
            "per-agent",
            "--agents",
            "5",
            "--map",
        ])
        .arg(map())
        .args(["--lacam3", "/no/such/lacam3", "--limit", "20", "--work-dir"])
        .arg(dir.path())
        .timeout(std::time::Duration::from_secs(120))
        .assert()
        .failure()
        .stderr(contains("/no/such/lacam3"));
}
