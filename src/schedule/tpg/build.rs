//! Building the TPG: the limits checked, the markers placed on each move, then every
//! drone's events and the cross-drone edges assembled into one graph.

use super::events::drone_events;
use super::handover::{cross_candidates, minimal_edges};
use super::holds::hold_edges;
use super::{Tpg, TpgDrone};
use crate::mission::{Limits, Mission};
use crate::plan::DiscretePlan;
use crate::schedule::ScheduleError;
use crate::world::{Voxel, VoxelGrid};

/// Builds the TPG of `plan` for `mission`: events, markers and minimal type-2 edges,
/// with the mission's setpoint period for the gates' decision lead.
///
/// Fails with a clear error if the safety distance exceeds the voxel size, if a path is
/// malformed, or if two drones meet in a voxel or swap along an edge.
pub fn build(mission: &Mission, plan: &DiscretePlan) -> Result<Tpg, ScheduleError> {
    let mut tpg = build_with(&mission.airspace, &mission.commanded_limits(), plan)?;
    tpg.setpoint_period_s = 1.0 / mission.link.setpoint_rate_hz;
    Ok(tpg)
}

/// [`build`] from a world and limits rather than a whole mission, with no
/// setpoint period (no decision lead is budgeted).
pub fn build_with(
    world: &VoxelGrid,
    limits: &Limits,
    plan: &DiscretePlan,
) -> Result<Tpg, ScheduleError> {
    let s = world.voxel_size_m();
    // Setpoints are kept apart by the safety distance plus both drones' tracking
    // error; everything below argues about setpoints with this `d`.
    let d = limits.setpoint_separation_m();
    if !(limits.tracking_error_m.is_finite() && limits.tracking_error_m >= 0.0) {
        return Err(ScheduleError::BadLimit {
            name: "limits.tracking_error_m",
            value: limits.tracking_error_m,
        });
    }
    for (name, value) in [
        ("world.voxel_size_m", s),
        ("limits.safety_distance_m", limits.safety_distance_m),
        ("limits.max_speed_mps", limits.max_speed_mps),
        ("limits.max_accel_mps2", limits.max_accel_mps2),
        ("limits.max_jerk_mps3", limits.max_jerk_mps3),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(ScheduleError::BadLimit { name, value });
        }
    }
    if d > s {
        return Err(ScheduleError::SafetyDistanceTooLarge {
            safety_distance_m: d,
            voxel_size_m: s,
        });
    }
    // Under an ellipsoid vertical spacing is kept by the vertical reach instead.
    let reach = limits.vertical_reach(world);
    if let Some(pad_z_m) = world.pad_layer_z_m().filter(|_| !limits.is_ellipsoid()) {
        let gap_m = world.center_m(Voxel::new(0, 0, 0)).z - pad_z_m;
        if gap_m < d {
            return Err(ScheduleError::SafetyDistanceTooLarge {
                safety_distance_m: d,
                voxel_size_m: gap_m,
            });
        }
    }
    let delta = 0.5 * (s - d);
    let vertical_marker_m = limits.is_ellipsoid().then_some(reach.vertical_marker_m);
    // Markers sit (length − d) / 2 from each end of a move (moves into and out of
    // the pad layer may be shorter or longer than a voxel), except on an
    // ellipsoid's vertical moves.
    let marker_m = |length_m: f64, vertical: bool| match vertical_marker_m {
        Some(sigma_m) if vertical => sigma_m,
        _ => 0.5 * (length_m - d).max(0.0),
    };
    let mut drones = Vec::with_capacity(plan.drones.len());
    let mut visits = Vec::with_capacity(plan.drones.len());
    for drone in &plan.drones {
        let (events, drone_visits) = drone_events(world, plan.makespan_steps, drone, &marker_m)?;
        drones.push(TpgDrone {
            id: drone.id.clone(),
            events,
        });
        visits.push(drone_visits);
    }
    let candidates = cross_candidates(world, plan, &visits, reach)?;
    let mut cross_edges = minimal_edges(candidates);
    cross_edges.extend(hold_edges(plan, &visits, &mut drones));
    cross_edges.sort_unstable_by_key(|e| (e.to, e.from));
    Ok(Tpg {
        voxel_size_m: s,
        separation_m: d,
        safety_distance_m: limits.safety_distance_m,
        marker_offset_m: delta,
        hold_radius_m: 0.5 * (s + d),
        vertical_marker_m,
        max_speed_mps: limits.max_speed_mps,
        max_accel_mps2: limits.max_accel_mps2,
        max_jerk_mps3: limits.max_jerk_mps3,
        drones,
        cross_edges,
        setpoint_period_s: 0.0,
    })
}
