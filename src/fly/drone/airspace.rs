//! Whether a drone is still where its plan can be: inside the mission's airspace.
//! Every voxel centre lies half a voxel inside the airspace's box, so a drone
//! flying its plan stays within `limits.tracking_error_m` of it; one beyond that
//! has left the plan for good, whoever took it there (its own geofence stopped
//! it outside, a rogue ground station, a flyaway).

use super::DroneRun;
use crate::fly::settings::LoopSettings;

impl DroneRun {
    /// How far outside the airspace the drone is by telemetry, metres, when that
    /// is beyond the tracking bound; `None` while it is inside (or unheard).
    pub fn outside_airspace_m(&self, settings: &LoopSettings) -> Option<f64> {
        let outside_m = settings.airspace.outside_by_m(self.position_m()?);
        (outside_m > settings.tracking_error_m).then_some(outside_m)
    }

    /// Puts the vehicle in its autopilot's land mode where it is, for a drone
    /// out of the plan over nobody's airspace; its result is nobody's to wait for
    /// (the retirement watches for the disarm).
    pub fn land_outside_airspace(&self) {
        self.send(crate::fly::command::Command::Land);
    }
}
