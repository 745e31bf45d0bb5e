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
    let fault = fly::parse_fault("slow=zz:0.5").expect("well-formed");
    let e =
        swarmctl_harness::bundled_sitl::vehicle_configs(&mission, &plan, Flavour::Px4, &[fault])
            .unwrap_err();
    assert!(e.to_string().contains("\"zz\""), "{e}");
}
