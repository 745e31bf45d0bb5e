//! Ten vehicles in one process, each armed and flown by its own rust-mavlink
//! client over real UDP on loopback.
// Tests may unwrap, expect and run long: a failure is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::too_many_lines)]

mod common;

use common::*;
use mavlink::dialects::common::{MavCmd, MavResult};
use std::time::Duration;
use swarmctl_sitl::{Flavour, FlightMode, VehicleConfig, spawn};
use tokio::time::{Instant, sleep};

/// Flies vehicle `index` to its goal: PX4 via OFFBOARD, ArduPilot via GUIDED.
async fn fly(client: Client, flavour: Flavour, goal: [f32; 3], end: Instant) {
    match flavour {
        Flavour::Px4 => {
            assert_eq!(client.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
            // Stream setpoints first: PX4 refuses OFFBOARD without a > 2 Hz stream.
            for _ in 0..8 {
                client.position_target(goal).await;
                sleep(Duration::from_millis(50)).await;
            }
            assert_eq!(
                client.set_mode(6.0, 0.0).await,
                Some(MavResult::MAV_RESULT_ACCEPTED)
            );
        }
        Flavour::ArduPilot => {
            assert_eq!(
                client.set_mode(4.0, 0.0).await,
                Some(MavResult::MAV_RESULT_ACCEPTED)
            );
            assert_eq!(client.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
            let takeoff = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -goal[2]];
            assert_eq!(
                client.command(MavCmd::MAV_CMD_NAV_TAKEOFF, takeoff).await,
                Some(MavResult::MAV_RESULT_ACCEPTED)
            );
            sleep(Duration::from_secs(3)).await;
        }
    }
    // Keep streaming until the common end (PX4 needs it; ArduPilot accepts it),
    // so all vehicles are checked while their setpoint streams are still live.
    while Instant::now() < end {
        client.position_target(goal).await;
        sleep(Duration::from_millis(100)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn ten_vehicles_on_their_own_ports_are_armed_and_moved() {
    let configs: Vec<VehicleConfig> = (1..=10u8)
        .map(|id| {
            let flavour = if id % 2 == 0 {
                Flavour::ArduPilot
            } else {
                Flavour::Px4
            };
            let mut c = VehicleConfig::new(id, flavour);
            c.initial_position_ned_m = [0.0, 2.0 * f32::from(id), 0.0];
            c
        })
        .collect();
    let swarm = spawn(LOOPBACK, configs.clone(), 100.0, 20.0)
        .await
        .expect("spawn");
    let addresses = swarm.addresses();
    assert_eq!(addresses.len(), 10);
    let mut ports: Vec<u16> = addresses.iter().map(|a| a.port()).collect();
    ports.dedup();
    assert_eq!(ports.len(), 10, "each vehicle has its own port");

    let mut flights = Vec::new();
    let mut goals = Vec::new();
    let end = Instant::now() + Duration::from_secs(14);
    for (config, address) in configs.iter().zip(&addresses) {
        let goal = [3.0, config.initial_position_ned_m[1] + 1.0, -2.0];
        goals.push(goal);
        let client = Client::connect(*address, config.system_id).await;
        flights.push(tokio::spawn(fly(client, config.flavour, goal, end)));
    }
    for flight in flights {
        tokio::time::timeout(Duration::from_secs(30), flight)
            .await
            .expect("flight finished in time")
            .expect("flight task");
    }
    for (i, goal) in goals.iter().enumerate() {
        let s = swarm.snapshot(i);
        assert!(s.armed, "vehicle {} armed", s.system_id);
        assert!(
            distance(s.position_ned_m, *goal) < 0.3,
            "vehicle {} at {:?}, goal {goal:?}",
            s.system_id,
            s.position_ned_m
        );
        let expected_mode = if s.flavour == Flavour::Px4 {
            FlightMode::Offboard
        } else {
            FlightMode::Guided
        };
        assert_eq!(s.mode, expected_mode);
    }
    let ticks = swarm.tick_stats();
    assert!(ticks.steps > 1000, "{ticks:?}");
    swarm.shutdown().await;
}

#[tokio::test]
async fn commands_via_rust_mavlink_get_px4_answers() {
    let swarm = spawn(
        LOOPBACK,
        vec![VehicleConfig::new(7, Flavour::Px4)],
        100.0,
        20.0,
    )
    .await
    .expect("spawn");
    let client = Client::connect(swarm.addresses()[0], 7).await;
    // AUTOPILOT_VERSION on request, after its ACK.
    assert_eq!(
        client
            .command(
                MavCmd::MAV_CMD_REQUEST_MESSAGE,
                [148.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
            )
            .await,
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    let version = client
        .recv_until(Duration::from_secs(1), |_, m| match m {
            mavlink::dialects::common::MavMessage::AUTOPILOT_VERSION(v) => {
                Some(v.flight_sw_version)
            }
            _ => None,
        })
        .await;
    assert!(version.is_some());
    // Takeoff to MIS_TAKEOFF_ALT, seen in telemetry.
    assert_eq!(client.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
    assert_eq!(
        client.command(MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7).await,
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    let climbed = client
        .recv_until(Duration::from_secs(8), |_, m| match m {
            mavlink::dialects::common::MavMessage::LOCAL_POSITION_NED(p) if p.z < -2.3 => Some(p.z),
            _ => None,
        })
        .await;
    assert!(climbed.is_some(), "reached ~2.5 m");
    swarm.shutdown().await;
}
