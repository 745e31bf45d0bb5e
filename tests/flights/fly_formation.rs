//! Two groups of four change formation through a wall: both autopilot flavours,
//! a drone flying at half speed, and 10 % packet loss. Every flight must finish
//! with every drone at its goal and the safety distance kept in telemetry.

use crate::fly_common::*;
use std::time::Duration;
use swarmctl_sitl::Flavour;

/// Bounds each flight, not a speed goal (speed is benchmarked): the plan takes 60.7 s
/// to its last arrival since its pillar stands on the ground (issue 29), and with 10 %
/// loss on ArduPilot the flight took 87 s alone, past 90 s with the other tests.
const LIMIT: Duration = Duration::from_secs(150);

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn formation_change_px4() {
    let (mission, plan) = load("missions/formation-change.yaml");
    let log = fly_bundled(&mission, &plan, Flavour::Px4, &[], LIMIT)
        .await
        .expect("flight");
    assert_success(&log);
    assert_traffic_within_budget(&log);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn formation_change_ardupilot() {
    let (mission, plan) = load("missions/formation-change.yaml");
    let log = fly_bundled(&mission, &plan, Flavour::ArduPilot, &[], LIMIT)
        .await
        .expect("flight");
    assert_success(&log);
    assert_traffic_within_budget(&log);
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

/// A small show pad to pad: launch pads beside the stage, three formations after
/// the first with holds, landing on the group's pads; the separation holds from the
/// first arm to the last touchdown.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn small_show_pad_to_pad() {
    let (mission, plan) = load("missions/small-show.yaml");
    assert_eq!(plan.legs.len(), 5);
    let log = fly_bundled(&mission, &plan, Flavour::Px4, &[], Duration::from_secs(150))
        .await
        .expect("flight");
    assert_success(&log);
    // Every drone ends on a pad of its group, where it is told to land.
    for (d, (g, _)) in log.drones.iter().zip(mission.drones()) {
        let pads: Vec<[f64; 3]> = g.drones.iter().map(|p| mission.pad_ground_m(p)).collect();
        let last = d.samples.last().expect("samples");
        let off_m = pads
            .iter()
            .map(|p| ((last[1] - p[0]).powi(2) + (last[2] - p[1]).powi(2)).sqrt())
            .fold(f64::INFINITY, f64::min);
        assert!(
            off_m < 0.2 && last[3] < 0.1,
            "{} ended {off_m:.2} m from a pad",
            d.id
        );
    }
}

/// The two missions of issue 29 that crashed or were refused after planning (stage
/// holds with spares that hold above their pads, one never moving at all) fly pad
/// to pad and complete: the holds are kept and every drone lands.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn stage_holds_with_spares_above_their_pads_fly() {
    for path in [
        "tests/data/missions/repro-panic.yaml",
        "tests/data/missions/repro-rotation.yaml",
    ] {
        let (mission, plan) = load(path);
        let log = fly_bundled(&mission, &plan, Flavour::Px4, &[], Duration::from_secs(150))
            .await
            .expect("flight");
        assert_success(&log);
        assert!(
            log.summary.succeeded(),
            "{path}: {:?}",
            log.summary.unaccounted
        );
    }
}
