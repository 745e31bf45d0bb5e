//! A vehicle that fails its pre-arm checks stops the flight before anybody arms
//! (after waiting the readiness deadline for it to pass), and the error names it
//! with the autopilot's own reason; bad fault flags are rejected with the flag named.

use crate::fly_common::*;
use std::time::Duration;
use swarmctl::fly::{self, FlyError};
use swarmctl_sitl::Flavour;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn refused_arming_aborts_with_nobody_airborne() {
    let (mission, plan) = load("missions/formation-change.yaml");
    // fly_bundled asserts that no vehicle is left armed.
    let result = fly_bundled(
        &mission,
        &plan,
        Flavour::Px4,
        &["refuse-arm=r2"],
        Duration::from_secs(30),
    )
    .await;
    match result {
        Err(FlyError::Preflight(lines)) => {
            assert!(lines.iter().any(|l| l.contains("r2")), "{lines:?}");
            assert_eq!(lines.len(), 1, "only r2 fails: {lines:?}");
            // The autopilot's own reason, asked for with MAV_CMD_RUN_PREARM_CHECKS.
            assert!(
                lines[0].contains(
                    "pre-arm checks fail (SYS_STATUS): Preflight Fail: simulated check failure"
                ),
                "{lines:?}"
            );
        }
        other => panic!(
            "expected a pre-flight failure, got {:?}",
            other.map(|l| l.summary)
        ),
    }
}

#[test]
fn unknown_drone_in_a_fault_is_an_error_naming_it() {
    let (mission, plan) = load("missions/swap-corridor.yaml");
    let fault = swarmctl_sitl::parse_fault("slow=zz:0.5").expect("well-formed");
    let e = swarmctl_bundled::vehicle_configs(&mission, &plan, Flavour::Px4, &[fault]).unwrap_err();
    assert!(e.to_string().contains("\"zz\""), "{e}");
}

/// Starts `configs` and runs pre-flight with `frames`; every vehicle stays disarmed.
async fn preflight_only(
    mission: &swarmctl::mission::Mission,
    plan: &swarmctl::plan::DiscretePlan,
    configs: Vec<swarmctl_sitl::VehicleConfig>,
    frames: fly::FrameSource,
) -> Result<swarmctl::fly::FlightLog, FlyError> {
    let (swarm, links) = swarmctl_bundled::start(configs, mission.link.setpoint_rate_hz)
        .await
        .expect("sitl");
    let mut options = swarmctl_bundled::fly_options(links);
    options.frames = frames;
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let result = tokio::time::timeout(
        Duration::from_secs(60),
        fly::fly(mission, plan, &options, abort_rx),
    )
    .await
    .expect("flight finished within its time limit");
    for i in 0..plan.drones.len() {
        assert!(!swarm.snapshot(i).armed, "vehicle {i} armed");
    }
    swarm.shutdown().await;
    result
}

/// Two vehicles swapped between their pads (the classic field mistake): each
/// vehicle's GPS origin, read against the mission's `world.geo_origin`, puts it on
/// the other's pad, so pre-flight refuses both, naming where each is and where its
/// pad is — before anybody arms.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn vehicles_on_the_wrong_pads_are_refused_with_both_positions() {
    let (mission, plan) = load("missions/formation-change.yaml");
    assert!(
        mission.geo_origin.is_some(),
        "the mission gives a geo origin"
    );
    let mut configs =
        swarmctl_bundled::vehicle_configs(&mission, &plan, Flavour::Px4, &[]).expect("configs");
    let (b1, b2) = (configs[0].clone(), configs[1].clone());
    assert_eq!(
        (plan.drones[0].id.as_str(), plan.drones[1].id.as_str()),
        ("b1", "b2")
    );
    for (i, stand) in [(0, &b2), (1, &b1)] {
        let c = &mut configs[i];
        c.initial_position_ned_m = stand.initial_position_ned_m;
        c.local_origin_ned_m = stand.local_origin_ned_m;
        c.home = stand.home;
    }
    match preflight_only(&mission, &plan, configs, fly::FrameSource::PerVehicle).await {
        Err(FlyError::Preflight(lines)) => {
            assert_eq!(lines.len(), 2, "b1 and b2 only: {lines:?}");
            let b1 = lines.iter().find(|l| l.contains("b1:")).expect("b1 named");
            assert!(
                b1.contains(
                    "its GPS puts it at ENU (0.00, 2.00) m, 1.00 m from its pad at (0.00, 1.00) m"
                ),
                "{b1}"
            );
            assert!(
                lines
                    .iter()
                    .any(|l| l.contains("b2:") && l.contains("wrong pad"))
            );
        }
        other => panic!("expected a refusal, got {:?}", other.map(|l| l.summary)),
    }
}

/// Real autopilots start their local frame where they stand; read as if all shared
/// the mission's frame (`--shared-frame`), every vehicle but the one at the origin's
/// column seems to be off its pad — the refusal a real swarm met before swarmctl
/// learned each vehicle's frame.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn own_frames_read_as_shared_are_refused() {
    let (mission, plan) = load("missions/swap-corridor.yaml");
    let configs =
        swarmctl_bundled::vehicle_configs(&mission, &plan, Flavour::Px4, &[]).expect("configs");
    match preflight_only(&mission, &plan, configs, fly::FrameSource::Shared).await {
        Err(FlyError::Preflight(lines)) => {
            assert!(
                lines
                    .iter()
                    .all(|l| l.contains("reports itself at ENU (0.00, 0.00) m")),
                "{lines:?}"
            );
        }
        other => panic!("expected a refusal, got {:?}", other.map(|l| l.summary)),
    }
}
