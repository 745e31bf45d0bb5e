//! Two groups of four change formation through a wall: both autopilot flavours,
//! a drone flying at half speed, and 10 % packet loss. Every flight must finish
//! with every drone at its goal and the safety distance kept in telemetry.

use crate::fly_common::*;
use std::time::Duration;
use swarmctl_sitl::Flavour;

const LIMIT: Duration = Duration::from_secs(90);

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn formation_change_px4() {
    let (mission, plan) = load("missions/formation-change.yaml");
    let log = fly_bundled(&mission, &plan, Flavour::Px4, &[], LIMIT)
        .await
        .expect("flight");
    assert_success(&log);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn formation_change_ardupilot() {
    let (mission, plan) = load("missions/formation-change.yaml");
    let log = fly_bundled(&mission, &plan, Flavour::ArduPilot, &[], LIMIT)
        .await
        .expect("flight");
    assert_success(&log);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn formation_change_with_a_half_speed_drone() {
    let (mission, plan) = load("missions/formation-change.yaml");
    let log = fly_bundled(&mission, &plan, Flavour::Px4, &["slow=b1:0.5"], LIMIT)
        .await
        .expect("flight");
    assert_success(&log);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn formation_change_with_ten_percent_loss() {
    let (mission, plan) = load("missions/formation-change.yaml");
    let log = fly_bundled(&mission, &plan, Flavour::ArduPilot, &["loss=10%"], LIMIT)
        .await
        .expect("flight");
    assert_success(&log);
}
