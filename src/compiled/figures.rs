//! What a flight log keeps of one run of the independent checker.
//!
//! The checker's [`SeparationReport`] has a record per drone; a flight log keeps
//! one check before arming and one per replan, so it keeps these few figures
//! instead: enough to read each check against the mission's limits, and how long
//! it took (a replan's check counts against the replan deadline).

use crate::mission::Limits;
use crate::verify::SeparationReport;
use serde::{Deserialize, Serialize};
use std::time::Duration;

/// The figures of one check of sampled trajectories.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckFigures {
    /// Drones checked.
    pub drones: usize,
    /// Samples per drone (the whole flight pad to pad before arming; from the
    /// splice down to the ground for a replan).
    pub samples: usize,
    /// The sample period, seconds.
    pub sample_period_s: f64,
    /// Guaranteed lower bound on the continuous separation of the setpoints,
    /// metres (the checker's interpolation bound).
    pub min_separation_bound_m: f64,
    /// What setpoints must keep: the safety distance plus twice the tracking
    /// error, metres (an ellipsoid's horizontal radius so grown).
    pub required_separation_m: f64,
    /// Under an ellipsoid, the guaranteed lower bound on the scaled distance of
    /// the setpoints' bounding cylinders (separated at 1 or more); `None` for a
    /// sphere.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_scaled_bound: Option<f64>,
    /// The two drones behind the minimum and when, seconds on the checked clock;
    /// `None` when no two drones came within the checker's search radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub closest: Option<(String, String, f64)>,
    /// Highest speed of any drone, m/s.
    pub max_speed_mps: f64,
    /// Highest acceleration of any drone, m/s².
    pub max_accel_mps2: f64,
    /// Highest jerk of any drone, m/s³.
    pub max_jerk_mps3: f64,
    /// How long sampling and checking took, seconds.
    pub check_s: f64,
    /// What broke, drones named by id; empty when every limit held.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub violations: Vec<String>,
}

impl CheckFigures {
    /// The figures of `report`, a check of `ids` (sample order) sampled `samples`
    /// times at `sample_period_s` against `limits`, which took `took`.
    pub fn new(
        report: &SeparationReport,
        limits: &Limits,
        ids: &[&str],
        samples: usize,
        sample_period_s: f64,
        took: Duration,
    ) -> Self {
        let closest = match &report.scaled {
            Some(scaled) => scaled.closest.as_ref(),
            None => report.closest.as_ref(),
        }
        .map(|pair| {
            let id = |i: usize| {
                ids.get(i)
                    .map_or_else(|| format!("#{i}"), |s| s.to_string())
            };
            (id(pair.first), id(pair.second), pair.time_s)
        });
        Self {
            drones: report.drones.len(),
            samples,
            sample_period_s,
            min_separation_bound_m: report.min_separation_bound_m,
            required_separation_m: limits.setpoint_separation_m(),
            min_scaled_bound: report.scaled.as_ref().map(|s| s.min_bound),
            closest,
            max_speed_mps: report.max_speed_mps,
            max_accel_mps2: report.max_accel_mps2,
            max_jerk_mps3: report.max_jerk_mps3,
            check_s: took.as_secs_f64(),
            violations: report.violations.clone(),
        }
    }

    /// Every limit held.
    pub fn passed(&self) -> bool {
        self.violations.is_empty()
    }

    /// The figures in one line, for people: `min separation ≥ 0.612 m (setpoints
    /// need 0.450 m), max speed 1.00 m/s, …; 8 drones × 812 samples in 3.1 ms`.
    pub fn line(&self) -> String {
        let scaled = self
            .min_scaled_bound
            .map_or(String::new(), |s| format!(", scaled ≥ {s:.3} (need 1)"));
        let verdict = if self.passed() {
            String::new()
        } else {
            format!(": REFUSED ({})", self.violations.join("; "))
        };
        format!(
            "min separation ≥ {:.3} m (setpoints need {:.3} m){scaled}, max speed {:.2} m/s, accel {:.2} m/s², jerk {:.2} m/s³; {} drones × {} samples in {:.1} ms{verdict}",
            self.min_separation_bound_m,
            self.required_separation_m,
            self.max_speed_mps,
            self.max_accel_mps2,
            self.max_jerk_mps3,
            self.drones,
            self.samples,
            1e3 * self.check_s
        )
    }
}
