//! The geofence check, every step while armed and in the air: a vehicle beyond
//! its fence (measured from where it armed, as both firmwares measure from home)
//! announces the breach once and switches to the fence's action.

use super::Vehicle;
use mavlink::dialects::common::MavSeverity;

impl Vehicle {
    /// Checks the fence; acts on the first breach of a flight.
    pub(super) fn check_fence(&mut self) {
        if !self.armed || !self.airborne() || self.fence_breached {
            return;
        }
        let Some(rule) = self.flavour.imitation().fence(&self.params) else {
            return;
        };
        let [n, e, d] = self.body.position_ned_m;
        let [hn, he, hd] = self.home_ned_m;
        let horizontal_m = (n - hn).hypot(e - he);
        let height_m = hd - d;
        if !rule.breached(horizontal_m, height_m) {
            return;
        }
        self.fence_breached = true;
        self.status_text(MavSeverity::MAV_SEVERITY_CRITICAL, rule.breach_text);
        if let Some(mode) = rule.action
            && mode != self.mode
        {
            self.set_mode(mode);
        }
    }
}
