//! The mission's scalar settings: its name, the world's extent and scale, the
//! kinematic limits and the link to the vehicles.

use super::bounds::{MAX_DIMENSION, MAX_VOXELS};
use super::report::Report;
use crate::mission::schema::{LimitsSpec, LinkSpec, WorldSpec};
use crate::mission::types::{DEFAULT_TRACKING_ERROR_M, KeySource};

/// The setpoint rates a mission may ask for, Hz: PX4 leaves offboard below 2 Hz;
/// far above 100 Hz no autopilot listens.
pub const SETPOINT_RATES_HZ: std::ops::RangeInclusive<f64> = 2.5..=100.0;

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
    if world
        .origin_m
        .is_some_and(|o| o.iter().any(|c| !c.is_finite()))
    {
        report.add("world.origin_m", "must be finite numbers");
    }
    if let Some(g) = &world.geo_origin {
        if !(g.lat_deg.is_finite() && (-90.0..=90.0).contains(&g.lat_deg)) {
            report.add(
                "world.geo_origin.lat_deg",
                format!("{} is not a latitude (−90 to 90 degrees)", g.lat_deg),
            );
        }
        if !(g.lon_deg.is_finite() && (-180.0..=180.0).contains(&g.lon_deg)) {
            report.add(
                "world.geo_origin.lon_deg",
                format!("{} is not a longitude (−180 to 180 degrees)", g.lon_deg),
            );
        }
        if !g.alt_m.is_finite() {
            report.add(
                "world.geo_origin.alt_m",
                "must be a finite number of metres",
            );
        }
    }
    dimensions
}

/// Of the room the spacing leaves for tracking, this much is kept back on each side.
const TRACKING_MARGIN_M: f64 = 0.01;

/// The tracking error the vehicles are trusted to keep: the mission's, if it fits
/// the geometry, else the default. Setpoints are kept `d + 2e` apart, and the
/// closest two cell centres are the voxel size or the pad layer's gap below layer 0
/// apart, so `d + 2e` must fit in both. Reports a written value that does not fit,
/// with the numbers.
///
/// An ellipsoid's horizontal radius needs only the voxel size (its vertical reach
/// is kept by the planner, see [`crate::world::VerticalReach`]); its default
/// tracking error also keeps `V + 2e` within the voxel size when `V` alone fits,
/// so an ellipsoid flatter than a voxel relates no two layers of the world (only,
/// when its gap is small, the pad layer and layer 0).
pub(super) fn tracking_error(
    limits: &LimitsSpec,
    voxel_size_m: f64,
    pad_gap_m: f64,
    report: &mut Report,
) -> f64 {
    let d = limits.horizontal_separation_m();
    let spacing_m = match limits.separation {
        Some(_) => voxel_size_m,
        None => voxel_size_m.min(pad_gap_m),
    };
    // Leave a centimetre of the spacing unused: setpoints of drones in neighbouring
    // cells then never sit exactly at the separation, which a sampled check (and
    // a real controller) cannot tell from just below it.
    let unclamped_room_m = 0.5 * (spacing_m - d) - TRACKING_MARGIN_M;
    if d.is_finite() && d > 0.0 && spacing_m > 0.0 && unclamped_room_m < -1e-9 {
        report_separation_too_wide(limits, d, spacing_m, voxel_size_m, pad_gap_m, report);
    }
    let room_m = unclamped_room_m.max(0.0);
    let Some(e) = limits.tracking_error_m else {
        let vertical_room_m = limits
            .separation
            .map(|sep| 0.5 * (voxel_size_m - sep.vertical_m) - TRACKING_MARGIN_M)
            .filter(|&room| room > 0.0)
            .unwrap_or(f64::INFINITY);
        return DEFAULT_TRACKING_ERROR_M.min(room_m).min(vertical_room_m);
    };
    if !(e.is_finite() && e >= 0.0) {
        report.add(
            "limits.tracking_error_m",
            format!("must be zero or a positive number of m, got {e}"),
        );
    } else if e > 0.0 && e > room_m + 1e-9 {
        let (what, spacing) = if pad_gap_m < voxel_size_m {
            ("the pad layer's gap below layer 0", pad_gap_m)
        } else {
            ("the voxel size", voxel_size_m)
        };
        report.add(
            "limits.tracking_error_m",
            format!(
                "{e:.3} m does not fit: setpoints must stay the safety distance plus twice the tracking error apart ({d:.3} + 2 × {e:.3} = {:.3} m, with {TRACKING_MARGIN_M} m to spare on each side), but {what} is only {spacing:.3} m; at most {room_m:.3} m fits (use larger voxels, a higher layer 0, or a smaller safety distance)",
                d + 2.0 * e
            ),
        );
    }
    e
}

/// Whether the separation as written fits the voxel size with room to track;
/// reports it (naming the separation and what fits) when it does not. Checked
/// before the pad layer, whose room no setting could make for such a separation.
pub(super) fn separation_fits_voxel(
    limits: &LimitsSpec,
    voxel_size_m: f64,
    report: &mut Report,
) -> bool {
    let d = limits.horizontal_separation_m();
    let fits = 0.5 * (voxel_size_m - d) - TRACKING_MARGIN_M >= -1e-9;
    if d.is_finite() && d > 0.0 && voxel_size_m.is_finite() && voxel_size_m > 0.0 && !fits {
        report_separation_too_wide(limits, d, voxel_size_m, voxel_size_m, voxel_size_m, report);
        return false;
    }
    true
}

/// The safety distance (or an ellipsoid's horizontal radius) `d` leaves less than
/// [`TRACKING_MARGIN_M`] on each side within the spacing of cell centres: the
/// scheduler would refuse it (`d` above the voxel size) or its own check would
/// find trajectories a hair closer than `d` (`d` at the voxel size), so the
/// mission is refused here, with the largest value that fits.
fn report_separation_too_wide(
    limits: &LimitsSpec,
    d: f64,
    spacing_m: f64,
    voxel_size_m: f64,
    pad_gap_m: f64,
    report: &mut Report,
) {
    let field = match limits.separation {
        Some(_) => "limits.separation.horizontal_m",
        None => "limits.safety_distance_m",
    };
    let what = if spacing_m < voxel_size_m {
        format!("the pad layer's gap below layer 0 ({pad_gap_m:.3} m)")
    } else {
        format!("the voxel size ({voxel_size_m:.3} m)")
    };
    let most_m = spacing_m - 2.0 * TRACKING_MARGIN_M;
    report.add(
        field,
        format!(
            "{d:.3} m does not fit: neighbouring drones' setpoints are only {what} apart, and at least {TRACKING_MARGIN_M} m on each side is kept for tracking; at most {most_m:.3} m fits (use larger voxels{}, or a smaller separation)",
            if spacing_m < voxel_size_m { " or a higher layer 0" } else { "" }
        ),
    );
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

/// Speed, acceleration, jerk and the separation must all be positive, the
/// separation given once (a sphere or an ellipsoid) and an ellipsoid's height
/// within [`MAX_VERTICAL_LAYERS`] voxels.
pub(super) fn check_limits(limits: &LimitsSpec, voxel_size_m: f64, report: &mut Report) {
    check_positive(report, "limits.max_speed_mps", limits.max_speed_mps, "m/s");
    check_positive(
        report,
        "limits.max_accel_mps2",
        limits.max_accel_mps2,
        "m/s²",
    );
    if let Some(jerk) = limits.max_jerk_mps3 {
        check_positive(report, "limits.max_jerk_mps3", jerk, "m/s³");
    }
    match (limits.safety_distance_m, limits.separation) {
        (Some(d), None) => check_positive(report, "limits.safety_distance_m", d, "m"),
        (None, Some(sep)) => {
            check_positive(report, "limits.separation.horizontal_m", sep.horizontal_m, "m");
            check_positive(report, "limits.separation.vertical_m", sep.vertical_m, "m");
            let s = voxel_size_m;
            let most_m = f64::from(MAX_VERTICAL_LAYERS) * s;
            if s.is_finite() && s > 0.0 && sep.vertical_m > most_m {
                report.add(
                    "limits.separation.vertical_m",
                    format!(
                        "{:.2} m is more than {MAX_VERTICAL_LAYERS} voxel sizes ({most_m:.2} m): every drone would keep that many layers of its column to itself, which few missions can fly; use larger voxels",
                        sep.vertical_m
                    ),
                );
            }
        }
        (Some(_), Some(_)) => report.add(
            "limits",
            "give safety_distance_m (a sphere) or separation (an ellipsoid), not both",
        ),
        (None, None) => report.add(
            "limits",
            "missing the separation: give safety_distance_m (a sphere, metres) or separation: { horizontal_m, vertical_m } (an ellipsoid)",
        ),
    }
}

/// How many voxel sizes an ellipsoid's vertical radius may span. The safety
/// argument holds for any height; past this a drone keeps so much of its column to
/// itself that a larger voxel is the better model.
pub const MAX_VERTICAL_LAYERS: u32 = 4;

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
    let floor_hz = link.autopilot.min_setpoint_rate_hz();
    if SETPOINT_RATES_HZ.contains(&link.setpoint_rate_hz) && link.setpoint_rate_hz < floor_hz {
        report.add(
            "link.setpoint_rate_hz",
            format!(
                "{} Hz is below {floor_hz} Hz, the lowest rate {} kept every guarantee at on its real firmware (README: setpoint rates); raise it to at least {floor_hz} Hz, or give the link more capacity (link.radios)",
                link.setpoint_rate_hz, link.autopilot
            ),
        );
    }
    check_positive(report, "link.link_timeout_s", link.link_timeout_s, "s");
    check_positive(report, "link.lost_after_s", link.lost_after_s, "s");
    if link.lost_after_s.is_finite() && link.lost_after_s < link.link_timeout_s {
        report.add(
            "link.lost_after_s",
            format!(
                "{} s is shorter than link.link_timeout_s ({} s): a silent drone first loses its link (its dependants hold) after link_timeout_s, and is given up (LOST, the swarm replanned around it) after lost_after_s; raise lost_after_s to at least {} s",
                link.lost_after_s, link.link_timeout_s, link.link_timeout_s
            ),
        );
    }
    if let Some(h) = link.speed_headroom
        && !(h.is_finite() && (0.0..=1.0).contains(&h))
    {
        report.add(
            "link.speed_headroom",
            format!(
                "must be a fraction from 0 to 1 (trajectories fly at the speed limit / (1 + headroom)), got {h}"
            ),
        );
    }
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
