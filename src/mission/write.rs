//! Writes mission files in the compact style people write by hand.
//!
//! A generic YAML serialiser would put every coordinate on a line of its own; a 100-drone mission
//! would run to a thousand lines nobody can read.

use super::schema::{MissionFile, ObstacleSpec, RawVoxel};
use std::fmt::Write;

/// Renders a mission as YAML that [`super::parse_yaml`] reads back unchanged.
///
/// ```
/// use swarmctl::generate::{generate, GenerateOptions};
/// use swarmctl::mission;
/// let file = generate(&GenerateOptions { drones: 4, groups: 2, ..Default::default() }).unwrap();
/// let text = mission::to_yaml(&file);
/// assert!(text.contains("dimensions: [10, 10, 5]"));
/// assert_eq!(mission::parse_yaml(&text).unwrap(), file);
/// ```
pub fn to_yaml(file: &MissionFile) -> String {
    let mut out = String::new();
    // Writing to a String cannot fail.
    let _ = write_mission(&mut out, file);
    out
}

fn write_mission(out: &mut String, file: &MissionFile) -> std::fmt::Result {
    writeln!(out, "name: {}", quoted(&file.name))?;
    if let Some(description) = &file.description {
        writeln!(out, "description: {}", quoted(description))?;
    }
    let world = &file.world;
    writeln!(out, "world:")?;
    writeln!(out, "  dimensions: {}", voxel(world.dimensions))?;
    writeln!(out, "  voxel_size_m: {:?}", world.voxel_size_m)?;
    if let Some(origin_m) = world.origin_m {
        writeln!(out, "  origin_m: {origin_m:?}")?;
    }
    if !world.formations_use_pad_layer {
        writeln!(out, "  formations_use_pad_layer: false")?;
    }
    if let Some(h) = world.pad_height_m {
        writeln!(out, "  pad_height_m: {h:?}")?;
    }
    if let Some(g) = &world.geo_origin {
        writeln!(
            out,
            "  geo_origin: {{ lat_deg: {:?}, lon_deg: {:?}, alt_m: {:?} }}",
            g.lat_deg, g.lon_deg, g.alt_m
        )?;
    }
    if world.obstacles.is_empty() {
        writeln!(out, "  obstacles: []")?;
    } else {
        writeln!(out, "  obstacles:")?;
        for obstacle in &world.obstacles {
            match obstacle {
                ObstacleSpec::Cell(v) => writeln!(out, "    - {}", voxel(*v))?,
                ObstacleSpec::Box(b) => writeln!(
                    out,
                    "    - {{ min: {}, max: {}{} }}",
                    voxel(b.min),
                    voxel(b.max),
                    if b.overhead { ", overhead: true" } else { "" }
                )?,
            }
        }
    }
    write_limits_and_link(out, file)?;
    writeln!(out, "groups:")?;
    for group in &file.groups {
        writeln!(out, "  - name: {}", quoted(&group.name))?;
        writeln!(out, "    drones:")?;
        for d in &group.drones {
            write!(out, "      - {{ id: {}", quoted(&d.id))?;
            if let Some(start) = d.start {
                write!(out, ", start: {}", voxel(start))?;
            }
            if let Some([x, y]) = d.pad {
                write!(out, ", pad: [{x}, {y}]")?;
            }
            if let Some(endpoint) = &d.endpoint {
                write!(out, ", endpoint: {}", quoted(endpoint))?;
            }
            if let Some(system_id) = d.system_id {
                write!(out, ", system_id: {system_id}")?;
            }
            writeln!(out, " }}")?;
        }
        let goals: Vec<String> = group.goals.iter().map(|&g| voxel(g)).collect();
        writeln!(out, "    goals: [{}]", goals.join(", "))?;
    }
    if !file.stages.is_empty() {
        writeln!(out, "stages:")?;
        for stage in &file.stages {
            writeln!(out, "  - name: {}", quoted(&stage.name))?;
            if let Some(hold_s) = stage.hold_s {
                writeln!(out, "    hold_s: {hold_s:?}")?;
            }
            writeln!(out, "    goals:")?;
            for (group, goals) in &stage.goals {
                let goals: Vec<String> = goals.iter().map(|&g| voxel(g)).collect();
                writeln!(out, "      {}: [{}]", quoted(group), goals.join(", "))?;
            }
        }
    }
    if let Some(landing) = file.landing {
        writeln!(out, "landing: {landing}")?;
    }
    Ok(())
}

fn voxel([x, y, z]: RawVoxel) -> String {
    format!("[{x}, {y}, {z}]")
}

/// A JSON string literal is a valid YAML double-quoted scalar.
fn quoted(s: &str) -> String {
    serde_json::Value::from(s).to_string()
}

/// The `limits` and `link` sections.
fn write_limits_and_link(out: &mut String, file: &MissionFile) -> std::fmt::Result {
    let limits = &file.limits;
    writeln!(out, "limits:")?;
    writeln!(out, "  max_speed_mps: {:?}", limits.max_speed_mps)?;
    writeln!(out, "  max_accel_mps2: {:?}", limits.max_accel_mps2)?;
    if let Some(j) = limits.max_jerk_mps3 {
        writeln!(out, "  max_jerk_mps3: {j:?}")?;
    }
    if let Some(d) = limits.safety_distance_m {
        writeln!(out, "  safety_distance_m: {d:?}")?;
    }
    if let Some(e) = limits.separation {
        writeln!(
            out,
            "  separation: {{ horizontal_m: {:?}, vertical_m: {:?} }}",
            e.horizontal_m, e.vertical_m
        )?;
    }
    if let Some(e) = limits.tracking_error_m {
        writeln!(out, "  tracking_error_m: {e:?}")?;
    }
    let link = &file.link;
    writeln!(out, "link:")?;
    writeln!(out, "  autopilot: {}", link.autopilot)?;
    writeln!(out, "  setpoint_rate_hz: {:?}", link.setpoint_rate_hz)?;
    writeln!(out, "  link_timeout_s: {:?}", link.link_timeout_s)?;
    writeln!(out, "  lost_after_s: {:?}", link.lost_after_s)?;
    if let Some(h) = link.speed_headroom {
        writeln!(out, "  speed_headroom: {h:?}")?;
    }
    if let Some(signing) = &link.signing {
        writeln!(out, "  signing:")?;
        if let Some(file) = &signing.key_file {
            writeln!(out, "    key_file: {}", quoted(&file.to_string_lossy()))?;
        }
        if let Some(var) = &signing.key_env {
            writeln!(out, "    key_env: {}", quoted(var))?;
        }
    }
    Ok(())
}
