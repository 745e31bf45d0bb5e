//! Geodetic positions and the flat-earth conversion to local NED metres.
//!
//! Swarm flights span a few hundred metres at most, so a flat-earth conversion
//! around the reference point with the WGS84 ellipsoid's radii of curvature there
//! (meridian for north, prime vertical for east) is accurate to millimetres and
//! keeps the SITL free of a geodesy dependency. (A mean-sphere radius would be off
//! by 0.3 %: 3 cm per 10 m, enough to misplace vehicles whose frames come from GPS.)

/// WGS84 semi-major axis, metres.
const WGS84_A_M: f64 = 6_378_137.0;
/// WGS84 first eccentricity squared.
const WGS84_E2: f64 = 6.694_379_990_14e-3;

/// Meridian and prime-vertical radii of curvature at `lat_rad`, metres.
fn radii_m(lat_rad: f64) -> (f64, f64) {
    let w2 = 1.0 - WGS84_E2 * lat_rad.sin().powi(2);
    let prime_vertical = WGS84_A_M / w2.sqrt();
    (prime_vertical * (1.0 - WGS84_E2) / w2, prime_vertical)
}

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
        let (meridian_m, prime_m) = radii_m(lat_rad);
        GeoPoint {
            lat_deg: self.lat_deg + (ned_m[0] / meridian_m).to_degrees(),
            lon_deg: self.lon_deg + (ned_m[1] / (prime_m * lat_rad.cos())).to_degrees(),
            alt_amsl_m: self.alt_amsl_m - ned_m[2],
        }
    }

    /// North, east, down metres from `self` to `other`.
    pub fn ned_to(&self, other: &GeoPoint) -> [f64; 3] {
        let lat_rad = self.lat_deg.to_radians();
        let (meridian_m, prime_m) = radii_m(lat_rad);
        [
            (other.lat_deg - self.lat_deg).to_radians() * meridian_m,
            (other.lon_deg - self.lon_deg).to_radians() * prime_m * lat_rad.cos(),
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
