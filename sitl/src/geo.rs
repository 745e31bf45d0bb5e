//! Geodetic positions and the flat-earth conversion to local NED metres.
//!
//! Swarm flights span a few hundred metres at most, so an equirectangular
//! approximation around the home point is accurate to millimetres and keeps
//! the SITL free of a geodesy dependency.

/// Mean Earth radius used for the flat-earth conversion, in metres.
const EARTH_RADIUS_M: f64 = 6_371_000.0;

/// A WGS84 position: latitude and longitude in degrees, altitude AMSL in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeoPoint {
    /// Latitude in degrees, north positive.
    pub lat_deg: f64,
    /// Longitude in degrees, east positive.
    pub lon_deg: f64,
    /// Altitude above mean sea level in metres.
    pub alt_amsl_m: f64,
}

impl Default for GeoPoint {
    /// PX4's default SITL home (Zürich), so logs look familiar to PX4 users.
    fn default() -> Self {
        Self {
            lat_deg: 47.397_742,
            lon_deg: 8.545_594,
            alt_amsl_m: 488.0,
        }
    }
}

impl GeoPoint {
    /// The point displaced by `ned_m` (north, east, down metres) from `self`.
    pub fn offset_ned(&self, ned_m: [f64; 3]) -> GeoPoint {
        let lat_rad = self.lat_deg.to_radians();
        GeoPoint {
            lat_deg: self.lat_deg + (ned_m[0] / EARTH_RADIUS_M).to_degrees(),
            lon_deg: self.lon_deg + (ned_m[1] / (EARTH_RADIUS_M * lat_rad.cos())).to_degrees(),
            alt_amsl_m: self.alt_amsl_m - ned_m[2],
        }
    }

    /// North, east, down metres from `self` to `other`.
    pub fn ned_to(&self, other: &GeoPoint) -> [f64; 3] {
        let lat_rad = self.lat_deg.to_radians();
        [
            (other.lat_deg - self.lat_deg).to_radians() * EARTH_RADIUS_M,
            (other.lon_deg - self.lon_deg).to_radians() * EARTH_RADIUS_M * lat_rad.cos(),
            self.alt_amsl_m - other.alt_amsl_m,
        ]
    }

    /// Latitude in degE7 as MAVLink's `*_INT` messages carry it.
    pub fn lat_e7(&self) -> i32 {
        (self.lat_deg * 1e7).round() as i32
    }

    /// Longitude in degE7 as MAVLink's `*_INT` messages carry it.
    pub fn lon_e7(&self) -> i32 {
        (self.lon_deg * 1e7).round() as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_and_back_round_trips() {
        let home = GeoPoint::default();
        let p = home.offset_ned([120.0, -35.0, -10.0]);
        let back = home.ned_to(&p);
        assert!((back[0] - 120.0).abs() < 1e-6);
        assert!((back[1] + 35.0).abs() < 1e-6);
        assert!((back[2] + 10.0).abs() < 1e-9);
        assert!((p.alt_amsl_m - 498.0).abs() < 1e-9);
    }
}
