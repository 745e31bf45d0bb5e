//! Where a drone stops when the swarm freezes for a replan, and which voxels a lost
//! drone may still be in.
//!
//! A replan plans from voxels, so every surviving drone must end up at rest at a
//! voxel centre. Which one follows from the safety markers of the Temporal Plan
//! Graph (see [`schedule`](crate::schedule)): on a move from `u` to `w` a drone
//! holds `u` until its `Leave u` marker and `w` from its `Enter w` marker on, and
//! the TPG keeps every other drone out of a voxel while it is held. The freeze
//! first brakes everyone to rest along their routes (a delay, which the TPG always
//! absorbs), then each drone goes to the centre of a voxel it holds at that point:
//!
//! - at rest on or just past a `Start` or `Arrive` event, before the next
//!   `Enter`: the voxel it is in; it is (nearly) at its centre;
//! - past `Enter w` but not `Leave u`: back to `u`, whose whole stretch up to
//!   `Leave u` it holds (it never went past a closed gate, so it may not be able
//!   to go on to `w`);
//! - past `Leave u`: on to `w`, the only voxel it still holds; no gate lies
//!   between `Leave u` and `Arrive w` (gates are on `Enter` markers and rests).
//!
//! Either way the move stays on the route's straight segment inside the held
//! voxel's stretch, so nobody comes within the safety distance of another: **no
//! drone stops inside a voxel another drone holds.**

use super::path::Route;
use crate::mission::Mission;
use crate::plan::DiscretePlan;
use crate::schedule::EventKind;
use crate::world::Voxel;

/// Arc lengths this close count as the same point, metres.
const ARC_EPS_M: f64 = 1e-4;

/// The voxel centre a frozen drone goes to, and what the replan needs of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreezeTarget {
    /// The voxel it holds and will start the new plan from.
    pub voxel: Voxel,
    /// Its centre, ENU metres.
    pub position_m: [f64; 3],
    /// The old plan's step at which the drone is (or was) there: which leg it is in.
    pub step: u32,
}

/// Where a drone at rest at arc length `arc_m` along `route` freezes (see the
/// module docs); `None` for a route without events.
pub fn freeze_target(route: &Route, arc_m: f64) -> Option<FreezeTarget> {
    let events = &route.events;
    let passed = events
        .iter()
        .rposition(|e| e.arc_m <= arc_m + ARC_EPS_M)
        .unwrap_or(0);
    let is_centre = |k: EventKind| matches!(k, EventKind::Start | EventKind::Arrive);
    let index = match events.get(passed)?.kind {
        EventKind::Start | EventKind::Arrive => passed,
        // Holds the voxel it came from: back to that centre.
        EventKind::Enter => events[..passed].iter().rposition(|e| is_centre(e.kind))?,
        // Holds only the voxel it is moving into: on to its centre.
        EventKind::Leave => {
            passed
                + events[passed..]
                    .iter()
                    .position(|e| e.kind == EventKind::Arrive)?
        }
    };
    let e = &events[index];
    Some(FreezeTarget {
        voxel: e.voxel,
        position_m: e.position_m,
        step: e.step,
    })
}

/// The voxels a drone that stopped reporting may be in: every voxel of its route
/// from the last centre at or before `observed_arc_m` (where telemetry last saw
/// it) to the first centre at or after `commanded_arc_m` (where it was told to
/// go), and the voxel nearest its last reported `position_m`. A replan blocks
/// each with its column (see [`plan::replan`](crate::plan::replan)).
pub fn lost_voxels(
    mission: &Mission,
    route: &Route,
    observed_arc_m: f64,
    commanded_arc_m: f64,
    position_m: Option<[f64; 3]>,
) -> Vec<Voxel> {
    let events = &route.events;
    let is_centre = |k: EventKind| matches!(k, EventKind::Start | EventKind::Arrive);
    let from = events
        .iter()
        .rposition(|e| is_centre(e.kind) && e.arc_m <= observed_arc_m + ARC_EPS_M)
        .unwrap_or(0);
    let ahead = commanded_arc_m.max(observed_arc_m) - ARC_EPS_M;
    let to = events
        .iter()
        .position(|e| is_centre(e.kind) && e.arc_m >= ahead)
        .unwrap_or(events.len().saturating_sub(1));
    let mut voxels: Vec<Voxel> = events
        .get(from..=to.max(from))
        .unwrap_or_default()
        .iter()
        .map(|e| e.voxel)
        .collect();
    if let Some(v) = position_m.and_then(|p| nearest_voxel(mission, p)) {
        voxels.push(v);
    }
    voxels.sort_unstable();
    voxels.dedup();
    voxels
}

/// The voxels whose columns a drone down (or holding) at `position_m` blocks: the
/// one nearest it and every other in that layer whose centre is within
/// `clearance_m` of it horizontally. A drone its autopilot landed between two
/// cells is too close to both columns for anyone to descend there (the executor
/// refuses such a landing and hands the drone over), so a replan must keep
/// every such column free, not only the nearest.
pub fn voxels_near(mission: &Mission, position_m: [f64; 3], clearance_m: f64) -> Vec<Voxel> {
    let Some(nearest) = nearest_voxel(mission, position_m) else {
        return Vec::new();
    };
    let airspace = &mission.airspace;
    let reach = (clearance_m / airspace.voxel_size_m())
        .ceil()
        .clamp(0.0, 8.0) as i32;
    let mut voxels = vec![nearest];
    for dx in -reach..=reach {
        for dy in -reach..=reach {
            let v = Voxel::new(nearest.x + dx, nearest.y + dy, nearest.z);
            let c = airspace.center_m(v);
            let horizontal_m = (c.x - position_m[0]).hypot(c.y - position_m[1]);
            if v != nearest && horizontal_m < clearance_m && airspace.contains(v) {
                voxels.push(v);
            }
        }
    }
    voxels
}

/// The airspace voxel whose centre is nearest `position_m` (ENU), if the point
/// is inside the airspace's horizontal extent; below half-way to layer 0 (on the
/// ground too), the pad-layer cell above.
pub fn nearest_voxel(mission: &Mission, position_m: [f64; 3]) -> Option<Voxel> {
    let airspace = &mission.airspace;
    let s = airspace.voxel_size_m();
    let [ox, oy, oz] = airspace.origin_m();
    let x = ((position_m[0] - ox) / s).round();
    let y = ((position_m[1] - oy) / s).round();
    let min_z = airspace.min_voxel().z;
    let z = match airspace.pad_layer_z_m() {
        // Below half-way between the pad layer and layer 0: the pad layer.
        Some(pad_z_m) if position_m[2] < (pad_z_m + oz) / 2.0 => f64::from(min_z),
        _ => ((position_m[2] - oz) / s).round().max(0.0),
    };
    let fits = |c: f64| c.is_finite() && c.abs() < f64::from(i32::MAX);
    if !(fits(x) && fits(y) && fits(z)) {
        return None;
    }
    let v = Voxel::new(x as i32, y as i32, z as i32);
    airspace.contains(v).then_some(v)
}

/// The index in `mission.legs()` of the leg a drone at `step` of `plan` is in
/// (the leg that ends at or after it); `None` when the plan names no such leg.
pub fn leg_at(mission: &Mission, plan: &DiscretePlan, step: u32) -> Option<usize> {
    let leg = plan
        .legs
        .iter()
        .find(|l| step <= l.end_step)
        .or(plan.legs.last())?;
    mission.legs().iter().position(|l| l.name == leg.name)
}

/// The leg a replan starts from: the one the least advanced survivor is in (its
/// freeze target's `step`), except that takeoff's targets (the starts) are only
/// waypoints on the way to the first formation — a survivor already past its
/// start would be sent back to it — so a replan during takeoff flies straight on
/// to the formation.
pub fn replan_from_leg(
    mission: &Mission,
    plan: &DiscretePlan,
    steps: impl IntoIterator<Item = u32>,
) -> usize {
    use crate::mission::LegKind;
    let least = steps
        .into_iter()
        .filter_map(|step| leg_at(mission, plan, step))
        .min()
        .unwrap_or(0);
    let legs = mission.legs();
    let kind = |i: usize| legs.get(i).map(|l| l.kind);
    if kind(least) == Some(LegKind::Takeoff) && kind(least + 1) == Some(LegKind::Formation) {
        least + 1
    } else {
        least
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::path::RouteEvent;

    fn event(kind: EventKind, x: i32, arc_m: f64) -> RouteEvent {
        RouteEvent {
            kind,
            voxel: Voxel::new(x, 0, 0),
            step: x.unsigned_abs(),
            position_m: [arc_m, 0.0, 1.5],
            arc_m,
            reach_s: arc_m,
            after: Vec::new(),
            hold_s: 0.0,
        }
    }

    /// u = 0 → w = 1 → 2 on a 1 m grid with δ = 0.2 m markers.
    fn route() -> Route {
        use EventKind::*;
        Route {
            id: "a".into(),
            start_m: [0.0, 0.0, 1.5],
            runs: Vec::new(),
            events: vec![
                event(Start, 0, 0.0),
                event(Enter, 1, 0.2),
                event(Leave, 0, 0.8),
                event(Arrive, 1, 1.0),
                event(Enter, 2, 1.2),
                event(Leave, 1, 1.8),
                event(Arrive, 2, 2.0),
            ],
        }
    }

    fn target_x(arc_m: f64) -> i32 {
        freeze_target(&route(), arc_m)
            .map(|t| t.voxel.x)
            .unwrap_or(-1)
    }

    #[test]
    fn a_drone_freezes_at_a_centre_it_holds() {
        // At rest at or just past a centre, before the next Enter: that centre.
        assert_eq!(target_x(0.0), 0);
        assert_eq!(target_x(0.1), 0);
        // Stopped at a closed gate just before Enter 1: still voxel 0.
        assert_eq!(target_x(0.19), 0);
        // Past Enter 1 but not Leave 0: back to 0 (the gate may never open).
        assert_eq!(target_x(0.5), 0);
        // Past Leave 0: on to 1, the only voxel it holds.
        assert_eq!(target_x(0.9), 1);
        assert_eq!(target_x(1.0), 1);
        assert_eq!(target_x(1.5), 1);
        assert_eq!(target_x(1.85), 2);
        assert_eq!(target_x(2.0), 2);
        let t = freeze_target(&route(), 0.9).expect("a target");
        assert_eq!((t.position_m, t.step), ([1.0, 0.0, 1.5], 1));
    }

    /// Four voxels in a row, 1 m apart, layer 0 at 1.5 m.
    fn mission() -> Mission {
        crate::mission::from_yaml(
            "
name: line
world: { dimensions: [4, 1, 1], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 1.5] }
limits: { max_speed_mps: 1.0, max_accel_mps2: 1.0, safety_distance_m: 0.2 }
groups:
  - name: g
    drones: [{ id: a, start: [0, 0, 0] }]
    goals: [[3, 0, 0]]
",
            "line.yaml".as_ref(),
        )
        .expect("valid mission")
    }

    #[test]
    fn a_lost_drone_may_be_anywhere_from_its_last_seen_centre_to_its_commanded_one() {
        let m = mission();
        let xs = |v: Vec<Voxel>| v.iter().map(|v| (v.x, v.z)).collect::<Vec<_>>();
        // Seen at 0.5 (between 0 and 1), commanded to 1.5: voxels 0, 1, 2.
        assert_eq!(
            xs(lost_voxels(&m, &route(), 0.5, 1.5, None)),
            vec![(0, 0), (1, 0), (2, 0)]
        );
        // At rest at 1, and last reported 1.4 m further east and 1.1 m lower
        // (drifting down): voxel 1 and the pad-layer cell below voxel 2.
        assert_eq!(
            xs(lost_voxels(&m, &route(), 1.0, 1.0, Some([2.4, 0.0, 0.4]))),
            vec![(1, 0), (2, -1)]
        );
    }

    /// The freeze never puts two drones in one voxel: on the formation change
    /// (8 drones, pad to pad), stopped anywhere along the schedule every 0.1 s,
    /// every drone's freeze voxel is its own, so the centres they go to are a
    /// voxel apart, and each is one its route visits.
    #[test]
    fn a_drone_down_between_cells_blocks_every_column_near_it() {
        let m = mission();
        let c = m.airspace.center_m(Voxel::new(1, 0, 0));
        // Half-way between cells 1 and 2: both columns are within 0.6 m.
        let between = [c.x + 0.5 * m.airspace.voxel_size_m(), c.y, c.z];
        let mut xs: Vec<i32> = voxels_near(&m, between, 0.6).iter().map(|v| v.x).collect();
        xs.sort_unstable();
        assert_eq!(xs, [1, 2]);
        // On a cell's centre, with a clearance below the voxel size: that cell alone.
        assert_eq!(voxels_near(&m, [c.x, c.y, c.z], 0.6), [Voxel::new(1, 0, 0)]);
    }

    #[test]
    fn frozen_drones_never_share_a_voxel() {
        let mission = crate::mission::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/missions/formation-change.yaml"
        )))
        .expect("mission");
        let plan = crate::plan::solve(&mission, &crate::plan::PlanOptions::default())
            .expect("plan")
            .plan;
        let checked = crate::compiled::compile_plan(&mission, &plan, 0).expect("checked");
        let routes = crate::fly::path::routes(&checked);
        let makespan_s = checked.compiled().execution.makespan_s;
        let mut checked = 0;
        for tenth in 0..=(makespan_s * 10.0).ceil() as u32 {
            let t_s = f64::from(tenth) / 10.0;
            let mut voxels: Vec<Voxel> = Vec::new();
            for (route, drone) in routes.iter().zip(&plan.drones) {
                let target = freeze_target(route, route.scheduled_arc_m(t_s)).expect("target");
                assert!(
                    drone.path.contains(&target.voxel),
                    "{} at {t_s} s",
                    route.id
                );
                assert_eq!(
                    drone.path.get(target.step as usize),
                    Some(&target.voxel),
                    "{}: the step names the voxel",
                    route.id
                );
                voxels.push(target.voxel);
            }
            let mut distinct = voxels.clone();
            distinct.sort_unstable();
            distinct.dedup();
            assert_eq!(distinct.len(), voxels.len(), "at {t_s} s: {voxels:?}");
            checked += 1;
        }
        assert!(checked > 300, "{checked} instants");
    }
}
