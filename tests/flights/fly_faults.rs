//! Link faults on the formation change (PX4): a drone whose link is cut mid-flight
//! and comes back, and 50 ms latency each way. Both flights must finish with every
//! drone at its goal and the safety distance kept in telemetry.

use crate::fly_common::*;
use std::time::Duration;
use swarmctl_sitl::Flavour;

const LIMIT: Duration = Duration::from_secs(90);

/// b1's link is cut 5 s after takeoff for 3 s. PX4 leaves OFFBOARD after 1 s
/// without setpoints and holds; the executor pauses b1 (telemetry stale), the
/// drones that depend on b1 wait at their gates, and once the link is back b1
/// re-enters OFFBOARD and the flight completes. The heartbeat timeout is set to
/// 2 s here (the mission says 3 s) so a 3 s cut is always reported as a link
/// loss: with 1 Hz heartbeats a 3 s cut leaves a 3–4 s gap, which a 3 s timeout
/// catches only most of the time.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn link_cut_mid_flight_recovers_and_completes() {
    let (mut mission, plan) = load("missions/formation-change.yaml");
    mission.link.link_timeout_s = 2.0;
    let log = fly_bundled(&mission, &plan, Flavour::Px4, &["drop=b1@5s+3s"], LIMIT)
        .await
        .expect("flight");
    for e in &log.events {
        eprintln!("{:6.1} s {:?} {}", e.t_s, e.drone, e.message);
    }
    assert_success(&log);
    let b1 = log.drones.iter().find(|d| d.id == "b1").expect("b1 logged");
    assert_eq!(b1.link_losses, 1, "b1's cut is counted once");
    let reported = |text: &str| {
        log.events
            .iter()
            .any(|e| e.drone.as_deref() == Some("b1") && e.message.contains(text))
    };
    assert!(
        reported("link lost"),
        "link loss in the log: {:?}",
        log.events
    );
    assert!(
        reported("link back"),
        "link recovery in the log: {:?}",
        log.events
    );
    assert!(
        log.summary.gating_waits > 0,
        "somebody waited at a gate while b1 was out"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn fifty_ms_latency_each_way_completes() {
    let (mission, plan) = load("missions/formation-change.yaml");
    let log = fly_bundled(&mission, &plan, Flavour::Px4, &["latency=50ms"], LIMIT)
        .await
        .expect("flight");
    assert_success(&log);
}
