//! MAVLink 2 signing end to end: with a per-mission key the bundled SITL refuses
//! every unsigned or wrongly signed command, so a third party on the same network
//! can neither arm a vehicle on the ground nor disarm or land one in flight, while
//! the signed swarm flies its plan. A controller without the key cannot arm it.

use crate::fly_common::*;
use mavlink::dialects::common::{COMMAND_LONG_DATA, MavCmd, MavMessage};
use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;
use swarmctl::fly::{self, FlyError};
use swarmctl::link::SigningKey;
use swarmctl_sitl::forge::{self, Signature};
use swarmctl_sitl::{Flavour, Swarm};
use tokio::net::UdpSocket;

const INTRUDER_SYSTEM: u8 = 200;

fn command(target: u8, command: MavCmd, param1: f32, param2: f32) -> MavMessage {
    MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        target_system: target,
        target_component: 1,
        command,
        param1,
        param2,
        ..COMMAND_LONG_DATA::default()
    })
}

async fn signed_swarm(
    key: &SigningKey,
) -> (
    swarmctl::mission::Mission,
    swarmctl::plan::DiscretePlan,
    Swarm,
    Vec<fly::VehicleLink>,
) {
    let (mission, plan) = load("missions/swap-corridor.yaml");
    let mut configs =
        swarmctl_bundled::vehicle_configs(&mission, &plan, Flavour::Px4, &[]).expect("configs");
    for c in &mut configs {
        c.signing_key = Some(key.bytes());
    }
    let (swarm, links) = swarmctl_bundled::start(configs, mission.link.setpoint_rate_hz)
        .await
        .expect("sitl");
    (mission, plan, swarm, links)
}

/// Sends `message` unsigned and signed with a wrong key to every vehicle.
async fn intrude(
    socket: &UdpSocket,
    targets: &[(u8, SocketAddr)],
    sequence: u8,
    what: impl Fn(u8) -> MavMessage,
) {
    for &(system_id, address) in targets {
        let message = what(system_id);
        let unsigned = forge::message(INTRUDER_SYSTEM, 190, sequence, &message);
        let wrong = forge::signed_message(
            INTRUDER_SYSTEM,
            190,
            sequence,
            &message,
            &Signature::now([0x11; 32]),
        );
        let _ = socket.send_to(&unsigned, address).await;
        let _ = socket.send_to(&wrong, address).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn unsigned_third_party_commands_are_refused_while_the_signed_swarm_flies() {
    let key = SigningKey::from_hex(&"5a".repeat(32)).expect("key");
    let (mission, plan, swarm, links) = signed_swarm(&key).await;
    let targets: Vec<(u8, SocketAddr)> = (0..swarm.len())
        .map(|i| (swarm.snapshot(i).system_id, swarm.snapshot(i).address))
        .collect();
    let intruder = Arc::new(UdpSocket::bind("127.0.0.1:0").await.expect("bind"));

    // On the ground: five unsigned and five wrongly signed arm commands each.
    for sequence in 0..5 {
        intrude(&intruder, &targets, sequence, |id| {
            command(id, MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0)
        })
        .await;
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    tokio::time::sleep(Duration::from_millis(300)).await;
    for i in 0..swarm.len() {
        let s = swarm.snapshot(i);
        assert!(
            !s.armed,
            "vehicle {} armed by an unsigned command",
            s.system_id
        );
        assert!(
            s.link.rx_bad_signature >= 10,
            "vehicle {} counted {} refused frames",
            s.system_id,
            s.link.rx_bad_signature
        );
    }
    let mut reply = [0u8; 512];
    let answered =
        tokio::time::timeout(Duration::from_millis(300), intruder.recv_from(&mut reply)).await;
    assert!(answered.is_err(), "a vehicle answered the intruder");

    // In flight: the intruder keeps trying to force-disarm and land everyone.
    let stop = Arc::new(AtomicBool::new(false));
    let attacker = {
        let (intruder, stop, targets) = (intruder.clone(), stop.clone(), targets.clone());
        tokio::spawn(async move {
            let mut sequence = 5u8;
            for _ in 0..2000 {
                if stop.load(Ordering::Relaxed) {
                    break;
                }
                sequence = sequence.wrapping_add(1);
                intrude(&intruder, &targets, sequence, |id| {
                    command(id, MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 0.0, 21196.0)
                })
                .await;
                intrude(&intruder, &targets, sequence, |id| {
                    command(id, MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0)
                })
                .await;
                tokio::time::sleep(Duration::from_millis(100)).await;
            }
        })
    };
    let mut options = swarmctl_bundled::fly_options(links);
    options.signing_key = Some(key);
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let log = tokio::time::timeout(
        Duration::from_secs(90),
        fly::fly(&mission, &plan, &options, abort_rx),
    )
    .await
    .expect("flight within its time limit")
    .expect("the signed swarm flies");
    stop.store(true, Ordering::Relaxed);
    attacker.await.expect("attacker task");
    assert_success(&log);
    for i in 0..swarm.len() {
        let s = swarm.snapshot(i);
        assert!(!s.armed, "vehicle {} still armed", s.system_id);
        assert!(
            s.link.rx_bad_signature > 100,
            "vehicle {} refused only {} frames in flight",
            s.system_id,
            s.link.rx_bad_signature
        );
    }
    swarm.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_controller_without_the_key_cannot_arm_a_signed_swarm() {
    let key = SigningKey::from_hex(&"a5".repeat(32)).expect("key");
    let (mission, plan, swarm, links) = signed_swarm(&key).await;
    let options = swarmctl_bundled::fly_options(links);
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let result = tokio::time::timeout(
        Duration::from_secs(60),
        fly::fly(&mission, &plan, &options, abort_rx),
    )
    .await
    .expect("refused within its time limit");
    let error = result.expect_err("an unsigned controller must not fly a signed swarm");
    assert!(
        matches!(error, FlyError::Preflight(_) | FlyError::Arming(_)),
        "refused on the ground, got: {error}"
    );
    eprintln!("refused as expected: {error}");
    for i in 0..swarm.len() {
        assert!(!swarm.snapshot(i).armed, "nobody armed");
    }
    swarm.shutdown().await;
}
