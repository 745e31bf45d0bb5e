//! Real peers: MAVSDK flies a PX4-flavoured vehicle and pymavlink decodes the
//! telemetry. Both run as Python scripts from the repository's `.venv`
//! (created by `bash .ci/install-peers`); a missing venv is a failure, not a skip.
// Tests may unwrap, expect and run long: a failure is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::too_many_lines)]

mod common;

use common::LOOPBACK;
use std::path::{Path, PathBuf};
use std::time::Duration;
use swarmctl_sitl::{Flavour, VehicleConfig, spawn};

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn python() -> PathBuf {
    let python = repo_root().join(".venv/bin/python");
    assert!(
        python.exists(),
        "{} is missing: run `bash .ci/install-peers` first",
        python.display()
    );
    python
}

/// Starts one PX4-flavoured vehicle on an ephemeral port and runs `script PORT`.
async fn run_peer(script: &str, limit: Duration) {
    let python = python();
    let swarm = spawn(
        LOOPBACK,
        vec![VehicleConfig::new(1, Flavour::Px4)],
        100.0,
        20.0,
    )
    .await
    .expect("spawn");
    let port = swarm.addresses()[0].port();
    let script_path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/peers")
        .join(script);
    let child = tokio::process::Command::new(&python)
        .arg(&script_path)
        .arg(port.to_string())
        .kill_on_drop(true)
        .output();
    let output = tokio::time::timeout(limit, child)
        .await
        .unwrap_or_else(|_| panic!("{script} did not finish within {limit:?}"))
        .expect("run python");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    println!("{script} stdout:\n{stdout}\n{script} stderr:\n{stderr}");
    assert!(
        output.status.success(),
        "{script} failed ({}):\n{stdout}\n{stderr}",
        output.status
    );
    swarm.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn mavsdk_flies_a_square_in_offboard() {
    run_peer("mavsdk_flight.py", Duration::from_secs(120)).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pymavlink_decodes_all_telemetry() {
    run_peer("pymavlink_decode.py", Duration::from_secs(60)).await;
}
