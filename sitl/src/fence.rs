//! The autopilots' own geofence, as each firmware keeps it in its parameters:
//! a maximum altitude and a circle around home, and what to do on a breach.
//! Each imitation reads its own parameters (`Imitation::fence`);
//! the vehicle checks its position against the result every step
//! (`vehicle::fence`).

use crate::mode::FlightMode;

/// One vehicle's fence as its parameters set it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FenceRule {
    /// Horizontal distance from home beyond which it is breached, metres
    /// (`None`: no circle).
    pub radius_m: Option<f32>,
    /// Height above home beyond which it is breached, metres (`None`: no ceiling).
    pub max_altitude_m: Option<f32>,
    /// The mode a breach switches to; `None` only reports it.
    pub action: Option<FlightMode>,
    /// The STATUSTEXT a breach is announced with, in the firmware's words.
    pub breach_text: &'static str,
}

impl FenceRule {
    /// Whether a vehicle `horizontal_m` from home and `height_m` above it is
    /// outside the fence.
    pub fn breached(&self, horizontal_m: f32, height_m: f32) -> bool {
        self.radius_m.is_some_and(|r| horizontal_m > r)
            || self.max_altitude_m.is_some_and(|a| height_m > a)
    }
}

/// A distance parameter that sets a limit: positive and finite, else none.
pub(crate) fn limit(value: Option<f32>) -> Option<f32> {
    value.filter(|v| v.is_finite() && *v > 0.0)
}
