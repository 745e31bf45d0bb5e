//! The mission's scalar settings: its name, the world's extent and scale, the
//! kinematic limits and the link to the vehicles.

use super::bounds::{MAX_DIMENSION, MAX_VOXELS};
use super::report::Report;
use crate::mission::schema::{LimitsSpec, LinkSpec, WorldSpec};
use crate::mission::types::KeySource;

/// PX4 leaves offboard below 2 Hz; far above 100 Hz no autopilot listens.
const SETPOINT_RATES_HZ: std::ops::RangeInclusive<f64> = 2.5..=100.0;

/// A mission needs a name: it labels logs, recordings and plan files.
pub(super) fn check_name(name: &str, report: &mut Report) {
    if name.trim().is_empty() {
        report.add("name", "must not be empty");
    }
}

/// Checks the world's extent, voxel size and origin. Returns the extent in voxels
/// along x, y and z when it is usable, which everything placed in the world needs.
pub(super) fn check_world(world: &WorldSpec, report: &mut Report) -> Option<[u32; 3]> {
    let dimensions = check_dimensions(world.dimensions, report);
    check_positive(report, "world.voxel_size_m", world.voxel_size_m, "m");
    if world.origin_m.iter().any(|c| !c.is_finite()) {
        report.add("world.origin_m", "must be finite numbers");
    }
    dimensions
}

/// Every edge from 1 to [`MAX_DIMENSION`] voxels, and at most [`MAX_VOXELS`] in all.
fn check_dimensions(dimensions: [i64; 3], report: &mut Report) -> Option<[u32; 3]> {
    let mut extents = [0u32; 3];
    let mut all_in_range = true;
    for ((axis, &d), extent) in ["x", "y", "z"].iter().zip(&dimensions).zip(&mut extents) {
        match u32::try_from(d)
            .ok()
            .filter(|_| (1..=MAX_DIMENSION).contains(&d))
        {
            Some(e) => *extent = e,
            None => {
                all_in_range = false;
                report.add(
                    "world.dimensions",
                    format!("{axis} extent {d} must be between 1 and {MAX_DIMENSION} voxels"),
                );
            }
        }
    }
    if !all_in_range {
        return None;
    }
    // Each edge is at most 4096, so the product fits comfortably.
    let voxels: i64 = dimensions.iter().product();
    if voxels > MAX_VOXELS {
        report.add(
            "world.dimensions",
            format!("{dimensions:?} holds {voxels} voxels; at most {MAX_VOXELS} are supported"),
        );
        return None;
    }
    Some(extents)
}

/// Speed, acceleration and safety distance must all be positive.
pub(super) fn check_limits(limits: &LimitsSpec, report: &mut Report) {
    check_positive(report, "limits.max_speed_mps", limits.max_speed_mps, "m/s");
    check_positive(
        report,
        "limits.max_accel_mps2",
        limits.max_accel_mps2,
        "m/s²",
    );
    check_positive(
        report,
        "limits.safety_distance_m",
        limits.safety_distance_m,
        "m",
    );
}

/// Checks the setpoint rate, the link timeout and the signing key source; returns
/// the key source when signing is asked for and well specified.
pub(super) fn check_link(link: &LinkSpec, report: &mut Report) -> Option<KeySource> {
    if !SETPOINT_RATES_HZ.contains(&link.setpoint_rate_hz) {
        report.add(
            "link.setpoint_rate_hz",
            format!(
                "{} Hz is outside {}..={} Hz (autopilots drop offboard control below 2 Hz)",
                link.setpoint_rate_hz,
                SETPOINT_RATES_HZ.start(),
                SETPOINT_RATES_HZ.end()
            ),
        );
    }
    check_positive(report, "link.link_timeout_s", link.link_timeout_s, "s");
    let spec = link.signing.as_ref()?;
    match (&spec.key_file, &spec.key_env) {
        (Some(file), None) if !file.as_os_str().is_empty() => Some(KeySource::File(file.clone())),
        (None, Some(var)) if !var.trim().is_empty() => Some(KeySource::Env(var.clone())),
        (Some(_), Some(_)) => {
            report.add("link.signing", "give key_file or key_env, not both");
            None
        }
        _ => {
            report.add(
                "link.signing",
                "needs key_file (a file with 64 hex digits) or key_env (an environment variable holding them)",
            );
            None
        }
    }
}

/// A finite, positive quantity in `unit`; zero, negative, NaN and infinity are not.
fn check_positive(report: &mut Report, path: &str, value: f64, unit: &str) {
    if !(value.is_finite() && value > 0.0) {
        report.add(
            path,
            format!("must be a positive number of {unit}, got {value}"),
        );
    }
}
