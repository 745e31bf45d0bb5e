//! Fuzzes the SITL's MAVLink receive path with frames that carry valid CRCs
//! (built with `swarmctl_sitl::forge`), so the input gets past the checksum
//! into the parser and the vehicle's command handling:
//!
//! (a) random known message ids with random payloads (some re-addressed to
//!     the vehicle so they are acted on),
//! (b) structurally random messages of the kinds the vehicle acts on —
//!     COMMAND_LONG / COMMAND_INT with random command ids and NaN/∞ params,
//!     SET_POSITION_TARGET_* with NaN/huge values and random type masks,
//!     SET_MODE, HEARTBEAT, PARAM_*, TIMESYNC — addressed to it or not,
//! (c) truncated, concatenated and garbage datagrams.
//!
//! Properties: nothing panics or hangs, the vehicle keeps stepping, its state
//! stays finite (never a NaN position, even after a NaN setpoint) and above
//! the ground, messages for another system never change its state, and it
//! still answers a normal command afterwards. Most cases drive `codec` and
//! `Vehicle` directly; a few go end to end through a spawned vehicle's UDP
//! socket.
// Tests may unwrap, expect and run long: a failure is a failed test.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::too_many_lines)]

mod common;

use common::{Client, LOOPBACK};
use mavlink::dialects::common::*;
use mavlink::{MavHeader, MavlinkVersion, Message};
use proptest::collection::vec;
use proptest::prelude::*;
use proptest::sample::select;
use std::time::Duration;
use swarmctl_sitl::{Flavour, Vehicle, VehicleConfig, codec, forge};

/// System id of the vehicle under test.
const ME: u8 = 1;
const DT_S: f64 = 0.01;
const GCS: MavHeader = MavHeader {
    system_id: 255,
    component_id: 190,
    sequence: 0,
};

mod id {
    pub const HEARTBEAT: u32 = 0;
    pub const SET_MODE: u32 = 11;
    pub const PARAM_REQUEST_READ: u32 = 20;
    pub const PARAM_REQUEST_LIST: u32 = 21;
    pub const PARAM_SET: u32 = 23;
    pub const COMMAND_INT: u32 = 75;
    pub const COMMAND_LONG: u32 = 76;
    pub const TIMESYNC: u32 = 111;
}

// ---------------------------------------------------------------- vehicle side

/// Asserts the invariants that must hold after every message and every step.
fn check(v: &Vehicle, context: &str) {
    let (p, velocity) = (v.position_ned_m(), v.velocity_ned_mps());
    assert!(
        v.state_is_finite(),
        "non-finite state {context}: position {p:?}, velocity {velocity:?}, mode {:?}",
        v.mode()
    );
    assert!(p[2] <= 1e-3, "below ground {context}: {p:?}");
}

fn run(v: &mut Vehicle, seconds: f64) {
    for _ in 0..(seconds / DT_S).round() as usize {
        v.step(DT_S);
        check(v, "while stepping");
    }
}

/// Sends a well-formed COMMAND_LONG from the ground station; returns its ACK.
fn command(v: &mut Vehicle, command: MavCmd, params: [f32; 7]) -> Option<MavResult> {
    let [param1, param2, param3, param4, param5, param6, param7] = params;
    v.handle(
        GCS,
        &MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            param1,
            param2,
            param3,
            param4,
            param5,
            param6,
            param7,
            command,
            target_system: ME,
            target_component: 1,
            confirmation: 0,
        }),
    );
    v.take_outbox().into_iter().find_map(|m| match m {
        MavMessage::COMMAND_ACK(a) if a.command == command => Some(a.result),
        _ => None,
    })
}

fn position_target(v: &mut Vehicle, ned_m: [f32; 3]) {
    v.handle(
        GCS,
        &MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
            x: ned_m[0],
            y: ned_m[1],
            z: ned_m[2],
            type_mask: PositionTargetTypemask::from_bits_truncate(3576),
            target_system: ME,
            target_component: 1,
            coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
            ..SET_POSITION_TARGET_LOCAL_NED_DATA::default()
        }),
    );
}

/// A vehicle in one of several states, so the fuzz reaches the mode logic of
/// each: 0 on the ground, 1 taking off, 2 flying under external control
/// (PX4 OFFBOARD / ArduPilot GUIDED), 3 landing.
fn prepared(flavour: Flavour, scenario: u8) -> Vehicle {
    let mut v = Vehicle::new(VehicleConfig::new(ME, flavour), 20.0);
    let nan7 = [f32::NAN; 7];
    let takeoff = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0];
    if scenario >= 1 {
        match flavour {
            Flavour::Px4 => {
                command(&mut v, MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, [1.0; 7]);
                command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, nan7);
            }
            Flavour::ArduPilot => {
                let guided = [1.0, 4.0, 0.0, 0.0, 0.0, 0.0, 0.0];
                command(&mut v, MavCmd::MAV_CMD_DO_SET_MODE, guided);
                command(&mut v, MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, [1.0; 7]);
                command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, takeoff);
            }
        }
        run(&mut v, 1.0);
    }
    if scenario >= 2 {
        run(&mut v, 2.0);
        for _ in 0..10 {
            position_target(&mut v, [1.0, 1.0, -3.0]);
            run(&mut v, 0.1);
        }
        if flavour == Flavour::Px4 {
            let offboard = [1.0, 6.0, 0.0, 0.0, 0.0, 0.0, 0.0];
            command(&mut v, MavCmd::MAV_CMD_DO_SET_MODE, offboard);
        }
    }
    if scenario >= 3 {
        command(&mut v, MavCmd::MAV_CMD_NAV_LAND, nan7);
        run(&mut v, 0.5);
    }
    v.take_outbox();
    v
}

/// Decodes a datagram as the link does and lets the vehicle handle it.
fn feed(v: &mut Vehicle, datagram: &[u8]) {
    for (header, message) in codec::decode(datagram, None).messages {
        v.handle(header, &message);
        check(v, &format!("after {message:?}"));
    }
    v.take_outbox();
}

/// The vehicle still answers a normal heartbeat and command.
fn still_answers(v: &mut Vehicle) {
    let heartbeat = MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        mavtype: MavType::MAV_TYPE_GCS,
        autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
        base_mode: MavModeFlag::empty(),
        ..HEARTBEAT_DATA::default()
    });
    v.handle(GCS, &heartbeat);
    let request_heartbeat = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    v.handle(
        GCS,
        &MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            command: MavCmd::MAV_CMD_REQUEST_MESSAGE,
            param1: request_heartbeat[0],
            target_system: ME,
            target_component: 1,
            ..COMMAND_LONG_DATA::default()
        }),
    );
    let out = v.take_outbox();
    assert!(
        out.iter().any(|m| matches!(m, MavMessage::COMMAND_ACK(a)
            if a.command == MavCmd::MAV_CMD_REQUEST_MESSAGE
                && a.result == MavResult::MAV_RESULT_ACCEPTED)),
        "no ACK: {out:?}"
    );
    assert!(
        out.iter().any(|m| matches!(m, MavMessage::HEARTBEAT(_))),
        "no heartbeat: {out:?}"
    );
    let before = v.time_s();
    run(v, 0.1);
    assert!(v.time_s() > before, "the vehicle keeps stepping");
}

// ------------------------------------------------------------------ strategies

/// Floats that break naive code: NaN, ±∞, extremes, plus ordinary values.
fn wild_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => any::<f32>(),
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
        1 => Just(f32::MAX),
        1 => Just(f32::MIN),
        1 => Just(1e30f32),
        1 => Just(-3e20f32),
        3 => -1000.0f32..1000.0,
        1 => Just(0.0f32),
        1 => Just(1.0f32),
    ]
}

fn wild_f32s<const N: usize>() -> impl Strategy<Value = [f32; N]> {
    proptest::array::uniform(wild_f32())
}

/// A target system: mostly this vehicle, sometimes broadcast or anyone.
fn any_target() -> BoxedStrategy<u8> {
    prop_oneof![3 => Just(ME), 1 => Just(0u8), 1 => any::<u8>()].boxed()
}

/// A target system that is neither this vehicle nor broadcast.
fn foreign_target() -> BoxedStrategy<u8> {
    (2u8..=255).boxed()
}

fn any_component() -> impl Strategy<Value = u8> {
    prop_oneof![3 => Just(1u8), 1 => Just(0u8), 1 => any::<u8>()]
}

/// Command ids: the ones the vehicle implements, neighbours, and anything.
fn command_id() -> impl Strategy<Value = u16> {
    prop_oneof![
        3 => select(vec![400u16, 176, 22, 21, 20, 511, 512, 520, 410, 246, 300, 179, 16, 17]),
        2 => any::<u16>(),
    ]
}

/// A parameter name: a real one of either flavour, or random bytes.
fn param_id() -> impl Strategy<Value = [u8; 16]> {
    let known = select(vec![
        "MIS_TAKEOFF_ALT",
        "COM_OF_LOSS_T",
        "MPC_XY_VEL_MAX",
        "MPC_LAND_SPEED",
        "LAND_SPEED",
        "MAV_SYS_ID",
        "PILOT_TKOFF_ALT",
        "WPNAV_SPEED",
        "SYSID_THISMAV",
        "",
    ])
    .prop_map(|name| {
        let mut id = [0u8; 16];
        id[..name.len()].copy_from_slice(name.as_bytes());
        id
    });
    prop_oneof![3 => known, 1 => any::<[u8; 16]>()]
}

fn le(parts: &[&[u8]]) -> Vec<u8> {
    parts.concat()
}

fn f32s(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

// Wire layouts (fields sorted by size, as MAVLink 2 sends them); checked
// against rust-mavlink by `raw_payload_layouts_match_rust_mavlink`.

fn command_long_payload(params: [f32; 7], command: u16, target: u8, component: u8) -> Vec<u8> {
    le(&[
        &f32s(&params),
        &command.to_le_bytes(),
        &[target, component, 0],
    ])
}

#[allow(clippy::too_many_arguments)]
fn command_int_payload(
    params: [f32; 4],
    x: i32,
    y: i32,
    z: f32,
    command: u16,
    target: u8,
    component: u8,
    frame: u8,
) -> Vec<u8> {
    le(&[
        &f32s(&params),
        &x.to_le_bytes(),
        &y.to_le_bytes(),
        &z.to_le_bytes(),
        &command.to_le_bytes(),
        &[target, component, frame, 0, 0],
    ])
}

fn set_mode_payload(custom_mode: u32, target: u8, base_mode: u8) -> Vec<u8> {
    le(&[&custom_mode.to_le_bytes(), &[target, base_mode]])
}

fn param_set_payload(value: f32, target: u8, component: u8, name: [u8; 16]) -> Vec<u8> {
    le(&[&value.to_le_bytes(), &[target, component], &name, &[9]])
}

fn param_request_read_payload(index: i16, target: u8, component: u8, name: [u8; 16]) -> Vec<u8> {
    le(&[&index.to_le_bytes(), &[target, component], &name])
}

fn timesync_payload(tc1: i64, ts1: i64, target: u8, component: u8) -> Vec<u8> {
    le(&[&tc1.to_le_bytes(), &ts1.to_le_bytes(), &[target, component]])
}

#[allow(deprecated)] // the *_INT frame names are what clients send in these messages
const FRAMES: [MavFrame; 11] = [
    MavFrame::MAV_FRAME_LOCAL_NED,
    MavFrame::MAV_FRAME_LOCAL_OFFSET_NED,
    MavFrame::MAV_FRAME_BODY_NED,
    MavFrame::MAV_FRAME_BODY_OFFSET_NED,
    MavFrame::MAV_FRAME_GLOBAL,
    MavFrame::MAV_FRAME_GLOBAL_INT,
    MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
    MavFrame::MAV_FRAME_GLOBAL_TERRAIN_ALT_INT,
    MavFrame::MAV_FRAME_LOCAL_ENU,
    MavFrame::MAV_FRAME_LOCAL_FRD,
    MavFrame::MAV_FRAME_MISSION,
];

/// A sender: mostly a ground station, sometimes anyone (even our own id).
fn sender() -> impl Strategy<Value = (u8, u8, u8)> {
    (
        prop_oneof![3 => Just(255u8), 1 => any::<u8>()],
        prop_oneof![3 => Just(190u8), 1 => any::<u8>()],
        any::<u8>(),
    )
}

/// One framed message of a kind the vehicle acts on, addressed by `target`.
/// With `with_untargeted`, HEARTBEAT (which has no target) is included too.
fn acted_on(target: BoxedStrategy<u8>, with_untargeted: bool) -> BoxedStrategy<Vec<u8>> {
    let command_long = (
        wild_f32s::<7>(),
        command_id(),
        target.clone(),
        any_component(),
    )
        .prop_map(|(p, c, t, k)| (id::COMMAND_LONG, command_long_payload(p, c, t, k)));
    let command_int = (
        wild_f32s::<4>(),
        any::<i32>(),
        any::<i32>(),
        wild_f32(),
        command_id(),
        target.clone(),
        any_component(),
        prop_oneof![3 => 0u8..22, 1 => any::<u8>()],
    )
        .prop_map(|(p, x, y, z, c, t, k, f)| {
            (id::COMMAND_INT, command_int_payload(p, x, y, z, c, t, k, f))
        });
    let local = (
        wild_f32s::<11>(),
        any::<u16>(),
        select(FRAMES.to_vec()),
        target.clone(),
        any_component(),
    )
        .prop_map(|(f, mask, frame, t, k)| {
            let m = MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
                time_boot_ms: 0,
                x: f[0],
                y: f[1],
                z: f[2],
                vx: f[3],
                vy: f[4],
                vz: f[5],
                afx: f[6],
                afy: f[7],
                afz: f[8],
                yaw: f[9],
                yaw_rate: f[10],
                type_mask: PositionTargetTypemask::from_bits_retain(mask),
                target_system: t,
                target_component: k,
                coordinate_frame: frame,
            });
            encoded(&m)
        });
    let global = (
        (any::<i32>(), any::<i32>()),
        wild_f32s::<9>(),
        any::<u16>(),
        select(FRAMES.to_vec()),
        target.clone(),
        any_component(),
    )
        .prop_map(|((lat, lon), f, mask, frame, t, k)| {
            let m =
                MavMessage::SET_POSITION_TARGET_GLOBAL_INT(SET_POSITION_TARGET_GLOBAL_INT_DATA {
                    time_boot_ms: 0,
                    lat_int: lat,
                    lon_int: lon,
                    alt: f[0],
                    vx: f[1],
                    vy: f[2],
                    vz: f[3],
                    afx: f[4],
                    afy: f[5],
                    afz: f[6],
                    yaw: f[7],
                    yaw_rate: f[8],
                    type_mask: PositionTargetTypemask::from_bits_retain(mask),
                    target_system: t,
                    target_component: k,
                    coordinate_frame: frame,
                });
            encoded(&m)
        });
    let set_mode = (
        prop_oneof![
            select(vec![
                0x0006_0000u32,
                0x0304_0000,
                0x0604_0000,
                0x0204_0000,
                4,
                6,
                9,
                17
            ]),
            any::<u32>()
        ],
        target.clone(),
        prop_oneof![Just(1u8), any::<u8>()],
    )
        .prop_map(|(c, t, b)| (id::SET_MODE, set_mode_payload(c, t, b)));
    let param_set = (wild_f32(), target.clone(), any_component(), param_id())
        .prop_map(|(v, t, k, n)| (id::PARAM_SET, param_set_payload(v, t, k, n)));
    let param_read =
        (any::<i16>(), target.clone(), any_component(), param_id()).prop_map(|(i, t, k, n)| {
            (
                id::PARAM_REQUEST_READ,
                param_request_read_payload(i, t, k, n),
            )
        });
    let param_list =
        (target.clone(), any_component()).prop_map(|(t, k)| (id::PARAM_REQUEST_LIST, vec![t, k]));
    let timesync = (
        prop_oneof![Just(0i64), any::<i64>()],
        any::<i64>(),
        target,
        any_component(),
    )
        .prop_map(|(tc1, ts1, t, k)| (id::TIMESYNC, timesync_payload(tc1, ts1, t, k)));
    let heartbeat = (any::<u32>(), 0u8..=43, 0u8..=20, any::<u8>(), 0u8..=8).prop_map(
        |(custom, kind, autopilot, base, status)| {
            (
                id::HEARTBEAT,
                le(&[&custom.to_le_bytes(), &[kind, autopilot, base, status, 3]]),
            )
        },
    );
    let targeted = prop_oneof![
        3 => command_long,
        2 => command_int,
        3 => local,
        2 => global,
        1 => set_mode,
        1 => param_set,
        1 => param_read,
        1 => param_list,
        1 => timesync,
    ];
    let message = if with_untargeted {
        prop_oneof![8 => targeted, 1 => heartbeat].boxed()
    } else {
        targeted.boxed()
    };
    (message, sender())
        .prop_map(|((message_id, payload), (system, component, sequence))| {
            forge::frame(system, component, sequence, message_id, &payload)
        })
        .boxed()
}

fn encoded(message: &MavMessage) -> (u32, Vec<u8>) {
    let mut payload = [0u8; 255];
    let len = message.ser(MavlinkVersion::V2, &mut payload);
    (message.message_id(), payload[..len].to_vec())
}

/// (a) A random known message id with a random payload; with `retarget`,
/// a payload that parses is re-addressed to this vehicle (or broadcast) so
/// that it is acted on rather than ignored.
fn random_frame() -> impl Strategy<Value = Vec<u8>> {
    (
        select(forge::known_message_ids()),
        vec(any::<u8>(), 0..=255),
        sender(),
        0u8..3,
    )
        .prop_map(
            |(message_id, payload, (system, component, sequence), retarget)| {
                if retarget > 0
                    && let Ok(mut message) =
                        MavMessage::parse(MavlinkVersion::V2, message_id, &payload)
                {
                    if let Some(target) = message.target_system_id_mut() {
                        *target = if retarget == 1 { ME } else { 0 };
                    }
                    if let Some(target) = message.target_component_id_mut() {
                        *target = 1;
                    }
                    return forge::message(system, component, sequence, &message);
                }
                forge::frame(system, component, sequence, message_id, &payload)
            },
        )
}

/// A frame using rust-mavlink's 32-bit system id extension (incompatibility
/// flag 0x02, 12-byte header), which `forge` does not build, with a valid CRC.
fn sysid32_frame() -> impl Strategy<Value = Vec<u8>> {
    (
        select(forge::known_message_ids()),
        vec(any::<u8>(), 0..=255),
        any::<u32>(),
        any::<u8>(),
        prop_oneof![Just(0x02u8), any::<u8>().prop_map(|f| f | 0x02)],
    )
        .prop_map(|(message_id, payload, system_id, component_id, flags)| {
            let id = message_id.to_le_bytes();
            let mut bytes = vec![0xfd, payload.len() as u8, flags, 0, 7];
            bytes.extend_from_slice(&system_id.to_le_bytes());
            bytes.extend_from_slice(&[component_id, id[0], id[1], id[2]]);
            bytes.extend_from_slice(&payload);
            let crc = mavlink::calculate_crc(&bytes[1..], forge::crc_extra(message_id));
            bytes.extend_from_slice(&crc.to_le_bytes());
            if flags & forge::IFLAG_SIGNED != 0 {
                bytes.extend_from_slice(&[0x5a; 13]);
            }
            bytes
        })
}

/// Any single well-formed frame the fuzzer makes.
fn any_frame() -> BoxedStrategy<Vec<u8>> {
    prop_oneof![
        4 => random_frame(),
        4 => acted_on(any_target(), true),
        1 => sysid32_frame(),
    ]
    .boxed()
}

/// (c) Damage done to a datagram.
#[derive(Debug, Clone)]
enum Damage {
    /// Cut the datagram at this fraction of its length.
    Truncate(f64),
    /// Insert these bytes at this fraction of its length.
    Insert(f64, Vec<u8>),
    /// XOR the byte at this fraction of its length.
    Flip(f64, u8),
}

fn damage() -> impl Strategy<Value = Damage> {
    let garbage = prop_oneof![
        vec(any::<u8>(), 0..40),
        vec(Just(0xfdu8), 1..4),
        Just(vec![0xfd, 0xff]),
        Just(vec![0xfe, 9, 0, 255, 190, 0]),
    ];
    prop_oneof![
        (0.0..1.0).prop_map(Damage::Truncate),
        (0.0..=1.0, garbage).prop_map(|(at, bytes)| Damage::Insert(at, bytes)),
        (0.0..1.0, 1u8..).prop_map(|(at, mask)| Damage::Flip(at, mask)),
    ]
}

fn apply(datagram: &mut Vec<u8>, damage: &Damage) {
    let at = |fraction: f64, len: usize| ((len as f64 * fraction) as usize).min(len);
    match damage {
        Damage::Truncate(f) => datagram.truncate(at(*f, datagram.len())),
        Damage::Insert(f, bytes) => {
            let i = at(*f, datagram.len());
            datagram.splice(i..i, bytes.iter().copied());
        }
        Damage::Flip(f, mask) => {
            let i = at(*f, datagram.len());
            if let Some(byte) = datagram.get_mut(i) {
                *byte ^= mask;
            }
        }
    }
}

/// A datagram: several frames back to back, possibly damaged, or pure garbage.
fn datagram() -> BoxedStrategy<Vec<u8>> {
    let frames = (vec(any_frame(), 1..5), vec(damage(), 0..3)).prop_map(|(frames, damage)| {
        let mut bytes = frames.concat();
        for d in &damage {
            apply(&mut bytes, d);
        }
        bytes
    });
    prop_oneof![
        4 => any_frame(),
        3 => frames,
        1 => vec(any::<u8>(), 0..600),
    ]
    .boxed()
}

fn flavour() -> impl Strategy<Value = Flavour> {
    prop_oneof![Just(Flavour::Px4), Just(Flavour::ArduPilot)]
}

/// `cases` per property; `FUZZ_CASES=N` runs N instead, for a deeper local search.
fn config(cases: u32, max_shrink_iters: u32) -> ProptestConfig {
    let cases = std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(cases);
    ProptestConfig {
        cases,
        max_shrink_iters,
        ..ProptestConfig::default()
    }
}

// ------------------------------------------------------------------ properties

#[test]
#[allow(deprecated)] // SET_MODE
fn raw_payload_layouts_match_rust_mavlink() {
    let parse = |message_id, payload: &[u8]| {
        MavMessage::parse(MavlinkVersion::V2, message_id, payload).expect("parses")
    };
    let p7 = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
    let MavMessage::COMMAND_LONG(c) = parse(id::COMMAND_LONG, &command_long_payload(p7, 400, 1, 2))
    else {
        panic!("COMMAND_LONG")
    };
    assert_eq!((c.param1, c.param7), (1.0, 7.0));
    assert_eq!(c.command, MavCmd::MAV_CMD_COMPONENT_ARM_DISARM);
    assert_eq!((c.target_system, c.target_component), (1, 2));
    let payload = command_int_payload([1.0, 2.0, 3.0, 4.0], 5, 6, 7.0, 176, 1, 2, 6);
    let MavMessage::COMMAND_INT(c) = parse(id::COMMAND_INT, &payload) else {
        panic!("COMMAND_INT")
    };
    assert_eq!((c.param4, c.x, c.y, c.z), (4.0, 5, 6, 7.0));
    assert_eq!(c.command, MavCmd::MAV_CMD_DO_SET_MODE);
    assert_eq!((c.target_system, c.target_component), (1, 2));
    assert_eq!(c.frame, MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT);
    let MavMessage::SET_MODE(m) = parse(id::SET_MODE, &set_mode_payload(0x0604_0000, 1, 1)) else {
        panic!("SET_MODE")
    };
    assert_eq!((m.custom_mode, m.target_system), (0x0604_0000, 1));
    assert_eq!(m.base_mode, MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED);
    let mut name = [0u8; 16];
    name[..3].copy_from_slice(b"ABC");
    let MavMessage::PARAM_SET(p) = parse(id::PARAM_SET, &param_set_payload(2.5, 1, 2, name)) else {
        panic!("PARAM_SET")
    };
    assert_eq!(
        (p.param_value, p.target_system, p.target_component),
        (2.5, 1, 2)
    );
    assert_eq!(p.param_id.to_str(), Ok("ABC"));
    let MavMessage::PARAM_REQUEST_READ(p) = parse(
        id::PARAM_REQUEST_READ,
        &param_request_read_payload(-1, 1, 2, name),
    ) else {
        panic!("PARAM_REQUEST_READ")
    };
    assert_eq!((p.param_index, p.target_system), (-1, 1));
    let MavMessage::TIMESYNC(t) = parse(id::TIMESYNC, &timesync_payload(0, 9, 1, 2)) else {
        panic!("TIMESYNC")
    };
    assert_eq!(
        (t.tc1, t.ts1, t.target_system, t.target_component),
        (0, 9, 1, 2)
    );
}

proptest! {
    #![proptest_config(config(192, 2000))]

    /// Random frames, acted-on messages and damaged datagrams, fed to a
    /// vehicle in each starting state and stepped in between.
    #[test]
    fn vehicle_survives_fuzzed_datagrams(
        flavour in flavour(),
        scenario in 0u8..4,
        datagrams in vec(datagram(), 1..40),
    ) {
        let mut v = prepared(flavour, scenario);
        for datagram in &datagrams {
            feed(&mut v, datagram);
            for _ in 0..3 {
                v.step(DT_S);
                check(&v, "after a fuzzed datagram");
            }
        }
        run(&mut v, 3.0);
        still_answers(&mut v);
    }

    /// Messages addressed to another system never change anything: the
    /// whole vehicle (state, outbox, noise generator) compares equal.
    #[test]
    fn messages_for_another_system_change_nothing(
        flavour in flavour(),
        scenario in 0u8..4,
        datagrams in vec(acted_on(foreign_target(), false), 1..30),
    ) {
        let mut v = prepared(flavour, scenario);
        for datagram in &datagrams {
            let before = v.clone();
            for (header, message) in codec::decode(datagram, None).messages {
                v.handle(header, &message);
                prop_assert!(v == before, "{message:?} for another system changed the vehicle");
            }
        }
        still_answers(&mut v);
    }

    /// Frames back to back all decode; a truncated last frame costs only itself.
    #[test]
    fn concatenated_frames_all_decode_and_truncation_costs_one(
        frames in vec(any_frame(), 1..8),
        cut in 1usize..20,
    ) {
        let all = frames.concat();
        let decoded = codec::decode(&all, None);
        // Frames with an unknown incompatibility flag (the 32-bit system id
        // ones) are dropped without a trace, as MAVLink 2 requires.
        let understood = frames.iter().filter(|f| f[2] & !forge::IFLAG_SIGNED == 0).count();
        prop_assert_eq!(decoded.messages.len() + decoded.rejected.len(), understood);
        let last = frames.last().map_or(0, Vec::len);
        let truncated = &all[..all.len() - cut.min(last - 1)];
        let head = codec::decode(&frames[..frames.len() - 1].concat(), None);
        let decoded = codec::decode(truncated, None);
        prop_assert!(decoded.messages.len() >= head.messages.len());
        // Compared as text: NaN fields make `==` false on identical messages.
        prop_assert_eq!(
            format!("{:?}", &decoded.messages[..head.messages.len()]),
            format!("{:?}", head.messages)
        );
    }
}

proptest! {
    #![proptest_config(config(256, 2000))]

    /// With a signing key, nothing forged without the key gets through —
    /// unsigned, flagged-but-garbage, or signed with another key — and
    /// nothing panics on the way.
    #[test]
    fn signed_link_accepts_nothing_forged_without_the_key(
        frames in vec(any_frame(), 1..6),
        resigned in vec((any::<[u8; 32]>(), any::<u8>(), any::<u64>()), 0..3),
        damage in vec(damage(), 0..3),
    ) {
        let signing = codec::Signing::new([0x11; 32]);
        let mut datagram = frames.concat();
        for (key, link_id, timestamp) in &resigned {
            let signature = forge::Signature { key: *key, link_id: *link_id, timestamp: *timestamp };
            let frame = forge::Frame::new(255, 190, 0, 76, &[0; 33]);
            datagram.extend(frame.signed(&signature));
        }
        for d in &damage {
            apply(&mut datagram, d);
        }
        let decoded = codec::decode(&datagram, Some(&signing));
        prop_assert!(decoded.messages.is_empty(), "{:?}", decoded.messages);
    }
}

/// Sends datagrams from a socket of its own and returns what came back.
async fn exchange(
    socket: &tokio::net::UdpSocket,
    to: std::net::SocketAddr,
    datagrams: &[Vec<u8>],
) -> Vec<MavMessage> {
    for datagram in datagrams {
        socket.send_to(datagram, to).await.expect("send");
    }
    let mut replies = Vec::new();
    let mut buffer = [0u8; 2048];
    let deadline = tokio::time::Instant::now() + Duration::from_millis(300);
    while let Ok(Ok((len, _))) =
        tokio::time::timeout_at(deadline, socket.recv_from(&mut buffer)).await
    {
        replies.extend(
            codec::decode(&buffer[..len], None)
                .messages
                .into_iter()
                .map(|(_, m)| m),
        );
    }
    replies
}

proptest! {
    #![proptest_config(config(6, 16))]

    /// End to end over UDP: foreign traffic is never answered and changes
    /// nothing, fuzzed datagrams break nothing, and a ground station can
    /// still command the vehicle afterwards.
    #[test]
    fn udp_vehicle_survives_fuzzed_datagrams(
        flavour in flavour(),
        foreign in vec(acted_on(foreign_target(), false), 5..20),
        datagrams in vec(datagram(), 20..60),
    ) {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("runtime");
        runtime.block_on(async {
            let config = VehicleConfig::new(ME, flavour);
            let swarm = swarmctl_sitl::spawn(LOOPBACK, vec![config], 100.0, 20.0)
                .await
                .expect("spawn");
            let address = swarm.addresses()[0];
            let fuzzer = tokio::net::UdpSocket::bind((LOOPBACK, 0)).await.expect("bind");
            let before = swarm.snapshot(0);
            let replies = exchange(&fuzzer, address, &foreign).await;
            let answers: Vec<_> = replies
                .iter()
                .filter(|m| {
                    matches!(
                        m,
                        MavMessage::COMMAND_ACK(_)
                            | MavMessage::PARAM_VALUE(_)
                            | MavMessage::TIMESYNC(_)
                            | MavMessage::STATUSTEXT(_)
                    )
                })
                .collect();
            assert!(answers.is_empty(), "foreign traffic was answered: {answers:?}");
            let after = swarm.snapshot(0);
            assert_eq!(
                (after.armed, after.mode, after.custom_mode, after.position_ned_m),
                (before.armed, before.mode, before.custom_mode, before.position_ned_m)
            );
            exchange(&fuzzer, address, &datagrams).await;
            tokio::time::sleep(Duration::from_millis(200)).await;
            let s = swarm.snapshot(0);
            let numbers = s.position_ned_m.iter().chain(&s.velocity_ned_mps).chain([&s.yaw_rad]);
            assert!(numbers.copied().all(f32::is_finite), "{s:?}");
            assert!(s.position_ned_m[2] <= 1e-3, "{s:?}");
            let client = Client::connect(address, ME).await;
            assert_eq!(
                client.command(MavCmd::MAV_CMD_REQUEST_MESSAGE, [0.0; 7]).await,
                Some(MavResult::MAV_RESULT_ACCEPTED),
                "still answers a ground station"
            );
            let ticks = swarm.tick_stats().steps;
            tokio::time::sleep(Duration::from_millis(100)).await;
            assert!(swarm.tick_stats().steps > ticks, "physics keeps stepping");
            swarm.shutdown().await;
        });
    }
}
