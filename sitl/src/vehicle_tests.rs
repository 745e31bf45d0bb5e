//! Mode-logic tests: a `Vehicle` driven message by message, without sockets.

use crate::config::{Faults, Flavour, LinkDrop, VehicleConfig};
use crate::dynamics::norm;
use crate::mode::FlightMode;
use crate::vehicle::Vehicle;
use mavlink::MavHeader;
use mavlink::dialects::common::*;
use std::time::Duration;

const DT_S: f64 = 0.01;
const GCS: MavHeader = MavHeader {
    system_id: 255,
    component_id: 190,
    sequence: 0,
};

fn vehicle(flavour: Flavour, faults: Faults) -> Vehicle {
    let mut config = VehicleConfig::new(1, flavour);
    config.faults = faults;
    Vehicle::new(config, 20.0)
}

fn run(v: &mut Vehicle, seconds: f64) {
    for _ in 0..(seconds / DT_S).round() as usize {
        v.step(DT_S);
    }
}

/// Sends a COMMAND_LONG and returns the result of its ACK.
fn command(v: &mut Vehicle, command: MavCmd, params: [f32; 7]) -> MavResult {
    v.outbox.clear();
    let [param1, param2, param3, param4, param5, param6, param7] = params;
    let message = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1,
        param2,
        param3,
        param4,
        param5,
        param6,
        param7,
        command,
        target_system: 1,
        target_component: 1,
        confirmation: 0,
    });
    v.handle(GCS, &message);
    v.outbox
        .iter()
        .find_map(|m| match m {
            MavMessage::COMMAND_ACK(ack) if ack.command == command => Some(ack.result),
            _ => None,
        })
        .expect("every addressed command is acknowledged")
}

fn arm(v: &mut Vehicle) -> MavResult {
    command(
        v,
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
        [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    )
}

fn set_mode(v: &mut Vehicle, main: f32, sub: f32) -> MavResult {
    command(
        v,
        MavCmd::MAV_CMD_DO_SET_MODE,
        [1.0, main, sub, 0.0, 0.0, 0.0, 0.0],
    )
}

fn position_target(v: &mut Vehicle, ned_m: [f32; 3]) {
    let message = MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
        time_boot_ms: 0,
        x: ned_m[0],
        y: ned_m[1],
        z: ned_m[2],
        vx: 0.0,
        vy: 0.0,
        vz: 0.0,
        afx: 0.0,
        afy: 0.0,
        afz: 0.0,
        yaw: 0.0,
        yaw_rate: 0.0,
        type_mask: PositionTargetTypemask::from_bits_truncate(3576), // position only
        target_system: 1,
        target_component: 1,
        coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
    });
    v.handle(GCS, &message);
}

fn velocity_target(v: &mut Vehicle, ned_mps: [f32; 3]) {
    let message = MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
        time_boot_ms: 0,
        x: 0.0,
        y: 0.0,
        z: 0.0,
        vx: ned_mps[0],
        vy: ned_mps[1],
        vz: ned_mps[2],
        afx: 0.0,
        afy: 0.0,
        afz: 0.0,
        yaw: 0.0,
        yaw_rate: 0.0,
        type_mask: PositionTargetTypemask::from_bits_truncate(3527), // velocity only
        target_system: 1,
        target_component: 1,
        coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
    });
    v.handle(GCS, &message);
}

const NAN7: [f32; 7] = [f32::NAN; 7];

#[test]
fn px4_arm_takeoff_hold_land_and_auto_disarm() {
    let mut v = vehicle(Flavour::Px4, Faults::default());
    assert_eq!(v.mode, FlightMode::Hold);
    assert_eq!(
        command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7),
        MavResult::MAV_RESULT_DENIED
    );
    assert_eq!(arm(&mut v), MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(
        command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7),
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(v.mode, FlightMode::Takeoff);
    assert_eq!(v.custom_mode(), 0x0204_0000);
    run(&mut v, 1.0);
    assert_eq!(v.landed_state(), MavLandedState::MAV_LANDED_STATE_TAKEOFF);
    run(&mut v, 9.0);
    assert_eq!(v.mode, FlightMode::Hold, "takeoff ends in Hold");
    assert!(
        (v.body.height_m() - 2.5).abs() < 0.2,
        "height {}",
        v.body.height_m()
    );
    assert_eq!(v.landed_state(), MavLandedState::MAV_LANDED_STATE_IN_AIR);
    // Disarming in the air is refused unless forced.
    assert_eq!(
        command(&mut v, MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, [0.0; 7]),
        MavResult::MAV_RESULT_DENIED
    );
    assert_eq!(
        command(&mut v, MavCmd::MAV_CMD_NAV_LAND, NAN7),
        MavResult::MAV_RESULT_ACCEPTED
    );
    run(&mut v, 2.0);
    assert_eq!(v.landed_state(), MavLandedState::MAV_LANDED_STATE_LANDING);
    run(&mut v, 8.0);
    assert!(v.landed());
    assert!(!v.armed, "PX4 disarms after landing");
}

/// A controller that lowers the landing speed is obeyed, as by real autopilots:
/// the fastest descent during LAND is the parameter's, for either flavour's name
/// and unit.
#[test]
fn land_descends_at_the_landing_speed_parameter() {
    let ardupilot_takeoff = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0];
    for (flavour, name, value, expected_mps, takeoff) in [
        (Flavour::Px4, "MPC_LAND_SPEED", 0.4, 0.4, NAN7),
        (
            Flavour::ArduPilot,
            "LAND_SPEED",
            30.0,
            0.3,
            ardupilot_takeoff,
        ),
    ] {
        let mut v = vehicle(flavour, Faults::default());
        v.params.set(name, value);
        if flavour == Flavour::ArduPilot {
            set_mode(&mut v, 4.0, 0.0); // GUIDED: ArduCopter takes off only there
        }
        arm(&mut v);
        command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, takeoff);
        run(&mut v, 10.0);
        assert!(v.body.height_m() > 2.0, "{flavour:?} took off");
        command(&mut v, MavCmd::MAV_CMD_NAV_LAND, NAN7);
        let mut fastest_mps = 0.0_f32;
        for _ in 0..(30.0 / DT_S).round() as usize {
            v.step(DT_S);
            fastest_mps = fastest_mps.max(v.body.velocity_ned_mps[2]);
        }
        assert!(v.landed(), "{flavour:?} landed");
        assert!(
            (fastest_mps - expected_mps).abs() < 0.02,
            "{flavour:?} descended at up to {fastest_mps} m/s, not {expected_mps}"
        );
    }
}

#[test]
fn px4_takeoff_param7_is_amsl_and_mis_takeoff_alt_is_used() {
    let mut v = vehicle(Flavour::Px4, Faults::default());
    arm(&mut v);
    let home_amsl = v.home.alt_amsl_m as f32;
    let low = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0];
    assert_eq!(
        command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, low),
        MavResult::MAV_RESULT_DENIED
    );
    let ok = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, home_amsl + 4.0];
    assert_eq!(
        command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, ok),
        MavResult::MAV_RESULT_ACCEPTED
    );
    run(&mut v, 8.0);
    assert!((v.body.height_m() - 4.0).abs() < 0.2);
}

#[test]
fn px4_offboard_needs_a_stream_and_fails_safe_when_it_stops() {
    let mut v = vehicle(Flavour::Px4, Faults::default());
    arm(&mut v);
    assert_eq!(
        set_mode(&mut v, 6.0, 0.0),
        MavResult::MAV_RESULT_TEMPORARILY_REJECTED
    );
    // Two setpoints in one second are not "more than 2 Hz".
    position_target(&mut v, [0.0, 0.0, -3.0]);
    run(&mut v, 0.4);
    position_target(&mut v, [0.0, 0.0, -3.0]);
    assert_eq!(
        set_mode(&mut v, 6.0, 0.0),
        MavResult::MAV_RESULT_TEMPORARILY_REJECTED
    );
    for _ in 0..10 {
        position_target(&mut v, [0.0, 0.0, -3.0]);
        run(&mut v, 0.1);
    }
    assert_eq!(set_mode(&mut v, 6.0, 0.0), MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(v.custom_mode(), 0x0006_0000);
    for _ in 0..60 {
        position_target(&mut v, [2.0, 1.0, -3.0]);
        run(&mut v, 0.1);
    }
    assert!(
        (v.body.position_ned_m[0] - 2.0).abs() < 0.1,
        "{:?}",
        v.body.position_ned_m
    );
    // Stream stops: hold after 1 s, land after the configured 5 s more.
    run(&mut v, 0.9);
    assert_eq!(v.mode, FlightMode::Offboard);
    run(&mut v, 0.2);
    assert_eq!(v.mode, FlightMode::Hold);
    run(&mut v, 4.8);
    assert_eq!(v.mode, FlightMode::Hold);
    run(&mut v, 0.3);
    assert_eq!(v.mode, FlightMode::Land);
}

#[test]
fn refused_arming_is_denied_with_a_reason() {
    let mut v = vehicle(
        Flavour::Px4,
        Faults {
            refuse_arm: true,
            ..Faults::default()
        },
    );
    assert_eq!(arm(&mut v), MavResult::MAV_RESULT_DENIED);
    assert!(!v.armed);
    assert!(v.outbox.iter().any(|m| matches!(m, MavMessage::STATUSTEXT(t) if t.text.to_str().is_ok_and(|s| s.contains("Arming denied")))));
}

#[test]
fn commands_for_other_systems_or_components_are_ignored() {
    let mut v = vehicle(Flavour::Px4, Faults::default());
    for (system, component) in [(2, 1), (1, 100)] {
        let message = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            param1: 1.0,
            command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            target_system: system,
            target_component: component,
            ..COMMAND_LONG_DATA::default()
        });
        v.handle(GCS, &message);
    }
    assert!(v.outbox.is_empty());
    assert!(!v.armed);
}

#[test]
fn ardupilot_takeoff_only_in_guided_and_armed_then_targets_and_velocity_timeout() {
    let mut v = vehicle(Flavour::ArduPilot, Faults::default());
    assert_eq!(v.custom_mode(), 0, "boots in STABILIZE");
    let takeoff = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0];
    assert_eq!(arm(&mut v), MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(
        command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, takeoff),
        MavResult::MAV_RESULT_FAILED
    );
    assert_eq!(set_mode(&mut v, 4.0, 0.0), MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(v.custom_mode(), 4);
    assert_eq!(
        command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, takeoff),
        MavResult::MAV_RESULT_ACCEPTED
    );
    run(&mut v, 6.0);
    assert!(
        (v.body.height_m() - 3.0).abs() < 0.2,
        "height {}",
        v.body.height_m()
    );
    position_target(&mut v, [3.0, 0.0, -3.0]);
    run(&mut v, 6.0);
    assert!((v.body.position_ned_m[0] - 3.0).abs() < 0.1);
    // A velocity target is followed, then replaced by a stop after 3 s.
    velocity_target(&mut v, [1.0, 0.0, 0.0]);
    run(&mut v, 2.5);
    assert!(v.body.velocity_ned_mps[0] > 0.9);
    run(&mut v, 1.5);
    assert!(v.body.velocity_ned_mps[0] < 0.9);
    run(&mut v, 3.0);
    assert!(
        v.body.velocity_ned_mps[0].abs() < 0.05,
        "stopped after timeout"
    );
    // LOITER, then RTL comes home and lands.
    assert_eq!(set_mode(&mut v, 5.0, 0.0), MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(set_mode(&mut v, 6.0, 0.0), MavResult::MAV_RESULT_ACCEPTED);
    run(&mut v, 25.0);
    assert!(v.landed() && !v.armed);
    let p = v.body.position_ned_m;
    assert!(
        p[0].abs() < 0.35 && p[1].abs() < 0.35,
        "landed at home, {p:?}"
    );
    // Copter cannot arm in RTL.
    assert_eq!(arm(&mut v), MavResult::MAV_RESULT_DENIED);
}

fn status_texts(v: &Vehicle) -> Vec<(MavSeverity, String)> {
    v.outbox
        .iter()
        .filter_map(|m| match m {
            MavMessage::STATUSTEXT(t) => Some((t.severity, t.text.to_str().ok()?.to_owned())),
            _ => None,
        })
        .collect()
}

fn sys_status_remaining(v: &mut Vehicle) -> i8 {
    match v.build_message(1) {
        Some(MavMessage::SYS_STATUS(s)) => s.battery_remaining,
        other => panic!("SYS_STATUS expected, got {other:?}"),
    }
}

fn charge_state(v: &mut Vehicle) -> MavBatteryChargeState {
    match v.build_message(147) {
        Some(MavMessage::BATTERY_STATUS(b)) => b.charge_state,
        other => panic!("BATTERY_STATUS expected, got {other:?}"),
    }
}

#[test]
fn low_battery_only_warns_then_critical_lands_px4_and_returns_ardupilot() {
    let faults = Faults {
        low_battery_after: Some(Duration::from_secs(4)),
        critical_battery_after: Some(Duration::from_secs(8)),
        ..Faults::default()
    };
    let mut px4 = vehicle(Flavour::Px4, faults.clone());
    assert_eq!(sys_status_remaining(&mut px4), 100);
    arm(&mut px4);
    command(&mut px4, MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7);
    px4.outbox.clear();
    run(&mut px4, 3.9);
    assert!(!px4.battery_low);
    assert_eq!(
        charge_state(&mut px4),
        MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_OK
    );
    assert!(status_texts(&px4).is_empty());
    run(&mut px4, 0.2);
    // LOW: a warning, nothing else changes.
    assert!(px4.battery_low && !px4.battery_critical);
    assert_eq!(px4.mode, FlightMode::Hold);
    assert!(sys_status_remaining(&mut px4) <= 25);
    assert_eq!(
        charge_state(&mut px4),
        MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_LOW
    );
    let texts = status_texts(&px4);
    assert_eq!(texts.len(), 1, "{texts:?}");
    assert_eq!(texts[0].0, MavSeverity::MAV_SEVERITY_WARNING);
    assert!(texts[0].1.starts_with("Low battery"), "{texts:?}");
    run(&mut px4, 3.7);
    assert!(!px4.battery_critical && px4.mode == FlightMode::Hold);
    assert_eq!(status_texts(&px4).len(), 1, "the warning is sent once");
    run(&mut px4, 0.3);
    assert!(px4.battery_critical);
    assert_eq!(px4.mode, FlightMode::Land);
    assert!(sys_status_remaining(&mut px4) <= 8);
    assert_eq!(
        charge_state(&mut px4),
        MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_CRITICAL
    );
    assert!(status_texts(&px4).iter().any(|(severity, text)| {
        *severity == MavSeverity::MAV_SEVERITY_CRITICAL && text.contains("Critical battery")
    }));

    let mut ap = vehicle(Flavour::ArduPilot, faults);
    set_mode(&mut ap, 4.0, 0.0);
    arm(&mut ap);
    command(
        &mut ap,
        MavCmd::MAV_CMD_NAV_TAKEOFF,
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0],
    );
    run(&mut ap, 4.1);
    assert!(ap.battery_low && !ap.battery_critical);
    assert_eq!(ap.mode, FlightMode::Guided, "a low battery does not RTL");
    run(&mut ap, 4.0);
    assert!(ap.battery_critical);
    assert_eq!(ap.mode, FlightMode::ReturnToLaunch);
    assert_eq!(ap.custom_mode(), 6);
}

#[test]
fn critical_battery_alone_is_todays_failsafe_and_blocks_arming() {
    let faults = Faults {
        critical_battery_after: Some(Duration::from_secs(2)),
        ..Faults::default()
    };
    let mut v = vehicle(Flavour::Px4, faults);
    arm(&mut v);
    command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7);
    run(&mut v, 2.1);
    assert!(v.battery_critical && v.battery_low);
    assert_eq!(v.mode, FlightMode::Land);
    run(&mut v, 15.0);
    assert!(!v.armed, "landed and disarmed");
    assert_eq!(arm(&mut v), MavResult::MAV_RESULT_DENIED);
}

#[test]
fn low_battery_alone_never_lands_and_arming_stays_allowed() {
    let faults = Faults {
        low_battery_after: Some(Duration::from_secs(1)),
        ..Faults::default()
    };
    let mut v = vehicle(Flavour::Px4, faults);
    arm(&mut v);
    command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7);
    run(&mut v, 20.0);
    assert!(v.battery_low && !v.battery_critical);
    assert_eq!(v.mode, FlightMode::Hold);
    assert!(v.airborne());
    command(&mut v, MavCmd::MAV_CMD_NAV_LAND, NAN7);
    run(&mut v, 15.0);
    assert!(!v.armed);
    assert_eq!(arm(&mut v), MavResult::MAV_RESULT_ACCEPTED);
}

#[test]
fn sys_status_reports_battery_remaining_draining_from_100() {
    let mut v = vehicle(Flavour::Px4, Faults::default());
    run(&mut v, 5.0);
    assert_eq!(sys_status_remaining(&mut v), 100, "no drain while disarmed");
    arm(&mut v);
    command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7);
    let mut last = 100;
    for _ in 0..6 {
        run(&mut v, 20.0);
        let now = sys_status_remaining(&mut v);
        assert!(
            (0..=100).contains(&now) && now <= last,
            "{now} after {last}"
        );
        last = now;
    }
    assert!(last < 100, "drains while armed: {last}");
}

#[test]
fn offboard_loss_hold_forever_with_duration_max() {
    let mut config = VehicleConfig::new(1, Flavour::Px4);
    config.offboard_loss_land_after = Duration::MAX;
    let mut v = Vehicle::new(config, 20.0);
    arm(&mut v);
    for _ in 0..10 {
        position_target(&mut v, [0.0, 0.0, -3.0]);
        run(&mut v, 0.1);
    }
    assert_eq!(set_mode(&mut v, 6.0, 0.0), MavResult::MAV_RESULT_ACCEPTED);
    for _ in 0..50 {
        position_target(&mut v, [0.0, 0.0, -3.0]);
        run(&mut v, 0.1);
    }
    run(&mut v, 1.5);
    assert_eq!(v.mode, FlightMode::Hold);
    run(&mut v, 120.0);
    assert_eq!(v.mode, FlightMode::Hold, "holds for good");
    assert!(v.armed && (v.body.height_m() - 3.0).abs() < 0.1);
}

#[test]
fn ardupilot_guided_holds_when_the_setpoint_stream_stops() {
    let mut v = vehicle(Flavour::ArduPilot, Faults::default());
    set_mode(&mut v, 4.0, 0.0);
    arm(&mut v);
    command(
        &mut v,
        MavCmd::MAV_CMD_NAV_TAKEOFF,
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0],
    );
    run(&mut v, 5.0);
    position_target(&mut v, [4.0, 0.0, -3.0]);
    run(&mut v, 60.0);
    assert_eq!(v.mode, FlightMode::Guided, "no failsafe: FS_GCS_ENABLE = 0");
    assert!(v.armed);
    let p = v.body.position_ned_m;
    assert!(
        (p[0] - 4.0).abs() < 0.1 && (p[2] + 3.0).abs() < 0.1,
        "holds at the last target: {p:?}"
    );
    // A velocity target times out after 3 s and the vehicle stops there.
    velocity_target(&mut v, [1.0, 0.0, 0.0]);
    run(&mut v, 60.0);
    assert_eq!(v.mode, FlightMode::Guided);
    assert!(v.body.position_ned_m[0] < 4.0 + 3.5 + 1.0, "stopped");
    assert!(norm(v.body.velocity_ned_mps) < 0.01);
}

/// A crash stops the motors: the vehicle falls straight down, lies on the ground
/// below where it was (still armed: nobody disarmed it), and never speaks again.
#[test]
fn a_crashed_vehicle_falls_to_the_ground_below_it_and_stays_silent() {
    let faults = Faults {
        crash_after_takeoff: Some(Duration::from_secs(3)),
        ..Faults::default()
    };
    let mut v = vehicle(Flavour::Px4, faults);
    arm(&mut v);
    command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7);
    run(&mut v, 2.5);
    assert!(v.airborne() && !v.crashed() && !v.link_down());
    let above = v.body.position_ned_m;
    run(&mut v, 1.0);
    assert!(v.crashed() && v.link_down());
    run(&mut v, 5.0);
    let p = v.body.position_ned_m;
    assert!(v.landed(), "on the ground: {p:?}");
    assert!(
        (p[0] - above[0]).abs() < 0.05 && (p[1] - above[1]).abs() < 0.05,
        "straight down from {above:?}, lies at {p:?}"
    );
    assert!(v.link_down(), "silent for good");
}

#[test]
fn permanent_link_drop_never_comes_back() {
    let faults = Faults {
        link_drop: Some(LinkDrop::permanent(Duration::from_secs(1))),
        ..Faults::default()
    };
    let mut v = vehicle(Flavour::Px4, faults);
    arm(&mut v);
    command(&mut v, MavCmd::MAV_CMD_NAV_TAKEOFF, NAN7);
    run(&mut v, 0.5);
    assert!(v.first_airborne_s.is_some() && !v.link_down());
    run(&mut v, 1.0);
    assert!(v.link_down());
    for time_s in [1e3, 1e9, 1e15, f64::from(f32::MAX)] {
        v.time_s = time_s;
        assert!(v.link_down(), "down at {time_s} s");
    }
    // Both fields at their maximum: still no overflow, and never down.
    let mut late = vehicle(
        Flavour::Px4,
        Faults {
            link_drop: Some(LinkDrop {
                after_takeoff: Duration::MAX,
                duration: Duration::MAX,
            }),
            ..Faults::default()
        },
    );
    late.first_airborne_s = Some(0.0);
    late.time_s = 1e12;
    assert!(!late.link_down());
}

#[test]
fn requests_intervals_params_and_timesync_are_answered() {
    let mut v = vehicle(Flavour::Px4, Faults::default());
    assert_eq!(
        command(
            &mut v,
            MavCmd::MAV_CMD_REQUEST_MESSAGE,
            [148.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
        ),
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert!(
        v.outbox
            .iter()
            .any(|m| matches!(m, MavMessage::AUTOPILOT_VERSION(_)))
    );
    assert_eq!(
        command(
            &mut v,
            MavCmd::MAV_CMD_REQUEST_MESSAGE,
            [242.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
        ),
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert!(
        v.outbox
            .iter()
            .any(|m| matches!(m, MavMessage::HOME_POSITION(_)))
    );
    assert_eq!(
        command(
            &mut v,
            MavCmd::MAV_CMD_REQUEST_MESSAGE,
            [9999.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
        ),
        MavResult::MAV_RESULT_UNSUPPORTED
    );
    assert_eq!(
        command(
            &mut v,
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
            [32.0, 200_000.0, 0.0, 0.0, 0.0, 0.0, 0.0]
        ),
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(v.streams.period_s(32), Some(0.2));
    v.outbox.clear();
    v.handle(
        GCS,
        &MavMessage::PARAM_SET(PARAM_SET_DATA {
            param_value: 3.5,
            target_system: 1,
            target_component: 1,
            param_id: "MIS_TAKEOFF_ALT".into(),
            param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
        }),
    );
    assert!(matches!(v.outbox.as_slice(), [MavMessage::PARAM_VALUE(p)] if p.param_value == 3.5));
    v.outbox.clear();
    v.handle(
        GCS,
        &MavMessage::TIMESYNC(TIMESYNC_DATA {
            tc1: 0,
            ts1: 42,
            target_system: 0,
            target_component: 0,
        }),
    );
    assert!(
        matches!(v.outbox.as_slice(), [MavMessage::TIMESYNC(t)] if t.ts1 == 42 && t.target_system == 255)
    );
}

#[test]
fn heartbeat_reports_armed_and_mode_explicitly() {
    let mut v = vehicle(Flavour::Px4, Faults::default());
    let Some(MavMessage::HEARTBEAT(hb)) = v.build_message(0) else {
        panic!("no heartbeat")
    };
    assert!(
        !hb.base_mode
            .contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED)
    );
    assert!(
        hb.base_mode
            .contains(MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED)
    );
    assert_eq!(hb.autopilot, MavAutopilot::MAV_AUTOPILOT_PX4);
    arm(&mut v);
    let Some(MavMessage::HEARTBEAT(hb)) = v.build_message(0) else {
        panic!("no heartbeat")
    };
    assert!(
        hb.base_mode
            .contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED)
    );
    assert_eq!(hb.custom_mode, 0x0304_0000);
}

#[test]
fn takeoff_mode_while_disarmed_stays_on_ground_until_armed() {
    let mut v = vehicle(Flavour::Px4, Faults::default());
    assert_eq!(set_mode(&mut v, 4.0, 2.0), MavResult::MAV_RESULT_ACCEPTED);
    run(&mut v, 1.0);
    assert!(v.landed());
    assert_eq!(v.landed_state(), MavLandedState::MAV_LANDED_STATE_ON_GROUND);
    arm(&mut v);
    run(&mut v, 8.0);
    assert!((v.body.height_m() - 2.5).abs() < 0.2);
}

#[test]
fn ardupilot_reentering_guided_does_not_chase_an_old_target() {
    let mut v = vehicle(Flavour::ArduPilot, Faults::default());
    set_mode(&mut v, 4.0, 0.0);
    arm(&mut v);
    command(
        &mut v,
        MavCmd::MAV_CMD_NAV_TAKEOFF,
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0],
    );
    run(&mut v, 5.0);
    position_target(&mut v, [5.0, 0.0, -2.0]);
    run(&mut v, 1.0);
    set_mode(&mut v, 5.0, 0.0); // LOITER: brake and hold
    run(&mut v, 3.0);
    let held = v.body.position_ned_m;
    set_mode(&mut v, 4.0, 0.0); // back to GUIDED without a new target
    run(&mut v, 3.0);
    assert!(
        crate::dynamics::norm(std::array::from_fn(|i| v.body.position_ned_m[i] - held[i])) < 0.1
    );
}

#[test]
fn global_int_targets_map_into_the_shared_local_frame() {
    let mut config = VehicleConfig::new(1, Flavour::ArduPilot);
    config = config.at(crate::geo::GeoPoint::default(), [10.0, -4.0, 0.0]);
    let mut v = Vehicle::new(config, 20.0);
    set_mode(&mut v, 4.0, 0.0);
    arm(&mut v);
    command(
        &mut v,
        MavCmd::MAV_CMD_NAV_TAKEOFF,
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0],
    );
    run(&mut v, 5.0);
    let goal = v.home.offset_ned([3.0, 4.0, 0.0]);
    #[allow(deprecated)] // the _INT frame is what clients put in this message
    let frame = MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT;
    v.handle(
        GCS,
        &MavMessage::SET_POSITION_TARGET_GLOBAL_INT(SET_POSITION_TARGET_GLOBAL_INT_DATA {
            lat_int: goal.lat_e7(),
            lon_int: goal.lon_e7(),
            alt: 3.0,
            type_mask: PositionTargetTypemask::from_bits_truncate(3576),
            target_system: 1,
            target_component: 1,
            coordinate_frame: frame,
            ..SET_POSITION_TARGET_GLOBAL_INT_DATA::default()
        }),
    );
    run(&mut v, 8.0);
    let p = v.body.position_ned_m;
    // Home is at (10, -4, 0) in the shared frame; degE7 rounding is ~1 cm.
    assert!(
        (p[0] - 13.0).abs() < 0.05 && (p[1] - 0.0).abs() < 0.05 && (p[2] + 3.0).abs() < 0.05,
        "{p:?}"
    );
}

#[test]
fn sensor_noise_is_deterministic_per_seed() {
    let sample = |seed: u64| {
        let mut config = VehicleConfig::new(1, Flavour::Px4);
        config.seed = seed;
        let mut v = Vehicle::new(config, 20.0);
        (0..5)
            .map(|_| format!("{:?}", v.build_message(32)))
            .collect::<Vec<_>>()
    };
    assert_eq!(sample(9), sample(9));
    assert_ne!(sample(9), sample(10));
}

#[test]
#[allow(deprecated)] // SET_MODE
fn set_mode_message_changes_mode_like_the_command() {
    let set_mode = |target_system: u8, custom_mode: u32| {
        MavMessage::SET_MODE(SET_MODE_DATA {
            custom_mode,
            target_system,
            base_mode: MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED,
        })
    };
    let mut px4 = vehicle(Flavour::Px4, Faults::default());
    px4.handle(GCS, &set_mode(1, 0x0604_0000));
    assert_eq!(px4.mode, FlightMode::Land);
    px4.handle(GCS, &set_mode(2, 0x0304_0000));
    assert_eq!(px4.mode, FlightMode::Land, "another system's SET_MODE");
    px4.handle(GCS, &set_mode(1, 0x0006_0000));
    assert_eq!(px4.mode, FlightMode::Land, "OFFBOARD still needs a stream");
    let mut ap = vehicle(Flavour::ArduPilot, Faults::default());
    ap.handle(GCS, &set_mode(1, 4));
    assert_eq!(ap.mode, FlightMode::Guided);
    ap.handle(GCS, &set_mode(1, u32::MAX));
    assert_eq!(ap.mode, FlightMode::Guided);
}

#[test]
fn timesync_requests_for_another_system_are_not_answered() {
    // Found by the receive-path fuzzer: requests were answered whatever
    // their target, and a reply at boot carried tc1 = 0 (a request).
    let mut v = vehicle(Flavour::Px4, Faults::default());
    let request = |target_system, target_component| {
        MavMessage::TIMESYNC(TIMESYNC_DATA {
            tc1: 0,
            ts1: 7,
            target_system,
            target_component,
        })
    };
    for (system, component) in [(2, 1), (200, 0), (1, 50)] {
        v.handle(GCS, &request(system, component));
        assert!(
            v.outbox.is_empty(),
            "answered a request for {system}/{component}"
        );
    }
    v.handle(GCS, &request(1, 1));
    assert!(matches!(v.outbox.as_slice(), [MavMessage::TIMESYNC(t)] if t.tc1 > 0 && t.ts1 == 7));
}

/// Sets parameter `name` as a ground station does, the value in the float field
/// as the firmware encodes it.
fn set_param(v: &mut Vehicle, name: &str, value: f32, param_type: MavParamType) {
    v.handle(
        GCS,
        &MavMessage::PARAM_SET(PARAM_SET_DATA {
            param_value: value,
            target_system: v.system_id,
            target_component: 1,
            param_id: name.into(),
            param_type,
        }),
    );
}

/// Each firmware's fence, set by its own parameters: a vehicle flown past its
/// circle announces the breach once and lands (PX4 `GF_ACTION` 5 as an INT32's
/// bits, ArduPilot `FENCE_ACTION` 2); the rogue ground station that sent it there
/// cannot keep it.
#[test]
fn a_vehicle_past_its_fence_announces_the_breach_and_lands() {
    for flavour in Flavour::ALL {
        let faults = Faults {
            rogue_after_takeoff: Some(Duration::from_secs(4)),
            ..Faults::default()
        };
        let mut v = vehicle(flavour, faults);
        let real = MavParamType::MAV_PARAM_TYPE_REAL32;
        match flavour {
            Flavour::Px4 => {
                set_param(&mut v, "GF_MAX_HOR_DIST", 6.0, real);
                set_param(&mut v, "GF_MAX_VER_DIST", 10.0, real);
                let land = f32::from_bits(5);
                set_param(
                    &mut v,
                    "GF_ACTION",
                    land,
                    MavParamType::MAV_PARAM_TYPE_INT32,
                );
            }
            Flavour::ArduPilot => {
                for (name, value) in [
                    ("FENCE_TYPE", 3.0),
                    ("FENCE_ACTION", 2.0),
                    ("FENCE_ALT_MAX", 10.0),
                    ("FENCE_RADIUS", 6.0),
                    ("FENCE_ENABLE", 1.0),
                ] {
                    set_param(&mut v, name, value, real);
                }
            }
        }
        let home = v.body.position_ned_m;
        match flavour {
            Flavour::Px4 => {
                assert_eq!(arm(&mut v), MavResult::MAV_RESULT_ACCEPTED);
                for _ in 0..30 {
                    position_target(&mut v, [home[0], home[1], -3.0]);
                    run(&mut v, 0.05);
                }
                assert_eq!(set_mode(&mut v, 6.0, 0.0), MavResult::MAV_RESULT_ACCEPTED);
                for _ in 0..60 {
                    position_target(&mut v, [home[0], home[1], -3.0]);
                    run(&mut v, 0.05);
                }
            }
            Flavour::ArduPilot => {
                set_mode(&mut v, 4.0, 0.0);
                assert_eq!(arm(&mut v), MavResult::MAV_RESULT_ACCEPTED);
                command(
                    &mut v,
                    MavCmd::MAV_CMD_NAV_TAKEOFF,
                    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0],
                );
                run(&mut v, 3.0);
            }
        }
        assert!(v.airborne(), "{flavour:?} took off");
        let mut farthest_m = 0.0f32;
        for _ in 0..600 {
            // The controller keeps streaming its own hold: the rogue wins.
            position_target(&mut v, [home[0], home[1], -3.0]);
            run(&mut v, 0.05);
            let p = v.body.position_ned_m;
            farthest_m = farthest_m.max((p[0] - home[0]).hypot(p[1] - home[1]));
        }
        let breaches = status_texts(&v)
            .into_iter()
            .filter(|(_, text)| text.to_ascii_lowercase().contains("fence"))
            .count();
        assert_eq!(breaches, 1, "{flavour:?}: {:?}", status_texts(&v));
        // Past the fence by at most its braking distance at full speed.
        let braking_m = v.limits.max_speed_mps.powi(2) / (2.0 * v.limits.max_accel_mps2);
        assert!(
            farthest_m > 6.0 && farthest_m < 6.0 + braking_m + 0.1,
            "{flavour:?}: stopped at its fence, farthest {farthest_m} m (braking {braking_m} m)"
        );
        let p = v.body.position_ned_m;
        assert!(
            v.landed() && !v.armed,
            "{flavour:?} landed and disarmed, at {p:?} in mode {:?}",
            v.mode
        );
    }
}
