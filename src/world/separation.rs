//! How close two drones may come: a sphere, or an axis-aligned ellipsoid that reaches
//! further below and above a drone than beside it (its downwash).
//!
//! Two drones are *separated* when their scaled distance
//! `√((dx/H)² + (dy/H)² + (dz/V)²)` is at least 1, with `H` the horizontal and `V`
//! the vertical separation. A sphere of radius `d` is `H = V = d`, and its scaled
//! distance is the distance over `d`.
//!
//! ```
//! use swarmctl::world::Separation;
//! let ellipsoid = Separation { horizontal_m: 0.25, vertical_m: 0.75 };
//! // 0.4 m side by side is fine, 0.4 m above is not.
//! assert!(ellipsoid.scaled([0.4, 0.0, 0.0]) >= 1.0);
//! assert!(ellipsoid.scaled([0.0, 0.0, 0.4]) < 1.0);
//! ```

use super::{Voxel, VoxelGrid};
use serde::{Deserialize, Serialize};

/// The separation two drones keep: their scaled distance (see the module docs) is at
/// least 1.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Separation {
    /// Radius beside a drone, metres; positive.
    pub horizontal_m: f64,
    /// Radius above and below a drone, metres; positive.
    pub vertical_m: f64,
}

impl Separation {
    /// A sphere of radius `distance_m`.
    pub fn sphere(distance_m: f64) -> Self {
        Self {
            horizontal_m: distance_m,
            vertical_m: distance_m,
        }
    }

    /// Whether this is a sphere (both radii equal).
    pub fn is_sphere(&self) -> bool {
        self.horizontal_m == self.vertical_m
    }

    /// The scaled distance of the offset `delta_m` (ENU metres) between two drones:
    /// they are separated when it is at least 1.
    pub fn scaled(&self, delta_m: [f64; 3]) -> f64 {
        let [dx, dy, dz] = delta_m;
        ((dx * dx + dy * dy) / (self.horizontal_m * self.horizontal_m)
            + dz * dz / (self.vertical_m * self.vertical_m))
            .sqrt()
    }
}

/// Which cells of one column two drones may not hold at the same time, and where the
/// safety markers sit on vertical moves, for an ellipsoid whose setpoint radii are
/// `H'` (at most the voxel size) and `V'` (any): see the schedule module's safety
/// argument. For a sphere nothing but the cell itself is related.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerticalReach {
    /// Two distinct cells of one column are related when their centres are closer
    /// than this, metres (0 for a sphere: no two distinct cells are), or no further
    /// apart than `V'` (see [`VerticalReach::related`]).
    pub reach_m: f64,
    /// The markers' distance from each end of a vertical move, metres (for an
    /// ellipsoid; a sphere keeps `(length − d) / 2` on every move).
    pub vertical_marker_m: f64,
}

impl VerticalReach {
    /// No cell related to another: the sphere's model.
    pub const NONE: Self = Self {
        reach_m: 0.0,
        vertical_marker_m: 0.0,
    };

    /// The reach of setpoint radii `setpoint` in `airspace` (voxel size `s`, and the
    /// pad layer's gap `g` below layer 0 when it has one): markers at
    /// `σ = max(0, (min(s, g) − V') / 2)` from each end of every vertical move, and
    /// cells related when their centres are closer than `V' + 2σ` (or exactly `V'`
    /// apart).
    pub fn new(airspace: &VoxelGrid, setpoint: Separation) -> Self {
        let spacing_m = vertical_spacing_m(airspace);
        let marker_m = (0.5 * (spacing_m - setpoint.vertical_m)).max(0.0);
        Self {
            reach_m: setpoint.vertical_m + 2.0 * marker_m,
            vertical_marker_m: marker_m,
        }
    }

    /// Whether two *distinct* drones may not hold `a` and `b` at the same time
    /// because of the vertical reach (same column, centres closer than the reach).
    /// A cell is never related to itself here: that is an ordinary vertex conflict.
    ///
    /// Centres exactly `V'` apart are related too. Setpoints that far apart one
    /// above the other are on the boundary of each other's cylinder: separated, but
    /// with nothing to spare, and two drones passing so (one at a pad-layer cell `V'`
    /// below a layer-0 cell the other flies through) would fail the trajectory
    /// checker, which charges moving drones for straying from their chords. Only
    /// when `σ = 0` can centres be that close without being closer than the reach.
    pub fn related(&self, airspace: &VoxelGrid, a: Voxel, b: Voxel) -> bool {
        let apart_m = (airspace.center_m(a).z - airspace.center_m(b).z).abs();
        a != b
            && a.x == b.x
            && a.y == b.y
            && (apart_m < self.reach_m - 1e-9 || apart_m <= self.vertical_setpoint_m() + 1e-9)
    }

    /// `V'`: the vertical radius of the setpoints' cylinder, from the reach and the
    /// markers (`reach = V' + 2σ`).
    fn vertical_setpoint_m(&self) -> f64 {
        self.reach_m - 2.0 * self.vertical_marker_m
    }

    /// Whether any two distinct cells are related at all.
    pub fn is_trivial(&self, airspace: &VoxelGrid) -> bool {
        let spacing_m = vertical_spacing_m(airspace);
        self.reach_m <= spacing_m + 1e-9 && self.vertical_setpoint_m() < spacing_m - 1e-9
    }

    /// The cells of `airspace` related to `v` (free or not), nearest first.
    pub fn related_cells(&self, airspace: &VoxelGrid, v: Voxel) -> Vec<Voxel> {
        // The schedule asks this for every visit of every drone: a sphere (or a
        // flat ellipsoid) answers without walking the column or allocating.
        if self.is_trivial(airspace) {
            return Vec::new();
        }
        let [_, _, depth] = airspace.dimensions();
        let bottom = airspace.min_voxel().z;
        let mut out: Vec<Voxel> = (0..depth)
            .map(|k| Voxel::new(v.x, v.y, bottom + k as i32))
            .filter(|&w| self.related(airspace, v, w))
            .collect();
        out.sort_by_key(|w| (w.z - v.z).abs());
        out
    }
}

/// The smallest vertical distance between two neighbouring cell centres: the voxel
/// size, or the pad layer's gap below layer 0 when that is less.
fn vertical_spacing_m(airspace: &VoxelGrid) -> f64 {
    let s = airspace.voxel_size_m();
    match airspace.pad_layer_z_m() {
        Some(pad_z_m) => s.min(airspace.center_m(Voxel::new(0, 0, 0)).z - pad_z_m),
        None => s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sphere_scales_by_its_radius() {
        let s = Separation::sphere(0.5);
        assert!((s.scaled([0.3, 0.0, 0.4]) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_ellipsoid_relates_one_layer_when_its_height_exceeds_a_voxel() {
        let grid = VoxelGrid::new([2, 2, 5], 1.0, [0.0, 0.0, 0.0]);
        let reach = VerticalReach::new(
            &grid,
            Separation {
                horizontal_m: 0.5,
                vertical_m: 1.35,
            },
        );
        assert_eq!(reach.vertical_marker_m, 0.0);
        let v = Voxel::new(1, 1, 2);
        assert_eq!(
            reach.related_cells(&grid, v),
            vec![Voxel::new(1, 1, 1), Voxel::new(1, 1, 3)]
        );
        assert!(!reach.related(&grid, v, Voxel::new(0, 1, 3)));
        assert!(!reach.is_trivial(&grid));
    }

    #[test]
    fn a_flat_ellipsoid_relates_no_two_cells_and_keeps_markers_off_the_ends() {
        let grid = VoxelGrid::new([2, 2, 5], 1.0, [0.0, 0.0, 0.0]);
        let reach = VerticalReach::new(
            &grid,
            Separation {
                horizontal_m: 0.5,
                vertical_m: 0.9,
            },
        );
        assert!((reach.vertical_marker_m - 0.05).abs() < 1e-12);
        assert!(reach.is_trivial(&grid));
        assert!(reach.related_cells(&grid, Voxel::new(0, 0, 2)).is_empty());
    }
}
