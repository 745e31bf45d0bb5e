//! Launch pads: the pad layer's height, one distinct pad per drone (written, below
//! its start, or assigned), and the airspace that reaches over all of them.
//!
//! The pad layer is a layer of cells below voxel layer 0 (`z = -1`), one per ground
//! cell `[x, y]`, centred at the pads' hover height: the slab from the ground up to
//! layer 0's lower face. Obstacles stand on the ground, so the cell under an
//! obstacle's column is blocked (unless it is overhead), and no pad lies there. A
//! drone takes off vertically from its pad to the cell above it and lands from a
//! pad-layer cell straight down; between, it moves in the pad layer like in any
//! other layer. So the layer needs
//! room: its hover height above the ground, and at least the safety distance between
//! it and layer 0 (the schedule's separation argument needs every two cell centres at
//! least the safety distance apart).

use super::bounds::PAD_REACH;
use super::report::Report;
use super::world::GroundCells;
use crate::mission::schema::WorldSpec;
use crate::mission::types::{Group, PadSource};
use crate::world::{Voxel, VoxelGrid};
use std::collections::HashMap;

/// The default pad layer is one voxel below layer 0 only if that leaves at least this
/// much hover height; otherwise it sits halfway between the ground and layer 0.
const MIN_UNIFORM_HOVER_M: f64 = 0.5;

/// The pad layer's hover height, metres above ground, when there is room for it.
/// Only asked when the safety distance fits the voxel size (else that is the cause
/// to report, and no pad height would help).
pub(super) fn pad_height(
    spec: &WorldSpec,
    safety_distance_m: f64,
    report: &mut Report,
) -> Option<f64> {
    let layer0_m = spec.origin_or_default_m()[2];
    let s = spec.voxel_size_m;
    if !(layer0_m.is_finite() && s.is_finite() && s > 0.0) {
        return None;
    }
    let (height_m, path) = match spec.pad_height_m {
        Some(h) => (h, "world.pad_height_m"),
        None if layer0_m - s >= MIN_UNIFORM_HOVER_M => (layer0_m - s, "world.origin_m"),
        None => (0.5 * layer0_m, "world.origin_m"),
    };
    let gap_m = layer0_m - height_m;
    if height_m.is_finite() && height_m > 0.0 && gap_m >= safety_distance_m {
        return Some(height_m);
    }
    // What fixes it: layer 0 high enough for the default pad layer (a voxel below,
    // half a metre up), or a pad height between the ground and the safety distance
    // below layer 0.
    let lowest_layer0_m = s + MIN_UNIFORM_HOVER_M;
    let highest_pad_m = layer0_m - safety_distance_m;
    let fix = if highest_pad_m > 0.0 {
        format!(
            "set world.pad_height_m above 0 and at most {highest_pad_m:.2} m, or raise world.origin_m z to at least {lowest_layer0_m:.2} m (the default pad layer then hovers {MIN_UNIFORM_HOVER_M} m up, one voxel below layer 0)"
        )
    } else {
        format!(
            "raise world.origin_m z to at least {lowest_layer0_m:.2} m (the default pad layer then hovers {MIN_UNIFORM_HOVER_M} m up, one voxel below layer 0)"
        )
    };
    let why = if height_m.is_finite() && height_m > 0.0 {
        format!(
            "the pad layer at {height_m:.2} m is only {gap_m:.2} m below voxel layer 0 ({layer0_m:.2} m above the ground), less than the safety distance ({safety_distance_m:.2} m)"
        )
    } else {
        format!(
            "the pad layer would be at {height_m:.2} m, not above the ground (voxel layer 0 is {layer0_m:.2} m above it)"
        )
    };
    report.add(path, format!("no room for the pad layer: {why}; {fix}"));
    None
}

/// Gives every drone without a written pad the cell below its start when no other
/// pad takes it and no obstacle stands there, else the nearest such cell; reports
/// pads used twice and written pads under an obstacle.
///
/// Deterministic: written pads first, then drones in file order take the cell below
/// their start, then the remaining drones, in file order, the nearest free cell
/// (least squared distance from their start's column, ties by y then x).
pub(super) fn assign_pads(groups: &mut [Group], ground: &GroundCells, report: &mut Report) {
    let mut taken: HashMap<[i32; 2], String> = HashMap::new();
    // Obstacles standing on the ground take their cells before any drone.
    for &cell in ground {
        taken.insert(cell, String::new());
    }
    let path = |gi: usize, di: usize| format!("groups[{gi}].drones[{di}].pad");
    for (gi, g) in groups.iter().enumerate() {
        for (di, d) in g.drones.iter().enumerate() {
            if d.pad_source != PadSource::Given {
                continue;
            }
            if ground.contains(&d.pad) {
                report.add(
                    path(gi, di),
                    format!(
                        "pad {:?} is under an obstacle that stands on the ground (world.obstacles): put the pad beside it, or make the obstacle `overhead: true` if the space below it is free",
                        d.pad
                    ),
                );
                continue;
            }
            if let Some(first) = taken.insert(d.pad, path(gi, di)) {
                report.add(
                    path(gi, di),
                    format!(
                        "pad {:?} is already the pad of {first}: every drone needs its own pad",
                        d.pad
                    ),
                );
            }
        }
    }
    let mut pending = Vec::new();
    for (gi, g) in groups.iter_mut().enumerate() {
        for (di, d) in g.drones.iter_mut().enumerate() {
            if d.pad_source == PadSource::Given {
                continue;
            }
            match d.start {
                Some(start) if !taken.contains_key(&[start.x, start.y]) => {
                    d.pad = [start.x, start.y];
                    d.pad_source = PadSource::BelowStart;
                    taken.insert(d.pad, path(gi, di));
                }
                _ => pending.push((gi, di)),
            }
        }
    }
    for (gi, di) in pending {
        let d = &mut groups[gi].drones[di];
        let column = d.start.map_or([0, 0], |s| [s.x, s.y]);
        if let Some(pad) = nearest_free(column, &taken) {
            d.pad = pad;
            d.pad_source = PadSource::Assigned;
            taken.insert(pad, path(gi, di));
        }
    }
}

/// The free cell nearest to `column`: rings of growing Chebyshev radius, within a ring
/// the least squared distance, then y, then x.
fn nearest_free(column: [i32; 2], taken: &HashMap<[i32; 2], String>) -> Option<[i32; 2]> {
    let reach = PAD_REACH as i32;
    for r in 1..=reach {
        let mut ring: Vec<[i32; 2]> = Vec::with_capacity(8 * r as usize);
        for dy in -r..=r {
            for dx in -r..=r {
                if dx.abs() == r || dy.abs() == r {
                    ring.push([column[0] + dx, column[1] + dy]);
                }
            }
        }
        ring.sort_by_key(|&[x, y]| {
            let (dx, dy) = (x - column[0], y - column[1]);
            (dx * dx + dy * dy, y, x)
        });
        if let Some(&cell) = ring.iter().find(|c| !taken.contains_key(*c)) {
            return Some(cell);
        }
    }
    None
}

/// The airspace: `world` with a pad layer at `pad_height_m` reaching over every pad,
/// blocked where obstacles stand on the ground.
pub(super) fn airspace(
    world: &VoxelGrid,
    ground: &GroundCells,
    pad_height_m: f64,
    groups: &[Group],
) -> VoxelGrid {
    let pads = || groups.iter().flat_map(|g| g.drones.iter().map(|d| d.pad));
    let xs = pads().map(|p| p[0]);
    let ys = pads().map(|p| p[1]);
    let (x_lo, x_hi) = (xs.clone().min().unwrap_or(0), xs.max().unwrap_or(0));
    let (y_lo, y_hi) = (ys.clone().min().unwrap_or(0), ys.max().unwrap_or(0));
    let mut airspace = VoxelGrid::airspace(world, pad_height_m, x_lo..=x_hi, y_lo..=y_hi);
    for &[x, y] in ground {
        airspace.block(Voxel::new(x, y, -1));
    }
    airspace
}

/// The first obstacle between `goal` and the ground in its column, if any, the pad
/// layer's cell included: what rules out a `below_goal` descent.
pub(super) fn blocked_below(world: &VoxelGrid, ground: &GroundCells, goal: Voxel) -> Option<Voxel> {
    (0..goal.z)
        .rev()
        .map(|z| Voxel::new(goal.x, goal.y, z))
        .find(|&v| world.is_blocked(v))
        .or_else(|| ground.contains(&[goal.x, goal.y]).then(|| goal.pad_below()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_free_walks_rings_deterministically() {
        let mut taken = HashMap::new();
        taken.insert([0, 0], String::new());
        // Radius 1, distance 1: (0,-1) has the smallest y.
        assert_eq!(nearest_free([0, 0], &taken), Some([0, -1]));
        taken.insert([0, -1], String::new());
        assert_eq!(nearest_free([0, 0], &taken), Some([-1, 0]));
    }
}
