//! Pre-flight: the autopilot's own geofence, derived from the mission, set on
//! every vehicle and read back.
//!
//! swarmctl's plan keeps every drone inside the mission's airspace; the fence is
//! what keeps it there when swarmctl is not the one flying it — the ground
//! station crashed, the link is gone, a rogue ground station or a fault streams
//! it away. The autopilot enforces it by itself and lands the vehicle (or only
//! warns: `fence.action`).
//!
//! Both autopilots measure their fence from home, which they set where they arm:
//! on the vehicle's pad. Each vehicle is given
//!
//! * a **maximum altitude** above its pad: the top of the airspace plus the
//!   margin (ArduPilot `FENCE_ALT_MAX`, PX4 `GF_MAX_VER_DIST`), and
//! * a **circle** around its pad that holds the airspace's whole footprint (the
//!   world and the launch area, whichever is wider) plus the margin (ArduPilot
//!   `FENCE_RADIUS`, PX4 `GF_MAX_HOR_DIST`).
//!
//! A circle, not the footprint's polygon: a circle is parameters, which both
//! autopilots take, report and keep alike, set and read back like the limits
//! (`vehicle_limits`); a polygon would be a fence plan uploaded with the mission
//! protocol, in each vehicle's geographic frame. The circle is wider than the
//! footprint by up to its corners: it keeps a runaway vehicle near the field,
//! not out of every corner of the neighbouring airspace.
//!
//! Setting it on a vehicle and reading it back is `parameters`. The fence is set
//! last, after the limits: a vehicle refused on a limit keeps
//! its old fence. After the flight it stays as set: every vehicle flies the next
//! flight (or a manual one) with the same airspace in it, and `fly` says so.

use crate::mission::{FenceAction, Mission};
use serde::{Deserialize, Serialize};

mod parameters;
mod span;

pub use parameters::apply;
pub use span::FenceSpan;

/// The box that holds the mission's airspace (the world and the launch area),
/// mission ENU metres, out to its voxels' faces.
///
/// Every voxel centre is half a voxel inside it, so a drone flying its plan —
/// within `limits.tracking_error_m` of a point between voxel centres — never
/// leaves it by more than that bound; one that does has left the plan for good
/// (its fence, a rogue ground station, a flyaway).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AirspaceBox {
    /// The lowest corner, mission ENU metres.
    pub min_enu_m: [f64; 3],
    /// The highest corner, mission ENU metres.
    pub max_enu_m: [f64; 3],
}

impl AirspaceBox {
    /// The box of the mission's airspace.
    pub fn of(mission: &Mission) -> AirspaceBox {
        let airspace = &mission.airspace;
        let half_m = airspace.voxel_size_m() / 2.0;
        let min = airspace.min_voxel();
        let [dx, dy, dz] = airspace.dimensions();
        let max = crate::world::Voxel::new(
            min.x + dx as i32 - 1,
            min.y + dy as i32 - 1,
            min.z + dz as i32 - 1,
        );
        let (lo, hi) = (airspace.center_m(min), airspace.center_m(max));
        AirspaceBox {
            min_enu_m: [lo.x - half_m, lo.y - half_m, lo.z - half_m],
            max_enu_m: [hi.x + half_m, hi.y + half_m, hi.z + half_m],
        }
    }

    /// How far `p_enu_m` lies outside the box, metres (0 inside).
    pub fn outside_by_m(&self, p_enu_m: [f64; 3]) -> f64 {
        let squared: f64 = (0..3)
            .map(|i| {
                (self.min_enu_m[i] - p_enu_m[i])
                    .max(p_enu_m[i] - self.max_enu_m[i])
                    .max(0.0)
                    .powi(2)
            })
            .sum();
        squared.sqrt()
    }
}

/// The mission's airspace and fence settings, from which each vehicle's fence is
/// derived with its pad ([`FencePlan::for_pad`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FencePlan {
    /// The airspace the fence stands around.
    pub airspace: AirspaceBox,
    /// How far beyond the airspace the fence stands, metres.
    pub margin_m: f64,
    /// What the autopilot does on a breach.
    pub action: FenceAction,
}

impl FencePlan {
    /// The mission's fence, or `None` when `fence.enabled` is false.
    pub fn of(mission: &Mission) -> Option<FencePlan> {
        mission.fence.enabled.then(|| FencePlan {
            airspace: AirspaceBox::of(mission),
            margin_m: mission.fence.margin_m,
            action: mission.fence.action,
        })
    }

    /// The fence of the vehicle whose pad (its home: both autopilots set home
    /// where they arm) is at `pad_enu_m`.
    pub fn for_pad(&self, pad_enu_m: [f64; 3]) -> VehicleFence {
        let (lo, hi) = (self.airspace.min_enu_m, self.airspace.max_enu_m);
        let farthest_east_m = (lo[0] - pad_enu_m[0])
            .abs()
            .max((hi[0] - pad_enu_m[0]).abs());
        let farthest_north_m = (lo[1] - pad_enu_m[1])
            .abs()
            .max((hi[1] - pad_enu_m[1]).abs());
        VehicleFence {
            radius_m: farthest_east_m.hypot(farthest_north_m) + self.margin_m,
            max_altitude_m: hi[2] - pad_enu_m[2] + self.margin_m,
            margin_m: self.margin_m,
            action: self.action,
        }
    }
}

/// One vehicle's fence, measured from its home (its pad).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct VehicleFence {
    /// Horizontal distance from home the vehicle may fly, metres.
    pub radius_m: f64,
    /// Height above home the vehicle may climb to, metres.
    pub max_altitude_m: f64,
    /// How far the fence stands beyond the airspace, metres.
    pub margin_m: f64,
    /// What the autopilot does on a breach.
    pub action: FenceAction,
}

impl std::fmt::Display for VehicleFence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:.1} m around its pad, {:.1} m above it, action {}",
            self.radius_m, self.max_altitude_m, self.action
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link::ParamValue;

    fn plan() -> FencePlan {
        FencePlan {
            airspace: AirspaceBox {
                min_enu_m: [-1.0, -2.0, 0.0],
                max_enu_m: [9.0, 4.0, 5.0],
            },
            margin_m: 2.0,
            action: FenceAction::Land,
        }
    }

    /// The circle reaches the footprint's farthest corner plus the margin, and the
    /// ceiling is the airspace's top above the pad plus the margin.
    #[test]
    fn the_circle_holds_the_whole_footprint_from_any_pad() {
        let fence = plan().for_pad([0.0, 0.0, 0.0]);
        assert!((fence.radius_m - (9.0f64.hypot(4.0) + 2.0)).abs() < 1e-9);
        assert!((fence.max_altitude_m - 7.0).abs() < 1e-9);
        for pad in [[-1.0, -2.0, 0.0], [9.0, 4.0, 0.0], [4.0, 1.0, 0.0]] {
            let fence = plan().for_pad(pad);
            for corner in [[-1.0, -2.0], [-1.0, 4.0], [9.0, -2.0], [9.0, 4.0]] {
                let d = (corner[0] - pad[0]).hypot(corner[1] - pad[1]);
                assert!(d + 2.0 <= fence.radius_m + 1e-9, "{pad:?} {corner:?}");
            }
        }
    }

    /// The mission's own airspace (world and pad layer) gives the plan's box: the
    /// bundled formation change's world is 10 × 6 × 4 voxels of 1 m.
    #[test]
    fn the_plan_is_the_airspace_box_of_the_mission() {
        let yaml = include_str!("../../../missions/formation-change.yaml");
        let mission =
            crate::mission::from_yaml(yaml, std::path::Path::new("formation-change.yaml"))
                .expect("valid mission");
        let plan = FencePlan::of(&mission).expect("on by default");
        let size: Vec<f64> = (0..3)
            .map(|i| plan.airspace.max_enu_m[i] - plan.airspace.min_enu_m[i])
            .collect();
        let [wx, wy, wz] = mission.world.dimensions();
        let s = mission.world.voxel_size_m();
        assert!(size[0] >= f64::from(wx) * s && size[1] >= f64::from(wy) * s);
        // The pad layer below the world adds one layer.
        assert!((size[2] - f64::from(wz + 1) * s).abs() < 1e-9, "{size:?}");
        assert_eq!(plan.margin_m, 2.0);
        let airspace = plan.airspace;
        assert_eq!(airspace.outside_by_m([0.0, 0.0, 1.0]), 0.0);
        assert!((airspace.outside_by_m([-3.5, 0.0, 1.0]) - 3.0).abs() < 1e-9);
        assert!(ParamValue::Int32(5).matches(f32::from_bits(5)));
        assert!(!ParamValue::Int32(5).matches(f32::from_bits(4)));
    }
}
