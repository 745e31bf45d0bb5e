//! The one place where planning coordinates (mission ENU) meet MAVLink coordinates
//! (each vehicle's own local NED).
//!
//! Planning works in east-north-up metres relative to the mission origin. Every
//! autopilot reports and takes `LOCAL_NED` positions relative to its *own* origin,
//! which a real EKF sets where the vehicle first got a GPS fix — normally where it
//! stands. A [`VehicleFrame`] is one vehicle's `mission_from_local` transform: the
//! mission ENU position of that vehicle's local origin. Both frames are level and
//! point north, so the transform is an axis swap (up is minus down) plus that
//! offset; over a field of a few hundred metres the tangent planes at the two
//! origins differ by far less than a millimetre per metre.
//!
//! A vehicle's frame is learned at pre-flight, from one of:
//! * the vehicle's GPS origin (`GPS_GLOBAL_ORIGIN`, else `HOME_POSITION`) and the
//!   mission's `world.geo_origin`: [`VehicleFrame::from_geo`], exact WGS84 geodesy;
//! * its placement: it stands on its pad, so its reported position is that point
//!   ([`VehicleFrame::from_placement`]);
//! * nothing: it shares the mission's frame ([`VehicleFrame::SHARED`]), as vehicles
//!   given a common EKF origin by hand do.
//!
//! Velocities carry no offset: [`ned_from_enu`] and [`enu_from_ned`] swap axes.

use crate::mission::Geodetic;

/// North-east-down from east-north-up (axes only: velocities, or offsets).
pub fn ned_from_enu(enu: [f64; 3]) -> [f64; 3] {
    [enu[1], enu[0], -enu[2]]
}

/// East-north-up from north-east-down (axes only: velocities, or offsets).
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

/// East-north-up metres of `point` from `origin` on the WGS84 ellipsoid (altitudes
/// above mean sea level on both sides, so the geoid cancels).
pub fn enu_between(origin: &Geodetic, point: &Geodetic) -> [f64; 3] {
    let (e, n, u) = map_3d::geodetic2enu(
        point.lat_deg.to_radians(),
        point.lon_deg.to_radians(),
        point.alt_m,
        origin.lat_deg.to_radians(),
        origin.lon_deg.to_radians(),
        origin.alt_m,
        map_3d::Ellipsoid::WGS84,
    );
    [e, n, u]
}

/// The point `enu_m` east-north-up metres from `origin` (WGS84).
pub fn geodetic_at(origin: &Geodetic, enu_m: [f64; 3]) -> Geodetic {
    let (lat, lon, alt) = map_3d::enu2geodetic(
        enu_m[0],
        enu_m[1],
        enu_m[2],
        origin.lat_deg.to_radians(),
        origin.lon_deg.to_radians(),
        origin.alt_m,
        map_3d::Ellipsoid::WGS84,
    );
    Geodetic {
        lat_deg: lat.to_degrees(),
        lon_deg: lon.to_degrees(),
        alt_m: alt,
    }
}

/// One vehicle's `mission_from_local` transform (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleFrame {
    /// Mission ENU position of the vehicle's local NED origin, metres.
    local_origin_enu_m: [f64; 3],
}

impl VehicleFrame {
    /// The vehicle's local frame is the mission's (its origin at the mission origin
    /// projected to the ground).
    pub const SHARED: Self = Self {
        local_origin_enu_m: [0.0; 3],
    };

    /// The vehicle's local origin is at `local_origin_enu_m` in the mission frame.
    pub fn with_origin(local_origin_enu_m: [f64; 3]) -> Self {
        Self { local_origin_enu_m }
    }

    /// The vehicle stands at `placed_enu_m` (its pad) and reports `reported_ned_m`.
    pub fn from_placement(placed_enu_m: [f64; 3], reported_ned_m: [f32; 3]) -> Self {
        let local = enu_from_ned_f32(reported_ned_m);
        Self::with_origin(std::array::from_fn(|i| placed_enu_m[i] - local[i]))
    }

    /// The vehicle's local origin is the geodetic point `vehicle_origin` (its
    /// `GPS_GLOBAL_ORIGIN`); the mission's ENU origin is `mission_origin` (on the
    /// ground below the mission origin, as `world.geo_origin` is written).
    pub fn from_geo(mission_origin: &Geodetic, vehicle_origin: &Geodetic) -> Self {
        Self::with_origin(enu_between(mission_origin, vehicle_origin))
    }

    /// Mission ENU position of the vehicle's local origin, metres.
    pub fn local_origin_enu_m(&self) -> [f64; 3] {
        self.local_origin_enu_m
    }

    /// Mission ENU position of a position the vehicle reports in its local NED frame.
    pub fn mission_from_local(&self, local_ned_m: [f32; 3]) -> [f64; 3] {
        let l = enu_from_ned_f32(local_ned_m);
        std::array::from_fn(|i| self.local_origin_enu_m[i] + l[i])
    }

    /// The vehicle's local NED position of a mission ENU position, as sent on the wire.
    pub fn local_from_mission(&self, mission_enu_m: [f64; 3]) -> [f32; 3] {
        let rel: [f64; 3] = std::array::from_fn(|i| mission_enu_m[i] - self.local_origin_enu_m[i]);
        ned_f32_from_enu(rel)
    }
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

    #[test]
    fn placement_maps_the_reported_point_onto_the_pad() {
        let frame = VehicleFrame::from_placement([3.0, -2.0, 0.0], [0.01, -0.02, 0.0]);
        let at = frame.mission_from_local([0.01, -0.02, 0.0]);
        assert!(
            (at[0] - 3.0).abs() < 1e-6 && (at[1] + 2.0).abs() < 1e-6,
            "{at:?}"
        );
        // One metre north and up in the vehicle's frame is one metre north and up here.
        let moved = frame.mission_from_local([1.01, -0.02, -1.0]);
        assert!((moved[1] - -1.0).abs() < 1e-6 && (moved[2] - 1.0).abs() < 1e-6);
        let back = frame.local_from_mission(moved);
        assert!((back[0] - 1.01).abs() < 1e-6 && (back[2] + 1.0).abs() < 1e-6);
    }

    /// 0.0001° of latitude is 11.1 m north at any longitude; of longitude at 47.4° N
    /// it is 7.54 m east (WGS84 reference values).
    #[test]
    fn geo_frames_place_origins_on_the_ellipsoid() {
        let origin = Geodetic {
            lat_deg: 47.397_742,
            lon_deg: 8.545_594,
            alt_m: 488.0,
        };
        let north = Geodetic {
            lat_deg: origin.lat_deg + 1e-4,
            ..origin
        };
        let east = Geodetic {
            lon_deg: origin.lon_deg + 1e-4,
            ..origin
        };
        let n = VehicleFrame::from_geo(&origin, &north).local_origin_enu_m();
        let e = VehicleFrame::from_geo(&origin, &east).local_origin_enu_m();
        assert!((n[1] - 11.12).abs() < 0.02 && n[0].abs() < 1e-6, "{n:?}");
        assert!((e[0] - 7.54).abs() < 0.02 && e[1].abs() < 1e-3, "{e:?}");
        let back = geodetic_at(&origin, [5.0, -3.0, 0.0]);
        let again = enu_between(&origin, &back);
        assert!((again[0] - 5.0).abs() < 1e-6 && (again[1] + 3.0).abs() < 1e-6);
    }
}
