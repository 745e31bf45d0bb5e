//! The paper's scale flown end to end: `missions/paper-scale.yaml`, 100 drones in
//! 5 groups, on 100 bundled PX4 SITL vehicles in this process.
//!
//! Ignored by default (`cargo test --test fly_paper_scale -- --ignored`): the
//! flight takes some 35 s of wall time with 100 simulated vehicles sharing the
//! machine, too heavy next to the other tests in CI. `benches/fly_stream.rs`
//! flies the same mission and measures the setpoint stream.
//!
//! Starts and goals in this mission are stacked in columns; every drone still has a
//! pad of its own, and takeoff and landing are planned legs, so the separation
//! measured from telemetry over the whole flight, pad to pad, must hold.

use crate::fly_common::*;
use std::time::Duration;
use swarmctl_sitl::Flavour;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
#[ignore = "100 simulated vehicles, ~50 s: run with --ignored"]
async fn paper_scale_hundred_drones_px4() {
    let (mission, plan) = load("missions/paper-scale.yaml");
    assert_eq!(plan.drones.len(), 100);
    let log = fly_bundled(&mission, &plan, Flavour::Px4, &[], Duration::from_secs(180))
        .await
        .expect("flight");
    assert_success(&log);
}

/// The same mission with downwash-aware separation
/// (`missions/paper-scale-downwash.yaml`: 0.25 m across, 0.75 m above and
/// below): the scaled separation from telemetry stays at 1 or more, pad to pad.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
#[ignore = "100 simulated vehicles, ~80 s: run with --ignored"]
async fn paper_scale_downwash_keeps_the_ellipsoid() {
    let (mission, plan) = load("missions/paper-scale-downwash.yaml");
    let log = fly_bundled(&mission, &plan, Flavour::Px4, &[], Duration::from_secs(240))
        .await
        .expect("flight");
    assert_success(&log);
    let scaled = log
        .summary
        .min_scaled_separation
        .expect("scaled separation");
    assert!(scaled >= 1.0, "scaled separation {scaled}");
}
