//! SET_POSITION_TARGET_LOCAL_NED / _GLOBAL_INT: decode the type_mask and the
//! frame into a [`Setpoint`] in the swarm's shared NED frame (LOCAL_NED targets
//! are relative to the vehicle's own local origin).

use crate::dynamics::Setpoint;
use crate::geo::GeoPoint;
use crate::vehicle::Vehicle;
use mavlink::dialects::common::{
    MavFrame, PositionTargetTypemask as Mask, SET_POSITION_TARGET_GLOBAL_INT_DATA,
    SET_POSITION_TARGET_LOCAL_NED_DATA,
};

/// Per-axis position and velocity components the type_mask keeps.
fn masked(
    mask: Mask,
    position: [f32; 3],
    velocity: [f32; 3],
    accel: [f32; 3],
    yaw_rad: f32,
) -> Setpoint {
    let keep = |flag: Mask, v: f32| (!mask.contains(flag) && v.is_finite()).then_some(v);
    Setpoint {
        position_ned_m: [
            keep(Mask::POSITION_TARGET_TYPEMASK_X_IGNORE, position[0]),
            keep(Mask::POSITION_TARGET_TYPEMASK_Y_IGNORE, position[1]),
            keep(Mask::POSITION_TARGET_TYPEMASK_Z_IGNORE, position[2]),
        ],
        velocity_ned_mps: [
            keep(Mask::POSITION_TARGET_TYPEMASK_VX_IGNORE, velocity[0]),
            keep(Mask::POSITION_TARGET_TYPEMASK_VY_IGNORE, velocity[1]),
            keep(Mask::POSITION_TARGET_TYPEMASK_VZ_IGNORE, velocity[2]),
        ],
        yaw_rad: keep(Mask::POSITION_TARGET_TYPEMASK_YAW_IGNORE, yaw_rad),
        // Force setpoints (FORCE_SET) are not simulated: their afx..afz are ignored.
        accel_ned_mps2: if mask.contains(Mask::POSITION_TARGET_TYPEMASK_FORCE_SET) {
            [None; 3]
        } else {
            [
                keep(Mask::POSITION_TARGET_TYPEMASK_AX_IGNORE, accel[0]),
                keep(Mask::POSITION_TARGET_TYPEMASK_AY_IGNORE, accel[1]),
                keep(Mask::POSITION_TARGET_TYPEMASK_AZ_IGNORE, accel[2]),
            ]
        },
    }
}

impl Vehicle {
    /// Handles SET_POSITION_TARGET_LOCAL_NED (frames LOCAL_NED and LOCAL_OFFSET_NED).
    pub(crate) fn position_target_local(&mut self, sp: &SET_POSITION_TARGET_LOCAL_NED_DATA) {
        let offset = match sp.coordinate_frame {
            MavFrame::MAV_FRAME_LOCAL_NED => self.local_origin_ned_m,
            MavFrame::MAV_FRAME_LOCAL_OFFSET_NED => self.body.position_ned_m,
            _ => return, // body frames are not simulated: ignored, as PX4 ignores unknown frames
        };
        let xyz = [sp.x, sp.y, sp.z];
        let position = std::array::from_fn(|i| xyz[i] + offset[i]);
        let accel = [sp.afx, sp.afy, sp.afz];
        let setpoint = masked(sp.type_mask, position, [sp.vx, sp.vy, sp.vz], accel, sp.yaw);
        self.accept_setpoint(setpoint);
    }

    /// Handles SET_POSITION_TARGET_GLOBAL_INT (AMSL, relative and terrain altitude frames).
    // The *_INT frame names are deprecated but are what clients send in this message.
    #[allow(deprecated)]
    pub(crate) fn position_target_global(&mut self, sp: &SET_POSITION_TARGET_GLOBAL_INT_DATA) {
        let relative = match sp.coordinate_frame {
            MavFrame::MAV_FRAME_GLOBAL_INT | MavFrame::MAV_FRAME_GLOBAL => false,
            MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
            | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT
            | MavFrame::MAV_FRAME_GLOBAL_TERRAIN_ALT_INT
            | MavFrame::MAV_FRAME_GLOBAL_TERRAIN_ALT => true,
            _ => return,
        };
        let alt_amsl_m = if relative {
            self.home.alt_amsl_m + f64::from(sp.alt)
        } else {
            f64::from(sp.alt)
        };
        let target = GeoPoint {
            lat_deg: f64::from(sp.lat_int) / 1e7,
            lon_deg: f64::from(sp.lon_int) / 1e7,
            alt_amsl_m,
        };
        let ned = self.home.ned_to(&target);
        let position = std::array::from_fn(|i| self.initial_position_ned_m[i] + ned[i] as f32);
        let accel = [sp.afx, sp.afy, sp.afz];
        let setpoint = masked(sp.type_mask, position, [sp.vx, sp.vy, sp.vz], accel, sp.yaw);
        self.accept_setpoint(setpoint);
    }

    /// PX4 records every setpoint (the stream gates OFFBOARD); ArduPilot only
    /// takes targets in GUIDED while flying, ignoring them otherwise.
    fn accept_setpoint(&mut self, setpoint: Setpoint) {
        if self.flavour.imitation().takes_setpoint(self) {
            self.record_setpoint(setpoint);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_mask_3520_keeps_position_and_velocity() {
        let sp = masked(
            Mask::from_bits_truncate(3520),
            [1.0, 2.0, -3.0],
            [0.5, 0.0, 0.0],
            [0.0; 3],
            0.0,
        );
        assert_eq!(sp.position_ned_m, [Some(1.0), Some(2.0), Some(-3.0)]);
        assert_eq!(sp.velocity_ned_mps, [Some(0.5), Some(0.0), Some(0.0)]);
        assert_eq!(sp.yaw_rad, None);
    }

    #[test]
    fn default_mask_ignores_x_and_nan_is_ignored() {
        let sp = masked(
            Mask::default(),
            [1.0, f32::NAN, -3.0],
            [0.0; 3],
            [0.0; 3],
            0.0,
        );
        assert_eq!(sp.position_ned_m, [None, None, Some(-3.0)]);
    }
}
