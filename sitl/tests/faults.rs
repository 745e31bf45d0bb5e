//! Every fault knob, measured on the wire (rust-mavlink client over UDP) or
//! through the vehicle's true state.
// Tests may unwrap, expect and run long: a failure is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::too_many_lines)]

mod common;

use common::*;
use mavlink::dialects::common::{
    COMMAND_LONG_DATA, MavBatteryChargeState, MavCmd, MavMessage, MavResult, MavSeverity,
    TIMESYNC_DATA,
};
use std::time::Duration;
use swarmctl_sitl::forge::{self, Signature};
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
async fn low_battery_warns_then_critical_battery_lands() {
    let faults = Faults {
        low_battery_after: Some(Duration::from_secs(2)),
        critical_battery_after: Some(Duration::from_secs(5)),
        ..Faults::default()
    };
    let swarm = spawn(LOOPBACK, px4_with(faults), 100.0, 20.0)
        .await
        .expect("spawn");
    let client = Client::connect(swarm.addresses()[0], 1).await;
    let first_remaining = client
        .recv_until(Duration::from_secs(3), |_, m| match m {
            MavMessage::SYS_STATUS(s) => Some(s.battery_remaining),
            _ => None,
        })
        .await;
    assert_eq!(first_remaining, Some(100), "a full battery at boot");
    assert_eq!(client.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
    assert_eq!(
        client.command(MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7).await,
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    // Stage 1: LOW — a warning, the vehicle keeps flying its mode.
    let warning = client
        .recv_until(Duration::from_secs(4), |_, m| match m {
            MavMessage::STATUSTEXT(t) => Some((t.severity, t.text.to_str().ok()?.to_owned())),
            _ => None,
        })
        .await;
    let (severity, text) = warning.expect("a STATUSTEXT for the low battery");
    assert_eq!(severity, MavSeverity::MAV_SEVERITY_WARNING);
    assert!(text.starts_with("Low battery"), "{text}");
    let (mut saw_low_sys_status, mut saw_low_charge) = (false, false);
    client
        .recv_until(Duration::from_millis(2500), |_, m| {
            match m {
                MavMessage::SYS_STATUS(s) => saw_low_sys_status |= s.battery_remaining <= 25,
                MavMessage::BATTERY_STATUS(b) => {
                    saw_low_charge |=
                        b.charge_state == MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_LOW;
                }
                _ => {}
            }
            (saw_low_sys_status && saw_low_charge).then_some(())
        })
        .await;
    assert!(saw_low_sys_status, "SYS_STATUS battery_remaining <= 25 %");
    assert!(saw_low_charge, "BATTERY_STATUS charge state LOW");
    let snapshot = swarm.snapshot(0);
    assert!(snapshot.battery_low && !snapshot.battery_critical);
    assert!(snapshot.armed);
    assert_ne!(snapshot.mode, FlightMode::Land, "a low battery only warns");
    // Stage 2: CRITICAL — PX4 lands.
    let critical = client
        .recv_until(Duration::from_secs(5), |_, m| match m {
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
    let snapshot = swarm.snapshot(0);
    assert_eq!(snapshot.mode, FlightMode::Land);
    assert!(snapshot.battery_critical && snapshot.battery_remaining_pct <= 8.0);
    swarm.shutdown().await;
}

#[tokio::test]
async fn duplicates_are_delivered_twice_and_counted() {
    let swarm = spawn(
        LOOPBACK,
        px4_with(Faults {
            duplicate_percent: 40.0,
            ..Faults::default()
        }),
        100.0,
        50.0,
    )
    .await
    .expect("spawn");
    let client = Client::connect(swarm.addresses()[0], 1).await;
    const SENT: u64 = 60;
    for _ in 1..SENT {
        client.send(&gcs_heartbeat()).await;
    }
    let messages = client.collect(Duration::from_secs(2)).await;
    // Outgoing: a duplicate carries the same sequence number as its original.
    let mut seen = std::collections::HashMap::new();
    for (_, header, message) in &messages {
        if matches!(message, MavMessage::LOCAL_POSITION_NED(_)) {
            *seen.entry(header.sequence).or_insert(0u32) += 1;
        }
    }
    let twice = seen.values().filter(|n| **n >= 2).count();
    assert!(
        (15..=70).contains(&twice),
        "{twice} of {} positions arrived twice",
        seen.len()
    );
    // Incoming: every heartbeat arrives, some twice; no loss.
    let stats = swarm.snapshot(0).link;
    assert_eq!(stats.rx_datagrams, SENT, "{stats:?}");
    assert!((10..=40).contains(&stats.rx_duplicated), "{stats:?}");
    assert_eq!(stats.rx_messages, SENT + stats.rx_duplicated, "{stats:?}");
    assert!(stats.tx_duplicated >= twice as u64, "{stats:?}");
    assert_eq!(stats.rx_dropped_by_fault + stats.tx_dropped_by_fault, 0);
    swarm.shutdown().await;
}

/// Pairs of consecutive items whose sequence numbers go backwards (mod 256).
fn backward_steps(sequences: &[u8]) -> usize {
    sequences
        .windows(2)
        .filter(|w| (w[1].wrapping_sub(w[0]) as i8) < 0)
        .count()
}

#[tokio::test]
async fn reordering_lets_later_datagrams_overtake_in_both_directions() {
    let swarm = spawn(
        LOOPBACK,
        px4_with(Faults {
            reorder_percent: 30.0,
            ..Faults::default()
        }),
        100.0,
        50.0,
    )
    .await
    .expect("spawn");
    let client = Client::connect(swarm.addresses()[0], 1).await;
    sleep(Duration::from_millis(200)).await;
    // Outgoing: telemetry sequence numbers arrive out of order.
    let arrived: Vec<u8> = client
        .collect(Duration::from_secs(2))
        .await
        .iter()
        .map(|(_, header, _)| header.sequence)
        .collect();
    assert!(arrived.len() > 150, "{} messages", arrived.len());
    let backwards = backward_steps(&arrived);
    assert!(backwards >= 5, "{backwards} out-of-order arrivals");
    // Incoming: TIMESYNC requests 1..=80, 3 ms apart. The vehicle numbers its
    // replies as it handles them, so sorted by request, the reply sequence
    // numbers go backwards wherever a request was overtaken.
    const REQUESTS: i64 = 80;
    for ts1 in 1..=REQUESTS {
        client
            .send(&MavMessage::TIMESYNC(TIMESYNC_DATA {
                tc1: 0,
                ts1,
                target_system: 1,
                target_component: 1,
            }))
            .await;
        sleep(Duration::from_millis(3)).await;
    }
    let mut replies = std::collections::BTreeMap::new();
    client
        .recv_until(Duration::from_secs(1), |header, m| {
            if let MavMessage::TIMESYNC(t) = m
                && t.tc1 != 0
            {
                replies.insert(t.ts1, header.sequence);
            }
            (replies.len() as i64 == REQUESTS).then_some(())
        })
        .await;
    assert_eq!(
        replies.len() as i64,
        REQUESTS,
        "every request answered once"
    );
    let handled: Vec<u8> = replies.values().copied().collect();
    assert!(backward_steps(&handled) >= 2, "{handled:?}");
    let stats = swarm.snapshot(0).link;
    assert!(
        stats.rx_reordered >= 5 && stats.tx_reordered >= 20,
        "{stats:?}"
    );
    swarm.shutdown().await;
}

#[tokio::test]
async fn permanent_link_drop_never_recovers() {
    let swarm = spawn(
        LOOPBACK,
        px4_with(Faults {
            link_drop: Some(LinkDrop {
                after_takeoff: Duration::from_millis(500),
                duration: Duration::MAX,
            }),
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
    // Poll the true state (no message arrives once the link is cut).
    let mut cut = None;
    for _ in 0..100 {
        if swarm.snapshot(0).link_down {
            cut = Some(Instant::now());
            break;
        }
        sleep(Duration::from_millis(50)).await;
    }
    let cut = cut.expect("the link is cut after takeoff");
    client
        .recv_until(Duration::from_millis(300), |_, _| None::<()>)
        .await; // in flight
    let after = client.collect(Duration::from_secs(4)).await;
    assert!(after.is_empty(), "{} messages after the cut", after.len());
    assert_eq!(client.command(MavCmd::MAV_CMD_NAV_LAND, NAN7).await, None);
    let snapshot = swarm.snapshot(0);
    assert!(
        snapshot.link_down,
        "still down {:?} after the cut",
        cut.elapsed()
    );
    assert!(snapshot.armed && snapshot.mode != FlightMode::Land);
    assert!(
        snapshot.link.rx_dropped_by_fault >= 4,
        "{:?}",
        snapshot.link
    );
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

#[tokio::test]
async fn signing_refuses_a_third_partys_unsigned_and_wrongly_signed_arms() {
    let key = [0x42u8; 32];
    let mut configs = px4_with(Faults::default());
    configs[0].signing_key = Some(key);
    let swarm = spawn(LOOPBACK, configs, 100.0, 20.0).await.expect("spawn");
    let address = swarm.addresses()[0];
    // The ground station, correctly signed, talks to the vehicle first.
    let gcs = Client::connect_signed(address, 1, Some(key)).await;
    assert!(
        gcs.recv_until(Duration::from_secs(2), |_, m| {
            matches!(m, MavMessage::HEARTBEAT(_)).then_some(())
        })
        .await
        .is_some(),
        "signed telemetry reaches the ground station"
    );
    // A third party: system 200 on its own socket.
    let intruder = tokio::net::UdpSocket::bind((LOOPBACK, 0))
        .await
        .expect("bind");
    let arm = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1: 1.0,
        command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
        target_system: 1,
        target_component: 1,
        ..COMMAND_LONG_DATA::default()
    });
    let wrong_key = Signature::now([0x24; 32]);
    let attempts: Vec<Vec<u8>> = (0..3u8)
        .flat_map(|i| {
            [
                forge::message(200, 190, 2 * i, &arm),
                forge::signed_message(
                    200,
                    190,
                    2 * i + 1,
                    &arm,
                    &Signature {
                        timestamp: wrong_key.timestamp + u64::from(i),
                        ..wrong_key
                    },
                ),
            ]
        })
        .collect();
    let before = swarm.snapshot(0).link.rx_bad_signature;
    for datagram in &attempts {
        intruder.send_to(datagram, address).await.expect("send");
        sleep(Duration::from_millis(20)).await;
    }
    // Nothing comes back to the intruder, least of all an ACCEPTED ack.
    let mut buffer = [0u8; 2048];
    let mut acks = Vec::new();
    let deadline = Instant::now() + Duration::from_millis(700);
    while let Ok(Ok((len, _))) =
        tokio::time::timeout_at(deadline, intruder.recv_from(&mut buffer)).await
    {
        for (_, message) in swarmctl_sitl::codec::decode(&buffer[..len], None).messages {
            if let MavMessage::COMMAND_ACK(ack) = message {
                acks.push(ack.result);
            }
        }
    }
    assert!(
        !acks.contains(&MavResult::MAV_RESULT_ACCEPTED),
        "acks to the intruder: {acks:?}"
    );
    let snapshot = swarm.snapshot(0);
    assert!(!snapshot.armed, "the intruder did not arm the vehicle");
    assert_eq!(
        snapshot.link.rx_bad_signature - before,
        attempts.len() as u64,
        "{:?}",
        snapshot.link
    );
    // The ground station's correctly signed arm still works.
    assert_eq!(gcs.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
    assert!(swarm.snapshot(0).armed);
    swarm.shutdown().await;
}
