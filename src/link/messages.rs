//! Builders for the messages a ground station sends, with every field set
//! explicitly: rust-mavlink's defaults are dangerous here (a default HEARTBEAT
//! claims SAFETY_ARMED, a default type mask ignores x).

use mavlink::dialects::common::{
    COMMAND_LONG_DATA, HEARTBEAT_DATA, MavAutopilot, MavCmd, MavFrame, MavMessage, MavModeFlag,
    MavState, MavType, PositionTargetTypemask, SET_POSITION_TARGET_LOCAL_NED_DATA,
};

/// Our MAVLink system id: 255 is the ground-station convention autopilots expect
/// (ArduPilot's GCS failsafe counts heartbeats from it).
pub const GCS_SYSTEM_ID: u8 = 255;
/// MAV_COMP_ID_MISSIONPLANNER.
pub const GCS_COMPONENT_ID: u8 = 190;
/// The autopilot's component id on every vehicle we fly.
pub const AUTOPILOT_COMPONENT_ID: u8 = 1;

/// Position, velocity and acceleration used (not as force); yaw and yaw rate
/// ignored (0x0C00). PX4 offboard and ArduPilot guided both take all three.
pub const TYPE_MASK_POSITION_VELOCITY_ACCEL: u16 = 3072;

/// The 1 Hz ground-station heartbeat (explicitly disarmed base mode).
pub fn gcs_heartbeat() -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: 0,
        mavtype: MavType::MAV_TYPE_GCS,
        autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
        base_mode: MavModeFlag::empty(),
        system_status: MavState::MAV_STATE_ACTIVE,
        mavlink_version: 3,
    })
}

/// A COMMAND_LONG to the autopilot of `target_system`.
pub fn command_long(
    target_system: u8,
    command: MavCmd,
    params: [f32; 7],
    confirmation: u8,
) -> MavMessage {
    let [param1, param2, param3, param4, param5, param6, param7] = params;
    MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1,
        param2,
        param3,
        param4,
        param5,
        param6,
        param7,
        command,
        target_system,
        target_component: AUTOPILOT_COMPONENT_ID,
        confirmation,
    })
}

/// A LOCAL_NED position target with velocity and acceleration feed-forward.
pub fn position_target(
    target_system: u8,
    time_boot_ms: u32,
    position_ned_m: [f32; 3],
    velocity_ned_mps: [f32; 3],
    accel_ned_mps2: [f32; 3],
) -> MavMessage {
    MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
        time_boot_ms,
        x: position_ned_m[0],
        y: position_ned_m[1],
        z: position_ned_m[2],
        vx: velocity_ned_mps[0],
        vy: velocity_ned_mps[1],
        vz: velocity_ned_mps[2],
        afx: accel_ned_mps2[0],
        afy: accel_ned_mps2[1],
        afz: accel_ned_mps2[2],
        yaw: 0.0,
        yaw_rate: 0.0,
        type_mask: PositionTargetTypemask::from_bits_truncate(TYPE_MASK_POSITION_VELOCITY_ACCEL),
        target_system,
        target_component: AUTOPILOT_COMPONENT_ID,
        coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn setpoint_uses_position_velocity_and_acceleration() {
        let MavMessage::SET_POSITION_TARGET_LOCAL_NED(m) =
            position_target(3, 0, [1.0, 2.0, -3.0], [0.5, 0.0, 0.0], [2.0, 0.0, 0.0])
        else {
            unreachable!()
        };
        assert_eq!(m.type_mask.bits(), 0x0C00);
        assert_eq!(m.afx, 2.0);
        assert!(
            !m.type_mask
                .contains(PositionTargetTypemask::POSITION_TARGET_TYPEMASK_FORCE_SET)
        );
        assert!(
            !m.type_mask
                .contains(PositionTargetTypemask::POSITION_TARGET_TYPEMASK_X_IGNORE)
        );
        assert_eq!(m.coordinate_frame, MavFrame::MAV_FRAME_LOCAL_NED);
    }

    #[test]
    fn heartbeat_is_not_armed() {
        let MavMessage::HEARTBEAT(h) = gcs_heartbeat() else {
            unreachable!()
        };
        assert!(
            !h.base_mode
                .contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED)
        );
    }
}
