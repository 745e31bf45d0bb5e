//! What the checker reports: per-drone figures, the closest approach found, and
//! the separation figures with the violations they add up to.

use serde::{Deserialize, Serialize};

/// Per-drone figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DroneReport {
    /// Highest finite-difference speed between consecutive samples, m/s.
    pub max_speed_mps: f64,
    /// Highest second-difference acceleration over three consecutive samples, m/s².
    pub max_accel_mps2: f64,
    /// Highest third-difference jerk over four consecutive samples, m/s³.
    #[serde(default)]
    pub max_jerk_mps3: f64,
    /// Speed over the first sample interval, m/s (a drone starting at rest under the
    /// acceleration limit covers at most `a·Δt²/2` there).
    pub start_speed_mps: f64,
    /// Speed over the last sample interval, m/s (likewise for coming to rest).
    pub end_speed_mps: f64,
}

/// The closest approach found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClosestPair {
    /// One drone, by index in the samples.
    pub first: usize,
    /// The other, by index in the samples.
    pub second: usize,
    /// Time of the closest approach of the interpolated motion, seconds.
    pub time_s: f64,
}

/// What the checker found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeparationReport {
    /// Pairs farther apart than this were not examined; separations are reported as at
    /// least this when no pair came closer.
    pub search_radius_m: f64,
    /// Smallest distance between two drones at a common sample time.
    pub min_separation_samples_m: f64,
    /// Smallest distance between the linearly interpolated motions.
    pub min_separation_interpolated_m: f64,
    /// Guaranteed lower bound on the true continuous separation, assuming the
    /// acceleration limit holds between samples.
    pub min_separation_bound_m: f64,
    /// The pair behind the interpolated minimum, if any pair came within the radius.
    pub closest: Option<ClosestPair>,
    /// Per-drone figures, in sample order.
    pub drones: Vec<DroneReport>,
    /// Highest speed of any drone, m/s.
    pub max_speed_mps: f64,
    /// Highest acceleration of any drone, m/s².
    pub max_accel_mps2: f64,
    /// Highest jerk of any drone, m/s³.
    #[serde(default)]
    pub max_jerk_mps3: f64,
    /// Under an ellipsoidal separation, the scaled distances the schedule
    /// promises (see the module docs); `None` for a sphere.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scaled: Option<ScaledSeparation>,
    /// Human-readable violations; empty means every limit holds.
    pub violations: Vec<String>,
}

/// Scaled distances of the setpoints' bounding cylinders: `max(ρ / H', |dz| / V')`,
/// separated when at least 1.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScaledSeparation {
    /// The cylinder's radius, metres: the horizontal separation plus twice the
    /// tracking error.
    pub horizontal_m: f64,
    /// The cylinder's half height, metres: the vertical separation plus twice the
    /// tracking error.
    pub vertical_m: f64,
    /// Smallest scaled distance at a common sample time.
    pub min_samples: f64,
    /// Smallest scaled distance of the linearly interpolated motions.
    pub min_interpolated: f64,
    /// Guaranteed lower bound on the true continuous scaled distance.
    pub min_bound: f64,
    /// The pair behind the bound, if any pair came within the search radius.
    pub closest: Option<ClosestPair>,
}

impl SeparationReport {
    /// True when separation, speed, acceleration, jerk and rest at both ends all hold.
    pub fn ok(&self) -> bool {
        self.violations.is_empty()
    }
}
