//! Two drones swap ends of a corridor (one ducks into a side pocket), flown end to
//! end over MAVLink against the bundled PX4-flavoured SITL.

use crate::fly_common::*;
use std::time::Duration;
use swarmctl_sitl::Flavour;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_drones_swap_the_corridor_px4() {
    let (mission, plan) = load("missions/swap-corridor.yaml");
    let log = fly_bundled(&mission, &plan, Flavour::Px4, &[], Duration::from_secs(60))
        .await
        .expect("flight");
    assert_success(&log);
}
