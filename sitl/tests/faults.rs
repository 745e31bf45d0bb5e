//! Every fault knob, measured on the wire (rust-mavlink client over UDP) or
//! through the vehicle's true state.

mod common;

use common::*;
use mavlink::dialects::common::{
    MavBatteryChargeState, MavCmd, MavMessage, MavResult, TIMESYNC_DATA,
};
use std::time::Duration;
use swarmctl_sitl::{Faults, Flavour, FlightMode, LinkDrop, VehicleConfig, spawn};
use tokio::time::{Instant, sleep};

fn px4_with(faults: Faults) -> Vec<VehicleConfig> {
    let mut config = VehicleConfig::new(1, Flavour::Px4);
    config.faults = faults;
    vec![config]
}

fn count_local_positions(messages: &[(Instant, mavlink::MavHeader, MavMessage)]) -> usize {
    messages
        .iter()
        .filter(|(_, _, m)| matches!(m, MavMessage::LOCAL_POSITION_NED(_)))
        .count()
}

#[tokio::test]
async fn loss_drops_the_configured_share_of_packets() {
    let swarm = spawn(
        LOOPBACK,
        px4_with(Faults {
            loss_percent: 40.0,
            ..Faults::default()
        }),
        100.0,
        50.0,
    )
    .await
    .expect("spawn");
    let client = Client::connect(swarm.addresses()[0], 1).await;
    // Our heartbeat may itself be lost: repeat until the vehicle answers.
    for _ in 0..10 {
        client.send(&gcs_heartbeat()).await;
        if client
            .recv_until(Duration::from_millis(200), |_, _| Some(()))
            .await
            .is_some()
        {
            break;
        }
    }
    let window = Duration::from_secs(4);
    let received = count_local_positions(&client.collect(window).await);
    // 50 Hz for 4 s is 200 messages; 40 % loss leaves ~120 (σ ≈ 7).
    assert!(
        (90..=150).contains(&received),
        "received {received} of ~200"
    );
    let stats = swarm.snapshot(0).link;
    assert!(stats.tx_dropped_by_fault > 50, "{stats:?}");
    swarm.shutdown().await;
}

#[tokio::test]
async fn latency_delays_each_direction() {
    let latency = Duration::from_millis(150);
    let swarm = spawn(
        LOOPBACK,
        px4_with(Faults {
            latency,
            ..Faults::default()
        }),
        100.0,
        20.0,
    )
    .await
    .expect("spawn");
    let client = Client::connect(swarm.addresses()[0], 1).await;
    sleep(Duration::from_millis(400)).await; // let the heartbeat reach it
    let mut round_trips = Vec::new();
    for ts1 in 1..=3i64 {
        let sent = Instant::now();
        client
            .send(&MavMessage::TIMESYNC(TIMESYNC_DATA {
                tc1: 0,
                ts1,
                target_system: 1,
                target_component: 1,
            }))
            .await;
        let answered = client
            .recv_until(Duration::from_secs(2), |_, m| match m {
                MavMessage::TIMESYNC(t) if t.ts1 == ts1 && t.tc1 != 0 => Some(()),
                _ => None,
            })
            .await;
        assert!(answered.is_some(), "timesync {ts1} answered");
        round_trips.push(sent.elapsed());
    }
    for rtt in round_trips {
        assert!(
            rtt >= 2 * latency && rtt < 2 * latency + Duration::from_millis(250),
            "round trip {rtt:?}"
        );
    }
    swarm.shutdown().await;
}

#[tokio::test]
async fn speed_factor_makes_a_slow_drone() {
    let mut configs = px4_with(Faults {
        speed_factor: 0.5,
        ..Faults::default()
    });
    configs[0].max_speed_mps = 2.0;
    let swarm = spawn(LOOPBACK, configs, 100.0, 20.0).await.expect("spawn");
    let client = Client::connect(swarm.addresses()[0], 1).await;
    assert_eq!(client.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
    let goal = [20.0, 0.0, -2.0];
    for _ in 0..5 {
        client.position_target(goal).await;
        sleep(Duration::from_millis(50)).await;
    }
    assert_eq!(
        client.set_mode(6.0, 0.0).await,
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    let mut top_speed = 0.0f32;
    for _ in 0..60 {
        client.position_target(goal).await;
        sleep(Duration::from_millis(100)).await;
        let v = swarm.snapshot(0).velocity_ned_mps;
        top_speed = top_speed.max(distance(v, [0.0; 3]));
    }
    assert!(
        top_speed <= 1.0 + 1e-3,
        "top speed {top_speed} exceeds 0.5 × 2 m/s"
    );
    assert!(
        top_speed > 0.95,
        "top speed {top_speed}: should reach the reduced limit"
    );
    swarm.shutdown().await;
}

#[tokio::test]
async fn link_drop_cuts_both_directions_after_takeoff() {
    let drop = LinkDrop {
        after_takeoff: Duration::from_secs(1),
        duration: Duration::from_secs(2),
    };
    let swarm = spawn(
        LOOPBACK,
        px4_with(Faults {
            link_drop: Some(drop),
            ..Faults::default()
        }),
        100.0,
        20.0,
    )
    .await
    .expect("spawn");
    let client = Client::connect(swarm.addresses()[0], 1).await;
    assert_eq!(client.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
    assert_eq!(
        client.command(MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7).await,
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    let messages = client.collect(Duration::from_secs(5)).await;
    let times: Vec<Instant> = messages.iter().map(|(t, _, _)| *t).collect();
    let longest_gap = times
        .windows(2)
        .map(|w| w[1] - w[0])
        .max()
        .unwrap_or_default();
    assert!(
        longest_gap >= Duration::from_millis(1800) && longest_gap <= Duration::from_millis(2300),
        "longest silence {longest_gap:?}"
    );
    // Commands sent during the drop are lost too, and the link comes back.
    let stats = swarm.snapshot(0).link;
    assert!(stats.tx_dropped_by_fault > 30, "{stats:?}");
    assert!(!swarm.snapshot(0).link_down);
    assert_eq!(
        client.command(MavCmd::MAV_CMD_NAV_LAND, NAN7).await,
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    swarm.shutdown().await;
}

#[tokio::test]
async fn refuse_arm_is_denied_with_a_reason_on_the_wire() {
    let swarm = spawn(
        LOOPBACK,
        px4_with(Faults {
            refuse_arm: true,
            ..Faults::default()
        }),
        100.0,
        20.0,
    )
    .await
    .expect("spawn");
    let client = Client::connect(swarm.addresses()[0], 1).await;
    assert_eq!(client.arm().await, Some(MavResult::MAV_RESULT_DENIED));
    assert!(!swarm.snapshot(0).armed);
    client
        .send(&MavMessage::COMMAND_LONG(
            mavlink::dialects::common::COMMAND_LONG_DATA {
                param1: 1.0,
                command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
                target_system: 1,
                target_component: 1,
                ..Default::default()
            },
        ))
        .await;
    let reason = client
        .recv_until(Duration::from_secs(1), |_, m| match m {
            MavMessage::STATUSTEXT(t) => t.text.to_str().ok().map(str::to_owned),
            _ => None,
        })
        .await;
    assert!(reason.is_some_and(|r| r.contains("Arming denied")));
    swarm.shutdown().await;
}

#[tokio::test]
async fn low_battery_reports_critical_and_lands() {
    let faults = Faults {
        low_battery_after: Some(Duration::from_secs(3)),
        ..Faults::default()
    };
    let swarm = spawn(LOOPBACK, px4_with(faults), 100.0, 20.0)
        .await
        .expect("spawn");
    let client = Client::connect(swarm.addresses()[0], 1).await;
    assert_eq!(client.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
    assert_eq!(
        client.command(MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7).await,
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    let critical = client
        .recv_until(Duration::from_secs(6), |_, m| match m {
            MavMessage::BATTERY_STATUS(b)
                if b.charge_state == MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_CRITICAL =>
            {
                Some(())
            }
            _ => None,
        })
        .await;
    assert!(critical.is_some(), "BATTERY_STATUS turned critical");
    let landing = client
        .recv_until(Duration::from_secs(2), |_, m| match m {
            MavMessage::HEARTBEAT(h) if h.custom_mode == 0x0604_0000 => Some(()),
            _ => None,
        })
        .await;
    assert!(landing.is_some(), "heartbeat shows AUTO.LAND");
    assert_eq!(swarm.snapshot(0).mode, FlightMode::Land);
    swarm.shutdown().await;
}

#[tokio::test]
async fn signing_rejects_unsigned_commands_and_accepts_signed_ones() {
    let key = [42u8; 32];
    let mut configs = px4_with(Faults::default());
    configs[0].signing_key = Some(key);
    let swarm = spawn(LOOPBACK, configs, 100.0, 20.0).await.expect("spawn");
    let address = swarm.addresses()[0];
    let unsigned = Client::connect(address, 1).await;
    assert_eq!(unsigned.arm().await, None, "unsigned arm is ignored");
    assert!(!swarm.snapshot(0).armed);
    assert!(swarm.snapshot(0).link.rx_bad_signature >= 4);
    let wrong = Client::connect_signed(address, 1, Some([7u8; 32])).await;
    assert_eq!(wrong.arm().await, None, "wrongly signed arm is ignored");
    // The correctly signed client also only accepts signed input, so its ACK proves outgoing signing.
    let signed = Client::connect_signed(address, 1, Some(key)).await;
    assert_eq!(signed.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
    assert!(swarm.snapshot(0).armed);
    swarm.shutdown().await;
}

#[tokio::test]
async fn garbage_and_foreign_traffic_never_break_the_vehicle() {
    let swarm = spawn(LOOPBACK, px4_with(Faults::default()), 100.0, 20.0)
        .await
        .expect("spawn");
    let address = swarm.addresses()[0];
    let raw = tokio::net::UdpSocket::bind((LOOPBACK, 0))
        .await
        .expect("bind");
    let mut state = 0x9e37_79b9u32;
    for len in [0usize, 1, 5, 12, 40, 280, 600, 1500] {
        let bytes: Vec<u8> = (0..len)
            .map(|i| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                if i % 13 == 0 {
                    0xfd
                } else {
                    (state >> 24) as u8
                }
            })
            .collect();
        raw.send_to(&bytes, address).await.expect("send garbage");
    }
    // A MAVLink 1 frame (ignored: MAVLink 2 only) and a command for another system.
    raw.send_to(
        &[0xfe, 9, 0, 255, 190, 0, 0, 0, 0, 0, 6, 8, 0, 0, 3, 0, 0],
        address,
    )
    .await
    .expect("send v1");
    let client = Client::connect(address, 2).await;
    assert_eq!(
        client.arm().await,
        None,
        "a command for system 2 is not answered by system 1"
    );
    let client = Client::connect(address, 1).await;
    assert_eq!(client.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
    swarm.shutdown().await;
}
