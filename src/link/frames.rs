//! The one place where planning coordinates (ENU) meet MAVLink coordinates (NED).
//!
//! Planning works in east-north-up metres relative to the mission origin; MAVLink
//! LOCAL_NED is north-east-down. Every vehicle shares one local frame whose origin is
//! the mission's ENU origin projected to the ground, so the conversion is a pure axis
//! swap with the up axis negated — no offsets, no per-vehicle state. Keeping it here,
//! and only here, is what keeps a sign error from hiding in two places at once.

/// North-east-down from east-north-up (positions or velocities).
pub fn ned_from_enu(enu: [f64; 3]) -> [f64; 3] {
    [enu[1], enu[0], -enu[2]]
}

/// East-north-up from north-east-down (positions or velocities).
pub fn enu_from_ned(ned: [f64; 3]) -> [f64; 3] {
    [ned[1], ned[0], -ned[2]]
}

/// `ned_from_enu` narrowed to the `f32` MAVLink carries on the wire.
pub fn ned_f32_from_enu(enu: [f64; 3]) -> [f32; 3] {
    ned_from_enu(enu).map(|c| c as f32)
}

/// `enu_from_ned` from the `f32` fields MAVLink reports.
pub fn enu_from_ned_f32(ned: [f32; 3]) -> [f64; 3] {
    enu_from_ned(ned.map(f64::from))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn east_is_y_north_is_x_up_is_minus_z() {
        assert_eq!(ned_from_enu([1.0, 2.0, 3.0]), [2.0, 1.0, -3.0]);
        assert_eq!(enu_from_ned([2.0, 1.0, -3.0]), [1.0, 2.0, 3.0]);
    }

    #[test]
    fn round_trip_is_identity() {
        let p = [0.25, -7.5, 1.5];
        assert_eq!(enu_from_ned(ned_from_enu(p)), p);
        assert_eq!(enu_from_ned_f32(ned_f32_from_enu(p)), p);
    }
}
