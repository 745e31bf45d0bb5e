//! Hostile and broken MAVLink input on the controller's receive path.
//!
//! Frames are built with `swarmctl_sitl::forge`, so they carry valid CRCs and get
//! past the checksum into the message parser and [`fold`]:
//!
//! - `fold_*` property tests decode random frames (any message id, any payload,
//!   any header) and fold them into a vehicle state: nothing panics, a frame from
//!   another system id changes nothing at all, and from the right system only the
//!   autopilot component steers armed/mode/position, positions stay finite and
//!   never go back in time, and only ACKs addressed to us come out.
//! - `session_survives_a_hostile_burst` runs a real [`Session`] against a UDP
//!   socket this test owns and sprays it with random frames, garbage and
//!   truncated datagrams from other system ids, interleaved with a few proper
//!   frames from the vehicle; armed/mode/position only ever show the vehicle's
//!   values, and afterwards the session still sees heartbeats and gets ACKs.

use mavlink::dialects::common::{
    COMMAND_ACK_DATA, HEARTBEAT_DATA, LOCAL_POSITION_NED_DATA, MavAutopilot, MavCmd, MavMessage,
    MavModeFlag, MavResult, MavState, MavType,
};
use mavlink::error::MessageReadError;
use mavlink::{MavHeader, MavlinkReader, MavlinkVersion};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use swarmctl::link::wire::{REBOOT_BACKSTEP_MS, fold};
use swarmctl::link::{CommandPolicy, Session, VehicleState};
use swarmctl_sitl::forge;
use tokio::net::UdpSocket;

/// The vehicle the session flies.
const VEHICLE: u8 = 7;
const AUTOPILOT: u8 = 1;
/// The mode the vehicle reports throughout the burst (PX4 AUTO.LOITER).
const MODE: u32 = 0x0304_0000;
/// Distinctive coordinates of the vehicle's own position samples.
const OWN_Y_M: f32 = 12.25;
const OWN_Z_M: f32 = -3.5;

// ---------------------------------------------------------------- strategies

/// Message ids [`fold`] acts on, so random payloads hit them often.
const FOLDED_IDS: [u32; 6] = [0, 1, 32, 77, 245, 253];

fn message_id() -> impl Strategy<Value = u32> {
    prop_oneof![
        3 => prop::sample::select(FOLDED_IDS.to_vec()),
        3 => prop::sample::select(forge::known_message_ids().to_vec()),
        1 => 0u32..0x0100_0000,
    ]
}

/// Floats a hostile sender likes.
fn nasty_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        Just(f32::MAX),
        Just(-0.0f32),
        -1e4f32..1e4,
        any::<f32>(),
    ]
}

/// Messages that would steer the executor if they got through.
fn steering_message() -> impl Strategy<Value = MavMessage> {
    prop_oneof![
        (any::<u32>(), any::<bool>(), any::<u8>()).prop_map(|(custom_mode, armed, autopilot)| {
            MavMessage::HEARTBEAT(HEARTBEAT_DATA {
                custom_mode,
                mavtype: MavType::MAV_TYPE_QUADROTOR,
                autopilot: if autopilot % 2 == 0 {
                    MavAutopilot::MAV_AUTOPILOT_PX4
                } else {
                    MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA
                },
                base_mode: if armed {
                    MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED
                        | MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
                } else {
                    MavModeFlag::from_bits_truncate(autopilot)
                },
                system_status: MavState::MAV_STATE_ACTIVE,
                mavlink_version: 3,
            })
        }),
        (any::<u32>(), prop::array::uniform6(nasty_f32())).prop_map(|(time_boot_ms, f)| {
            MavMessage::LOCAL_POSITION_NED(LOCAL_POSITION_NED_DATA {
                time_boot_ms,
                x: f[0],
                y: f[1],
                z: f[2],
                vx: f[3],
                vy: f[4],
                vz: f[5],
            })
        }),
        (any::<bool>(), any::<u8>(), any::<u8>()).prop_map(|(accepted, ts, tc)| {
            MavMessage::COMMAND_ACK(ack(
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                if accepted {
                    MavResult::MAV_RESULT_ACCEPTED
                } else {
                    MavResult::MAV_RESULT_DENIED
                },
                if ts % 2 == 0 { 255 } else { ts },
                if tc % 2 == 0 { 190 } else { tc },
            ))
        }),
    ]
}

/// One frame with a valid CRC: random parts, or an encoded steering message.
fn frame(system_id: BoxedStrategy<u8>) -> impl Strategy<Value = Vec<u8>> {
    let component = prop_oneof![Just(AUTOPILOT), any::<u8>()];
    prop_oneof![
        (
            system_id.clone(),
            component.clone(),
            any::<u8>(),
            message_id(),
            prop::collection::vec(any::<u8>(), 0..=64),
        )
            .prop_map(|(s, c, q, id, payload)| forge::frame(s, c, q, id, &payload)),
        (
            system_id.clone(),
            component.clone(),
            any::<u8>(),
            message_id(),
            prop::collection::vec(any::<u8>(), 0..=255),
        )
            .prop_map(|(s, c, q, id, payload)| forge::frame(s, c, q, id, &payload)),
        (system_id, component, any::<u8>(), steering_message())
            .prop_map(|(s, c, q, m)| forge::message(s, c, q, &m)),
    ]
}

fn any_system() -> BoxedStrategy<u8> {
    prop_oneof![Just(VEHICLE), any::<u8>()].boxed()
}

fn other_system() -> BoxedStrategy<u8> {
    any::<u8>()
        .prop_filter("not the vehicle", |&s| s != VEHICLE)
        .boxed()
}

/// Every message in `bytes` (a frame, several, or junk), as the connection decodes it.
fn decode_all(bytes: &[u8]) -> Vec<(MavHeader, MavMessage)> {
    let mut reader = MavlinkReader::new(bytes);
    let mut out = Vec::new();
    for _ in 0..64 {
        match reader.read_message::<MavMessage>(MavlinkVersion::V2) {
            Ok(m) => out.push(m),
            Err(MessageReadError::Parse(_)) => continue,
            Err(MessageReadError::Io(_)) => break,
        }
    }
    out
}

// ---------------------------------------------------------------- helpers

fn heartbeat(armed: bool, custom_mode: u32) -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode,
        mavtype: MavType::MAV_TYPE_QUADROTOR,
        autopilot: MavAutopilot::MAV_AUTOPILOT_PX4,
        base_mode: if armed {
            MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED | MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
        } else {
            MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
        },
        system_status: MavState::MAV_STATE_STANDBY,
        mavlink_version: 3,
    })
}

fn position(time_boot_ms: u32, x: f32) -> MavMessage {
    MavMessage::LOCAL_POSITION_NED(LOCAL_POSITION_NED_DATA {
        time_boot_ms,
        x,
        y: OWN_Y_M,
        z: OWN_Z_M,
        vx: 0.0,
        vy: 0.0,
        vz: 0.0,
    })
}

fn ack(
    command: MavCmd,
    result: MavResult,
    target_system: u8,
    target_component: u8,
) -> COMMAND_ACK_DATA {
    COMMAND_ACK_DATA {
        command,
        result,
        progress: 0,
        result_param2: 0,
        target_system,
        target_component,
    }
}

/// A state that has heard the vehicle: disarmed in [`MODE`], at x = 1 m.
fn heard_state(now: Instant) -> VehicleState {
    let mut s = VehicleState {
        recording: true,
        ..VehicleState::default()
    };
    let h = MavHeader {
        system_id: u32::from(VEHICLE),
        component_id: AUTOPILOT,
        sequence: 0,
    };
    fold(&mut s, &h, heartbeat(false, MODE), VEHICLE, now);
    fold(&mut s, &h, position(1_000, 1.0), VEHICLE, now);
    s
}

fn is_own_position(s: &VehicleState) -> bool {
    s.position.is_none_or(|p| {
        p.position_ned_m[1] == OWN_Y_M
            && p.position_ned_m[2] == OWN_Z_M
            && p.velocity_ned_mps == [0.0; 3]
    })
}

// ---------------------------------------------------------------- fold

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, .. ProptestConfig::default() })]

    /// Frames from any other system id leave the state exactly as it was.
    #[test]
    fn fold_ignores_other_systems(frames in prop::collection::vec(frame(other_system()), 1..24)) {
        let t0 = Instant::now();
        let mut state = heard_state(t0);
        let before = state.clone();
        for (i, bytes) in frames.iter().enumerate() {
            for (header, message) in decode_all(bytes) {
                let now = t0 + Duration::from_millis(i as u64 + 1);
                let ack = fold(&mut state, &header, message, VEHICLE, now);
                prop_assert!(ack.is_none());
                prop_assert_eq!(&state, &before);
            }
        }
    }

    /// Frames from anyone, the vehicle included: nothing panics, and the state
    /// keeps its invariants.
    #[test]
    fn fold_keeps_invariants(frames in prop::collection::vec(frame(any_system()), 1..24)) {
        let t0 = Instant::now();
        let mut state = heard_state(t0);
        for (i, bytes) in frames.iter().enumerate() {
            for (header, message) in decode_all(bytes) {
                let now = t0 + Duration::from_millis(i as u64 + 1);
                let before = state.clone();
                let own = header.system_id == u32::from(VEHICLE);
                let from_autopilot = own && header.component_id == AUTOPILOT;
                let is_heartbeat = matches!(message, MavMessage::HEARTBEAT(_));
                let sent_ack = match &message {
                    MavMessage::COMMAND_ACK(a) => Some(a.clone()),
                    _ => None,
                };
                let time_boot_ms = match &message {
                    MavMessage::LOCAL_POSITION_NED(p) => Some(p.time_boot_ms),
                    _ => None,
                };
                let ack = fold(&mut state, &header, message, VEHICLE, now);

                if !own {
                    prop_assert_eq!(&state, &before);
                    prop_assert!(ack.is_none());
                    continue;
                }
                prop_assert_eq!(state.last_message, Some(now));
                if state.armed != before.armed
                    || state.custom_mode != before.custom_mode
                    || state.last_heartbeat != before.last_heartbeat
                {
                    prop_assert!(from_autopilot && is_heartbeat);
                }
                if state.position != before.position {
                    prop_assert!(from_autopilot);
                    let p = state.position.unwrap();
                    prop_assert!(p.position_ned_m.iter().chain(&p.velocity_ned_mps).all(|c| c.is_finite()));
                    let (old, new) = (before.position_time_boot_ms.unwrap(), time_boot_ms.unwrap());
                    prop_assert!(new >= old || old - new >= REBOOT_BACKSTEP_MS, "{old} -> {new}");
                }
                if let Some(a) = &ack {
                    prop_assert_eq!(Some(a), sent_ack.as_ref());
                    prop_assert!(matches!(a.target_system, 0 | 255));
                    prop_assert!(matches!(a.target_component, 0 | 190));
                }
                if let Some(p) = state.position {
                    prop_assert!(p.position_ned_m.iter().all(|c| c.is_finite()));
                }
                prop_assert!(state.battery_remaining_pct.is_none_or(|b| (0..=100).contains(&b)));
            }
        }
    }

    /// Junk and truncated frames decode to nothing harmful.
    #[test]
    fn fold_survives_junk(
        junk in prop::collection::vec(any::<u8>(), 0..300),
        frame in frame(any_system()),
        cut in any::<prop::sample::Index>(),
    ) {
        let t0 = Instant::now();
        let mut state = heard_state(t0);
        let mut bytes = frame.clone();
        bytes.truncate(cut.index(frame.len()));
        bytes.extend_from_slice(&junk);
        bytes.extend_from_slice(&frame);
        for (header, message) in decode_all(&bytes) {
            fold(&mut state, &header, message, VEHICLE, t0);
        }
        let p = state.position.expect("heard_state has a position");
        prop_assert!(p.position_ned_m.iter().chain(&p.velocity_ned_mps).all(|c| c.is_finite()));
    }
}

// ---------------------------------------------------------------- end to end

/// One datagram of the hostile burst.
fn hostile_datagram() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        // One random frame from another system.
        6 => frame(other_system()),
        // Several frames in one datagram.
        2 => prop::collection::vec(frame(other_system()), 2..5).prop_map(|fs| fs.concat()),
        // A truncated frame (its header promises more bytes than come).
        2 => (frame(other_system()), any::<prop::sample::Index>())
            .prop_map(|(f, i)| f[..i.index(f.len())].to_vec()),
        // Pure junk, sometimes starting like a frame.
        2 => (prop::collection::vec(any::<u8>(), 0..300), any::<bool>()).prop_map(|(mut j, stx)| {
            if stx && !j.is_empty() {
                j[0] = 0xfd;
            }
            j
        }),
    ]
}

fn own(sequence: u8, message: &MavMessage) -> Vec<u8> {
    forge::message(VEHICLE, AUTOPILOT, sequence, message)
}

/// Waits (bounded) until `ok` holds on the session's state.
async fn until(session: &Session, within: Duration, ok: impl Fn(&VehicleState) -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < within {
        if ok(&session.state()) {
            return true;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    false
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn session_survives_a_hostile_burst() {
    tokio::time::timeout(Duration::from_secs(40), hostile_burst())
        .await
        .expect("the test finished in time");
}

async fn hostile_burst() {
    let vehicle = Arc::new(UdpSocket::bind("127.0.0.1:0").await.expect("bind"));
    let port = vehicle.local_addr().unwrap().port();
    let policy = CommandPolicy {
        attempts: 3,
        ack_timeout: Duration::from_millis(500),
    };
    let session = Arc::new(
        Session::connect(&format!("udpout:127.0.0.1:{port}"), VEHICLE, policy, None)
            .await
            .expect("session"),
    );
    // The session's first ground-station heartbeat tells us where it listens.
    let mut buf = [0u8; 2048];
    let (_, gcs) = tokio::time::timeout(Duration::from_secs(3), vehicle.recv_from(&mut buf))
        .await
        .expect("a ground-station heartbeat within 3 s")
        .expect("recv");

    let mut sequence = 0u8;
    let mut send_own = async |message: MavMessage| {
        sequence = sequence.wrapping_add(1);
        vehicle
            .send_to(&own(sequence, &message), gcs)
            .await
            .expect("send");
    };
    send_own(heartbeat(false, MODE)).await;
    send_own(position(1_000, 1.0)).await;
    assert!(
        until(&session, Duration::from_secs(3), |s| {
            s.last_heartbeat.is_some() && s.position.is_some()
        })
        .await,
        "the vehicle's own heartbeat and position arrive"
    );

    // A watcher checks, all through the burst, that only the vehicle steers.
    let running = Arc::new(AtomicBool::new(true));
    let watcher = {
        let (session, running) = (session.clone(), running.clone());
        tokio::spawn(async move {
            let mut looks = 0u32;
            while running.load(Ordering::Relaxed) && looks < 20_000 {
                {
                    let s = session.state();
                    assert!(!s.armed, "a foreign frame armed the vehicle");
                    assert_eq!(s.custom_mode, MODE, "a foreign frame changed the mode");
                    assert!(
                        is_own_position(&s),
                        "a foreign frame moved the vehicle: {:?}",
                        s.position
                    );
                }
                looks += 1;
                tokio::time::sleep(Duration::from_millis(2)).await;
            }
            looks
        })
    };

    let mut runner = TestRunner::deterministic();
    let burst = prop::collection::vec(hostile_datagram(), 1500)
        .new_tree(&mut runner)
        .expect("burst")
        .current();
    // The burst is not vacuous: most of it decodes, much of it would steer.
    let decoded: Vec<MavMessage> = burst
        .iter()
        .flat_map(|d| decode_all(d))
        .map(|(_, m)| m)
        .collect();
    let steering = decoded
        .iter()
        .filter(|m| {
            matches!(
                m,
                MavMessage::HEARTBEAT(_)
                    | MavMessage::LOCAL_POSITION_NED(_)
                    | MavMessage::COMMAND_ACK(_)
            )
        })
        .count();
    assert!(
        decoded.len() > 600 && steering > 300,
        "{} decoded, {steering} steering",
        decoded.len()
    );
    let mut time_boot_ms = 1_000u32;
    for (i, datagram) in burst.iter().enumerate() {
        vehicle.send_to(datagram, gcs).await.expect("send");
        if i % 50 == 0 {
            // The vehicle keeps talking, with its own (monotonic) clock.
            time_boot_ms += 100;
            send_own(heartbeat(false, MODE)).await;
            send_own(position(time_boot_ms, time_boot_ms as f32 / 1000.0)).await;
            // Pace the burst so the kernel's receive buffer is not the limit.
            tokio::time::sleep(Duration::from_millis(2)).await;
        }
    }
    tokio::time::sleep(Duration::from_millis(200)).await;
    running.store(false, Ordering::Relaxed);
    let looks = watcher.await.expect("no foreign frame steered the vehicle");
    assert!(looks > 10, "the watcher looked only {looks} times");

    // Afterwards the session still follows the vehicle ...
    let new_mode = 0x0006_0000;
    time_boot_ms += 100;
    send_own(heartbeat(false, new_mode)).await;
    send_own(position(time_boot_ms, 42.0)).await;
    assert!(
        until(&session, Duration::from_secs(3), |s| {
            s.custom_mode == new_mode && s.position.is_some_and(|p| p.position_ned_m[0] == 42.0)
        })
        .await,
        "the session no longer follows the vehicle after the burst: {:?}",
        *session.state()
    );

    // ... and a command gets its ACK, even with foreign refusals arriving first.
    let responder = {
        let vehicle = vehicle.clone();
        tokio::spawn(async move {
            let mut buf = [0u8; 2048];
            let deadline = Instant::now() + Duration::from_secs(5);
            while Instant::now() < deadline {
                let Ok(Ok((n, from))) =
                    tokio::time::timeout(Duration::from_millis(500), vehicle.recv_from(&mut buf))
                        .await
                else {
                    continue;
                };
                for (_, message) in decode_all(&buf[..n]) {
                    let MavMessage::COMMAND_LONG(c) = message else {
                        continue;
                    };
                    if c.target_system != VEHICLE {
                        continue;
                    }
                    let refuse = MavResult::MAV_RESULT_DENIED;
                    let accept = MavResult::MAV_RESULT_ACCEPTED;
                    let answers = [
                        // Another vehicle refuses, addressed to us.
                        forge::message(
                            9,
                            AUTOPILOT,
                            0,
                            &MavMessage::COMMAND_ACK(ack(c.command, refuse, 255, 190)),
                        ),
                        // Our vehicle refuses, but to another ground station.
                        forge::message(
                            VEHICLE,
                            AUTOPILOT,
                            0,
                            &MavMessage::COMMAND_ACK(ack(c.command, refuse, 42, 190)),
                        ),
                        // Our vehicle accepts, addressed to us.
                        forge::message(
                            VEHICLE,
                            AUTOPILOT,
                            0,
                            &MavMessage::COMMAND_ACK(ack(c.command, accept, 255, 190)),
                        ),
                    ];
                    for a in answers {
                        vehicle.send_to(&a, from).await.expect("send");
                    }
                    return true;
                }
            }
            false
        })
    };
    session
        .command(
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
            [32.0, 50_000.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .await
        .expect("the command is accepted: only the vehicle's ACK to us counts");
    assert!(
        responder.await.expect("responder"),
        "the command reached the vehicle"
    );
    let s = session.state();
    assert!(!s.armed);
    assert_eq!(s.custom_mode, new_mode);
}
