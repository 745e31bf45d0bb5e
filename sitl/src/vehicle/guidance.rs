//! What the position controller tracks in each mode, and with which limits.

use super::Vehicle;
use crate::dynamics::{Limits, Setpoint};
use crate::mode::FlightMode;

/// Climb speed limit during takeoff, m/s.
const TAKEOFF_SPEED_MPS: f32 = 1.5;

impl Vehicle {
    /// What the position controller tracks in the current mode.
    pub(super) fn current_setpoint(&self) -> Setpoint {
        if let Some(height_m) = self.takeoff_height_m {
            let mut sp = self.hold;
            sp.position_ned_m[2] = Some(self.body.ground_down_m - height_m);
            return sp;
        }
        if self.rogue_active() && matches!(self.mode, FlightMode::Offboard | FlightMode::Guided) {
            return self.rogue_target();
        }
        match self.mode {
            FlightMode::Offboard => self.external.map_or(self.hold, |e| e.setpoint),
            FlightMode::Guided => match self.external {
                Some(e) if self.airborne() || self.takeoff_height_m.is_some() => e.setpoint,
                _ => self.hold,
            },
            FlightMode::Land => self.descend_at(self.hold.position_ned_m),
            FlightMode::ReturnToLaunch => {
                let home = self.initial_position_ned_m;
                if self.rtl_descending {
                    self.descend_at([Some(home[0]), Some(home[1]), None])
                } else {
                    Setpoint {
                        position_ned_m: [Some(home[0]), Some(home[1]), self.hold.position_ned_m[2]],
                        velocity_ned_mps: [None; 3],
                        yaw_rad: None,
                        accel_ned_mps2: [None; 3],
                    }
                }
            }
            FlightMode::Manual | FlightMode::Hold | FlightMode::Takeoff => self.hold,
        }
    }

    /// The rogue ground station's target: far west of home, at the current height.
    fn rogue_target(&self) -> Setpoint {
        let home = self.home_ned_m;
        Setpoint {
            position_ned_m: [
                Some(home[0]),
                Some(home[1] - crate::faults::ROGUE_TARGET_WEST_M),
                Some(self.body.position_ned_m[2]),
            ],
            velocity_ned_mps: [None; 3],
            yaw_rad: None,
            accel_ned_mps2: [None; 3],
        }
    }

    /// Hold north/east, sink at the landing speed of the parameter table (so a
    /// controller that lowers it is obeyed, as by real autopilots).
    fn descend_at(&self, position: [Option<f32>; 3]) -> Setpoint {
        Setpoint {
            position_ned_m: [position[0], position[1], None],
            velocity_ned_mps: [None, None, Some(self.params.land_speed_mps())],
            yaw_rad: None,
            accel_ned_mps2: [None; 3],
        }
    }

    /// Limits for the current phase (slower climbs during takeoff).
    pub(super) fn mode_limits(&self) -> Limits {
        let mut limits = self.limits;
        if self.takeoff_height_m.is_some() {
            limits.max_speed_mps = limits.max_speed_mps.min(TAKEOFF_SPEED_MPS);
        }
        limits
    }
}
