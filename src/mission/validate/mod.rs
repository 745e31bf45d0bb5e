//! Turns a parsed [`MissionFile`] into a [`Mission`], reporting every problem at once.
//!
//! The checks run in file order: the name, the world's extent and scale, the limits,
//! the link, then the obstacles, the groups with their drones and goals, the pads, the
//! stages and the landing, and last whether every drone can reach every formation of
//! its group from its pad, and whether every leg has room for all its drones at once.
//! Only the world's extent stops the checks early, since nothing placed in the world
//! can be checked without it; and reachability and room are only asked of a mission
//! that is otherwise valid.

mod bounds;
mod contests;
mod fence;
mod fields;
mod groups;
mod pads;
mod radios;
mod reachability;
mod relays;
mod report;
mod settings;
mod stacking;
mod stages;
mod world;

use super::error::Problem;
use super::schema::MissionFile;
use super::types::{DEFAULT_MAX_JERK_MPS3, Limits, LinkSettings, Mission};
use crate::world::Voxel;
use report::Report;

pub use bounds::{MAX_DIMENSION, MAX_VOXELS};
pub use settings::{MAX_VERTICAL_LAYERS, SETPOINT_RATES_HZ};

/// Checks a parsed mission. Returns every problem found, not just the first.
pub fn validate(file: &MissionFile) -> Result<Mission, Vec<Problem>> {
    let mut report = Report::default();
    settings::check_name(&file.name, &mut report);
    let dimensions = settings::check_world(&file.world, &mut report);
    settings::check_limits(&file.limits, file.world.voxel_size_m, &mut report);
    let separation_fits =
        settings::separation_fits_voxel(&file.limits, file.world.voxel_size_m, &mut report);
    let signing = settings::check_link(&file.link, &mut report);
    let relay_of = relays::check_relays(&file.link, &file.groups, &mut report);
    radios::check_radios(&file.link, &file.groups, &mut report);
    fence::check_fence(&file.fence, &mut report);
    if file.groups.is_empty() {
        report.add("groups", "a mission needs at least one group of drones");
    }
    let Some(dimensions) = dimensions else {
        return Err(report.into_problems());
    };
    let bounds = world::Bounds::new(dimensions);
    let (world, ground) = world::build(&file.world, &bounds, &mut report);
    let mut groups = groups::check_groups(&file.groups, &world, &bounds, &relay_of, &mut report);
    // A separation wider than a voxel is the cause to name: no pad layer would fit it.
    let pad_height_m = separation_fits
        .then(|| {
            pads::pad_height(
                &file.world,
                file.limits.horizontal_separation_m(),
                &mut report,
            )
        })
        .flatten();
    pads::assign_pads(&mut groups, &ground, &mut report);
    let stages = stages::check_stages(&file.stages, &groups, &world, &bounds, &mut report);
    let landing = file.landing.unwrap_or_default();
    // Where each drone may be when landing starts: the last goals, or a spare's hold.
    let final_targets: Vec<Vec<Voxel>> = super::legs::last_formations(&groups, &stages)
        .iter()
        .zip(&groups)
        .map(|(goals, g)| g.formation_targets(goals))
        .collect();
    stages::check_landing(landing, &final_targets, &world, &ground, &mut report);
    let Some(pad_height_m) = pad_height_m.filter(|_| report.is_empty()) else {
        return Err(report.into_problems());
    };
    let tracking_error_m = settings::tracking_error(
        &file.limits,
        file.world.voxel_size_m,
        file.world.origin_or_default_m()[2] - pad_height_m,
        &mut report,
    );
    let airspace = pads::airspace(&world, &ground, pad_height_m, &groups);
    let formations_use_pad_layer = file.world.formations_use_pad_layer;
    reachability::check_reachability(
        &airspace,
        formations_use_pad_layer,
        &groups,
        &stages,
        &mut report,
    );
    if !report.is_empty() {
        return Err(report.into_problems());
    }
    let (limits, link) = (&file.limits, &file.link);
    let limits = Limits {
        max_speed_mps: limits.max_speed_mps,
        max_accel_mps2: limits.max_accel_mps2,
        max_jerk_mps3: limits.max_jerk_mps3.unwrap_or(DEFAULT_MAX_JERK_MPS3),
        safety_distance_m: limits.horizontal_separation_m(),
        vertical_separation_m: limits.separation.map(|e| e.vertical_m),
        tracking_error_m,
    };
    stacking::check_stacking(&airspace, &limits, &groups, &stages, &mut report);
    if !report.is_empty() {
        return Err(report.into_problems());
    }
    let mission = Mission {
        name: file.name.clone(),
        description: file.description.clone(),
        world,
        airspace,
        formations_use_pad_layer,
        limits,
        geo_origin: file.world.geo_origin,
        link: link_settings(link, signing),
        groups,
        stages,
        landing,
        fence: file.fence,
    };
    contests::check_leg_targets(&mission, &mut report);
    if !report.is_empty() {
        return Err(report.into_problems());
    }
    Ok(mission)
}

/// The validated link section: the file's, with the defaults that depend on the
/// autopilot filled in.
fn link_settings(
    link: &super::schema::LinkSpec,
    signing: Option<super::types::KeySource>,
) -> LinkSettings {
    LinkSettings {
        autopilot: link.autopilot,
        setpoint_rate_hz: link.setpoint_rate_hz,
        link_timeout_s: link.link_timeout_s,
        lost_after_s: link.lost_after_s,
        speed_headroom: link
            .speed_headroom
            .unwrap_or_else(|| link.autopilot.speed_overshoot()),
        signing,
        relays: link.relays.clone(),
        zenoh: link.zenoh.clone(),
        radios: link.radios.clone(),
    }
}
