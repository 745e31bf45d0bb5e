//! The controller's receive path as a pure function: one decoded MAVLink
//! message in, the vehicle's [`VehicleState`] updated (or deliberately not).
//!
//! [`fold`] is what the session's reader task calls for every frame the
//! connection decodes; keeping it free of I/O lets tests (and the fuzz harness in
//! `tests/fuzz_link.rs`) drive it with hostile input directly. The rules, in the
//! order they are applied:
//!
//! 1. **Only the vehicle we fly.** A message whose header names any system other
//!    than `system_id` is dropped before anything is touched: a stray vehicle, a
//!    second ground station or a forged frame from another id cannot change the
//!    state, not even the link-alive clock.
//! 2. **Any message from that system proves the link is alive**
//!    ([`VehicleState::last_message`]), even one whose content is refused below:
//!    the bytes did cross the link.
//! 3. **What the executor steers by comes from the autopilot component**
//!    ([`AUTOPILOT_COMPONENT_ID`]): HEARTBEAT (armed, mode, autopilot family),
//!    LOCAL_POSITION_NED, EXTENDED_SYS_STATE and SYS_STATUS. A companion computer
//!    or a camera on the same system id cannot arm, move or land the drone in our
//!    bookkeeping.
//! 4. **Positions must be finite and not older than the newest one seen.** A NaN
//!    or infinite LOCAL_POSITION_NED sample is ignored. A sample whose
//!    `time_boot_ms` is older than the newest one accepted is a reordered or
//!    replayed packet and is ignored, so the drone never jumps backwards in our
//!    view. A sample with the *same* `time_boot_ms` is accepted (a duplicate
//!    carries the same data, and an autopilot that leaves the field at 0 must
//!    still be followed). A jump back of more than [`REBOOT_BACKSTEP_MS`] is taken
//!    as an autopilot reboot (or the 49-day wrap of the counter) and accepted; a
//!    reboot that happens within the first [`REBOOT_BACKSTEP_MS`] of the previous
//!    boot therefore freezes the position until the new clock passes the old one.
//! 5. **COMMAND_ACKs only from that system and addressed to us.** With the MAVLink
//!    2 extension fields present, `target_system` must be our ground-station id
//!    ([`GCS_SYSTEM_ID`]) and `target_component` ours ([`GCS_COMPONENT_ID`]); 0 is
//!    also accepted for both, because that is what a MAVLink 1 sender or an
//!    autopilot that omits the extensions decodes to. The ACK is returned for the
//!    caller to hand to whoever waits on a command; it is not part of the state.

use super::messages::{AUTOPILOT_COMPONENT_ID, GCS_COMPONENT_ID, GCS_SYSTEM_ID};
use super::telemetry::{PositionSample, VehicleState};
use crate::mission::Geodetic;
use mavlink::dialects::common::{
    COMMAND_ACK_DATA, MavMessage, MavModeFlag, MavParamType, MavSysStatusSensor,
};
use mavlink::{MavHeader, Message};
use std::time::Instant;

/// A LOCAL_POSITION_NED `time_boot_ms` this far (or further) behind the newest one
/// accepted is taken as an autopilot reboot rather than a late packet.
pub const REBOOT_BACKSTEP_MS: u32 = 10_000;

/// Folds one received message into `state`; returns the COMMAND_ACK to hand to a
/// waiting command, if the message is one that is meant for us.
///
/// `system_id` is the vehicle this session flies and `now` the arrival time. See
/// the module documentation for what is accepted and what is ignored. Never
/// panics, whatever the message holds.
pub fn fold(
    state: &mut VehicleState,
    header: &MavHeader,
    message: MavMessage,
    system_id: u8,
    now: Instant,
) -> Option<COMMAND_ACK_DATA> {
    if header.system_id != u32::from(system_id) {
        return None;
    }
    state.last_message = Some(now);
    let from_autopilot = header.component_id == AUTOPILOT_COMPONENT_ID;
    if from_autopilot {
        // Bounded: one entry per message id the dialect knows.
        let seen = state.messages_seen.entry(message.message_id()).or_default();
        *seen = seen.saturating_add(1);
    }
    match message {
        MavMessage::HEARTBEAT(h) if from_autopilot => {
            state.last_heartbeat = Some(now);
            state.autopilot = Some(h.autopilot);
            state.armed = h
                .base_mode
                .contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED);
            state.custom_mode = h.custom_mode;
        }
        MavMessage::LOCAL_POSITION_NED(p) if from_autopilot => {
            let position_ned_m = [p.x, p.y, p.z];
            let velocity_ned_mps = [p.vx, p.vy, p.vz];
            let finite = position_ned_m
                .iter()
                .chain(&velocity_ned_mps)
                .all(|c| c.is_finite());
            if !finite || is_stale(state.position_time_boot_ms, p.time_boot_ms) {
                return None;
            }
            state.position_time_boot_ms = Some(p.time_boot_ms);
            let sample = PositionSample {
                received: now,
                position_ned_m,
                velocity_ned_mps,
            };
            state.position = Some(sample);
            if state.recording {
                state.track.push(sample);
            }
        }
        MavMessage::EXTENDED_SYS_STATE(e) if from_autopilot => {
            state.landed_state = Some(e.landed_state);
        }
        MavMessage::SYS_STATUS(st) if from_autopilot => {
            let check = MavSysStatusSensor::MAV_SYS_STATUS_PREARM_CHECK;
            state.prearm_ok = Some(
                !st.onboard_control_sensors_present.contains(check)
                    || st.onboard_control_sensors_health.contains(check),
            );
            // -1 means "not sent"; anything else outside 0..=100 is nonsense.
            state.battery_remaining_pct = (0..=100)
                .contains(&st.battery_remaining)
                .then_some(st.battery_remaining);
        }
        MavMessage::GPS_GLOBAL_ORIGIN(o) if from_autopilot => {
            state.gps_origin = geodetic(o.latitude, o.longitude, o.altitude).or(state.gps_origin);
        }
        MavMessage::HOME_POSITION(h) if from_autopilot => {
            state.home = geodetic(h.latitude, h.longitude, h.altitude).or(state.home);
        }
        // PX4 sends an INT32's bits in the float field (-1 reads as a NaN).
        MavMessage::PARAM_VALUE(v)
            if from_autopilot
                && (v.param_value.is_finite()
                    || v.param_type == MavParamType::MAV_PARAM_TYPE_INT32) =>
        {
            if let Ok(name) = v.param_id.to_str() {
                state.params.insert(name.to_string(), v.param_value);
            }
        }
        MavMessage::STATUSTEXT(t) => {
            state.last_status_text = t.text.to_str().ok().map(str::to_string);
            if let Some(text) = &state.last_status_text
                && is_prearm_reason(text)
            {
                state.prearm_reason = Some(text.clone());
            }
            if let Some(text) = &state.last_status_text
                && text.to_ascii_lowercase().contains("fence")
            {
                state.fence_text = Some(text.clone());
            }
        }
        MavMessage::COMMAND_ACK(a) if addressed_to_us(&a) => return Some(a),
        _ => {}
    }
    None
}

/// A geodetic point from MAVLink's degE7 / millimetre fields; `None` when the
/// latitude or longitude is out of range (as an unset origin reports 0, 0 it is
/// accepted: no field has a drone there, and pre-flight would refuse it).
fn geodetic(lat_e7: i32, lon_e7: i32, alt_mm: i32) -> Option<Geodetic> {
    let (lat_deg, lon_deg) = (f64::from(lat_e7) / 1e7, f64::from(lon_e7) / 1e7);
    ((-90.0..=90.0).contains(&lat_deg) && (-180.0..=180.0).contains(&lon_deg)).then_some(Geodetic {
        lat_deg,
        lon_deg,
        alt_m: f64::from(alt_mm) / 1000.0,
    })
}

/// A STATUSTEXT explaining a pre-arm failure: ArduPilot's "PreArm: …" and PX4's
/// "Preflight Fail: …" (either case).
fn is_prearm_reason(text: &str) -> bool {
    let lower = text.to_ascii_lowercase();
    lower.starts_with("prearm") || lower.starts_with("preflight fail")
}

/// A sample stamped `time_boot_ms` is older than the newest accepted one, and not
/// so much older that it must be a reboot.
fn is_stale(newest_ms: Option<u32>, time_boot_ms: u32) -> bool {
    newest_ms
        .is_some_and(|newest| time_boot_ms < newest && newest - time_boot_ms < REBOOT_BACKSTEP_MS)
}

/// The ACK's extension fields name us, or are absent (decoded as 0).
fn addressed_to_us(ack: &COMMAND_ACK_DATA) -> bool {
    matches!(ack.target_system, 0 | GCS_SYSTEM_ID)
        && matches!(ack.target_component, 0 | GCS_COMPONENT_ID)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::{
        EXTENDED_SYS_STATE_DATA, HEARTBEAT_DATA, LOCAL_POSITION_NED_DATA, MavAutopilot, MavCmd,
        MavLandedState, MavResult, MavState, MavType, MavVtolState, SYS_STATUS_DATA,
    };
    use std::time::Duration;

    const VEHICLE: u8 = 3;

    fn header(system_id: u32, component_id: u8) -> MavHeader {
        MavHeader {
            system_id,
            component_id,
            sequence: 0,
        }
    }

    fn autopilot() -> MavHeader {
        header(u32::from(VEHICLE), AUTOPILOT_COMPONENT_ID)
    }

    fn heartbeat(armed: bool, custom_mode: u32) -> MavMessage {
        MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode,
            mavtype: MavType::MAV_TYPE_QUADROTOR,
            autopilot: MavAutopilot::MAV_AUTOPILOT_PX4,
            base_mode: if armed {
                MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED
                    | MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
            } else {
                MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
            },
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        })
    }

    fn position(time_boot_ms: u32, x: f32) -> MavMessage {
        MavMessage::LOCAL_POSITION_NED(LOCAL_POSITION_NED_DATA {
            time_boot_ms,
            x,
            y: 0.0,
            z: -1.0,
            vx: 0.0,
            vy: 0.0,
            vz: 0.0,
        })
    }

    fn ack(target_system: u8, target_component: u8) -> MavMessage {
        MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
            command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            result: MavResult::MAV_RESULT_ACCEPTED,
            progress: 0,
            result_param2: 0,
            target_system,
            target_component,
        })
    }

    fn x_of(state: &VehicleState) -> Option<f32> {
        state.position.map(|p| p.position_ned_m[0])
    }

    #[test]
    fn heartbeat_from_the_autopilot_sets_armed_mode_and_autopilot() {
        let mut s = VehicleState::default();
        let now = Instant::now();
        fold(
            &mut s,
            &autopilot(),
            heartbeat(true, 0x0006_0000),
            VEHICLE,
            now,
        );
        assert!(s.armed);
        assert_eq!(s.custom_mode, 0x0006_0000);
        assert_eq!(s.autopilot, Some(MavAutopilot::MAV_AUTOPILOT_PX4));
        assert_eq!(s.last_heartbeat, Some(now));
        assert_eq!(s.last_message, Some(now));
    }

    #[test]
    fn another_system_changes_nothing() {
        let mut s = VehicleState::default();
        let now = Instant::now();
        for message in [heartbeat(true, 7), position(10, 5.0), ack(255, 190)] {
            let before = s.clone();
            let out = fold(&mut s, &header(4, 1), message, VEHICLE, now);
            assert!(out.is_none());
            assert_eq!(s, before);
        }
        // A system id above 255 (MAVLink 2 routing) must not alias ours either.
        let before = s.clone();
        fold(
            &mut s,
            &header(256 + 3, 1),
            heartbeat(true, 7),
            VEHICLE,
            now,
        );
        assert_eq!(s, before);
    }

    #[test]
    fn heartbeat_from_another_component_does_not_steer() {
        let mut s = VehicleState::default();
        let now = Instant::now();
        fold(&mut s, &header(3, 191), heartbeat(true, 7), VEHICLE, now);
        assert!(!s.armed);
        assert_eq!(s.custom_mode, 0);
        assert_eq!(s.last_heartbeat, None);
        // ... but it does show the link is alive.
        assert_eq!(s.last_message, Some(now));
    }

    #[test]
    fn non_finite_positions_are_ignored() {
        let mut s = VehicleState::default();
        let now = Instant::now();
        fold(&mut s, &autopilot(), position(100, 1.0), VEHICLE, now);
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            fold(&mut s, &autopilot(), position(200, bad), VEHICLE, now);
            let mut m = position(300, 2.0);
            if let MavMessage::LOCAL_POSITION_NED(p) = &mut m {
                p.vz = bad;
            }
            fold(&mut s, &autopilot(), m, VEHICLE, now);
            assert_eq!(x_of(&s), Some(1.0));
        }
        assert_eq!(s.position_time_boot_ms, Some(100));
    }

    #[test]
    fn older_positions_are_ignored_equal_and_newer_accepted() {
        let mut s = VehicleState {
            recording: true,
            ..VehicleState::default()
        };
        let now = Instant::now();
        fold(&mut s, &autopilot(), position(5_000, 1.0), VEHICLE, now);
        fold(&mut s, &autopilot(), position(4_950, 0.5), VEHICLE, now);
        assert_eq!(x_of(&s), Some(1.0), "a late packet moved the drone back");
        fold(&mut s, &autopilot(), position(5_000, 1.0), VEHICLE, now);
        fold(&mut s, &autopilot(), position(5_050, 1.5), VEHICLE, now);
        assert_eq!(x_of(&s), Some(1.5));
        assert_eq!(s.track.len(), 3, "the late packet is not recorded either");
    }

    #[test]
    fn a_large_jump_back_is_a_reboot() {
        let mut s = VehicleState::default();
        let now = Instant::now();
        fold(&mut s, &autopilot(), position(60_000, 1.0), VEHICLE, now);
        fold(&mut s, &autopilot(), position(200, 0.0), VEHICLE, now);
        assert_eq!(x_of(&s), Some(0.0));
        assert_eq!(s.position_time_boot_ms, Some(200));
        // The counter wrapping after 49 days looks the same.
        fold(
            &mut s,
            &autopilot(),
            position(u32::MAX - 5, 2.0),
            VEHICLE,
            now,
        );
        fold(&mut s, &autopilot(), position(3, 2.1), VEHICLE, now);
        assert_eq!(x_of(&s), Some(2.1));
    }

    #[test]
    fn acks_must_come_from_the_vehicle_and_name_us() {
        let mut s = VehicleState::default();
        let now = Instant::now();
        assert!(fold(&mut s, &autopilot(), ack(255, 190), VEHICLE, now).is_some());
        assert!(fold(&mut s, &autopilot(), ack(0, 0), VEHICLE, now).is_some());
        assert!(fold(&mut s, &autopilot(), ack(254, 190), VEHICLE, now).is_none());
        assert!(fold(&mut s, &autopilot(), ack(255, 1), VEHICLE, now).is_none());
        assert!(fold(&mut s, &header(9, 1), ack(255, 190), VEHICLE, now).is_none());
    }

    #[test]
    fn sys_status_reports_battery_and_prearm() {
        let mut s = VehicleState::default();
        let now = Instant::now();
        let check = MavSysStatusSensor::MAV_SYS_STATUS_PREARM_CHECK;
        let status = |battery_remaining: i8, healthy: bool| {
            MavMessage::SYS_STATUS(SYS_STATUS_DATA {
                onboard_control_sensors_present: check,
                onboard_control_sensors_enabled: check,
                onboard_control_sensors_health: if healthy {
                    check
                } else {
                    MavSysStatusSensor::empty()
                },
                battery_remaining,
                ..SYS_STATUS_DATA::default()
            })
        };
        fold(&mut s, &autopilot(), status(73, true), VEHICLE, now);
        assert_eq!(s.battery_remaining_pct, Some(73));
        assert_eq!(s.prearm_ok, Some(true));
        assert!(is_prearm_reason("PreArm: Need Position Estimate"));
        assert!(is_prearm_reason("Preflight Fail: ekf2 missing data"));
        assert!(!is_prearm_reason("Arming denied: not landed"));
        fold(&mut s, &autopilot(), status(-1, false), VEHICLE, now);
        assert_eq!(s.battery_remaining_pct, None);
        assert_eq!(s.prearm_ok, Some(false));
        fold(&mut s, &autopilot(), status(-100, true), VEHICLE, now);
        assert_eq!(s.battery_remaining_pct, None);
    }

    #[test]
    fn landed_state_only_from_the_autopilot() {
        let mut s = VehicleState::default();
        let now = Instant::now();
        let landed = MavMessage::EXTENDED_SYS_STATE(EXTENDED_SYS_STATE_DATA {
            vtol_state: MavVtolState::MAV_VTOL_STATE_UNDEFINED,
            landed_state: MavLandedState::MAV_LANDED_STATE_ON_GROUND,
        });
        fold(&mut s, &header(3, 100), landed.clone(), VEHICLE, now);
        assert!(!s.on_ground());
        fold(&mut s, &autopilot(), landed, VEHICLE, now);
        assert!(s.on_ground());
    }

    #[test]
    fn any_message_from_the_vehicle_refreshes_the_link_clock() {
        let mut s = VehicleState::default();
        let t0 = Instant::now();
        fold(&mut s, &autopilot(), position(1_000, 1.0), VEHICLE, t0);
        let t1 = t0 + Duration::from_secs(1);
        // Even a stale sample proves the link works.
        fold(&mut s, &autopilot(), position(900, 1.0), VEHICLE, t1);
        assert_eq!(s.last_message, Some(t1));
        assert_eq!(s.last_heartbeat, None);
        assert_eq!(s.message_age_s(t1 + Duration::from_secs(2)), Some(2.0));
    }
}
