//! An independent check of a plan against its mission.
//!
//! Written from the problem statement alone and sharing no code with the solver, so a
//! bug in one is not silently repeated in the other.

use super::discrete_plan::{DiscretePlan, DronePlan};
use crate::mission::{Drone, Mission};
use crate::world::Voxel;
use std::collections::{HashMap, HashSet};

/// One way a plan breaks its mission. Drones are named by id; `step` counts plan steps
/// from 0; voxels are mission grid coordinates.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanViolation {
    /// A drone id of the plan that the mission does not have, or a second path for one.
    #[error("drone {0:?} is in the plan but not in the mission, or appears twice")]
    UnknownDrone(String),
    /// A drone of the mission that the plan leaves out.
    #[error("drone {0:?} of the mission has no path")]
    MissingDrone(String),
    /// The plan files a drone under another group than the mission does.
    #[error("drone {id:?} is listed in group {found:?} but belongs to {expected:?}")]
    WrongGroup {
        /// The drone.
        id: String,
        /// Its group in the mission.
        expected: String,
        /// The group the plan gives.
        found: String,
    },
    /// A path that does not cover every step from 0 to the makespan.
    #[error("drone {id:?}: path has {len} entries, expected makespan + 1 = {expected}")]
    PathLength {
        /// The drone.
        id: String,
        /// Entries in its path.
        len: usize,
        /// `makespan_steps + 1`.
        expected: usize,
    },
    /// A path that does not start above the drone's pad.
    #[error("drone {id:?}: path starts at {found} instead of above its pad, {expected}")]
    WrongStart {
        /// The drone.
        id: String,
        /// Its start in the mission.
        expected: Voxel,
        /// The path's first voxel.
        found: Voxel,
    },
    /// The rest of a flight has a path that does not start where the replan found
    /// the drone.
    #[error("drone {id:?}: path starts at {found} instead of where the drone is, {expected}")]
    WrongLiveStart {
        /// The drone.
        id: String,
        /// Its live voxel.
        expected: Voxel,
        /// The path's first voxel.
        found: Voxel,
    },
    /// The rest of a flight plans a drone no live start was given for.
    #[error("drone {0:?}: planned, but no start was given for it")]
    NoStart(String),
    /// The plan's legs are not the mission's (names, order, holds or steps).
    #[error("the plan's legs do not match the mission's: {0}")]
    Legs(String),
    /// A drone not on a target of its leg when the leg ends.
    #[error("drone {id:?}: at the end of leg {leg:?} (step {step}) it is at {found}, {expected}")]
    MissesLegTarget {
        /// The drone.
        id: String,
        /// The leg.
        leg: String,
        /// The leg's last step.
        step: usize,
        /// Where the drone is then.
        found: Voxel,
        /// What the leg asks, in words.
        expected: String,
    },
    /// A formation or stage leg through the pad layer, where the mission keeps
    /// them in the world's own voxels (`world.formations_use_pad_layer: false`).
    #[error(
        "drone {id:?}: leg {leg:?} passes through the pad layer at step {step} ({voxel}), but the mission keeps formations in the world's voxels"
    )]
    InPadLayer {
        /// The drone.
        id: String,
        /// The leg.
        leg: String,
        /// The first step in the pad layer.
        step: usize,
        /// Where the path is then.
        voxel: Voxel,
    },
    /// A path that does not end where the plan says it does (`goal`).
    #[error("drone {id:?}: path ends at {found}, not at its goal {goal}")]
    MissesGoal {
        /// The drone.
        id: String,
        /// Its assigned goal.
        goal: Voxel,
        /// The path's last voxel.
        found: Voxel,
    },
    /// A path through an obstacle or out of the world.
    #[error("drone {id:?}: step {step} at {voxel} is {}", if *.in_obstacle { "inside an obstacle" } else { "outside the airspace (the world's voxels and the pad layer's cells)" })]
    NotFree {
        /// The drone.
        id: String,
        /// The first offending step.
        step: usize,
        /// Where the path is then.
        voxel: Voxel,
        /// In an obstacle of the airspace (else outside the airspace altogether).
        in_obstacle: bool,
    },
    /// A move between voxels that are not face neighbours.
    #[error("drone {id:?}: jumps from {from} to {to} at step {step}")]
    Jump {
        /// The drone.
        id: String,
        /// The step the move starts at.
        step: usize,
        /// Where it starts.
        from: Voxel,
        /// Where it lands.
        to: Voxel,
    },
    /// Two drones in one voxel at one step.
    #[error("drones {a:?} and {b:?} are both in {voxel} at step {step}")]
    VertexConflict {
        /// One drone.
        a: String,
        /// The other.
        b: String,
        /// The shared voxel.
        voxel: Voxel,
        /// The step they share it.
        step: usize,
    },
    /// Two drones trading places in one step (they would pass through each other).
    #[error("drones {a:?} and {b:?} swap {from} and {to} between steps {step} and {}", step + 1)]
    SwapConflict {
        /// The drone moving `from` → `to`.
        a: String,
        /// The drone moving `to` → `from`.
        b: String,
        /// Where `a` starts.
        from: Voxel,
        /// Where `b` starts.
        to: Voxel,
        /// The step the swap starts at.
        step: usize,
    },
    /// Drones following each other round a loop in one step: no precedence schedule
    /// can fly it with a safety distance.
    #[error(
        "drones {} rotate between steps {step} and {}: each enters the voxel the next leaves, which no drone can fly safely",
        drones.join(", "), step + 1
    )]
    Rotation {
        /// The drones round the loop, in order.
        drones: Vec<String>,
        /// The step the rotation starts at.
        step: usize,
    },
    /// Under an ellipsoidal separation, two drones in one column closer than its
    /// vertical reach at one step.
    #[error(
        "drones {a:?} and {b:?} are at {a_voxel} and {b_voxel} at step {step}: stacked {apart_m:.2} m apart, inside the separation ellipsoid's vertical reach ({reach_m:.2} m)"
    )]
    Stacked {
        /// One drone.
        a: String,
        /// The other.
        b: String,
        /// Where `a` is.
        a_voxel: Voxel,
        /// Where `b` is.
        b_voxel: Voxel,
        /// The step.
        step: usize,
        /// Their cell centres' vertical distance, metres.
        apart_m: f64,
        /// The reach, metres.
        reach_m: f64,
    },
    /// Under an ellipsoidal separation, drones that each move in one step into the
    /// cell the next leaves or one within the vertical reach of it: each would wait
    /// for the next to be out of reach, for ever.
    #[error(
        "drones {} wait for one another in a cycle between steps {step} and {}: each moves into the reach of the cell the next one leaves",
        drones.join(", "), step + 1
    )]
    StackedCycle {
        /// The drones on the cycle (and any waiting on it), sorted.
        drones: Vec<String>,
        /// The step the moves start at.
        step: usize,
    },
    /// The plan's makespan is not when its last drone arrives.
    #[error("reported makespan {reported} but the last drone arrives at step {actual}")]
    Makespan {
        /// What the plan says, steps.
        reported: u32,
        /// What its paths give, steps.
        actual: u32,
    },
    /// The plan's sum of costs is not the sum of its drones' arrival steps.
    #[error("reported sum of costs {reported} but the arrival steps add up to {actual}")]
    SumOfCosts {
        /// What the plan says, steps.
        reported: u64,
        /// What its paths give, steps.
        actual: u64,
    },
}

/// Every way `plan` breaks `mission`; empty means the plan is valid.
pub fn validate_plan(mission: &Mission, plan: &DiscretePlan) -> Result<(), Vec<PlanViolation>> {
    let pad = |drone: &Drone| Some(Start::Pad(drone.pad_voxel()));
    check(mission, 0, &pad, plan)
}

/// Every way `plan`, the rest of a flight from leg `from_leg` of `mission` (an
/// index into `Mission::legs`), breaks it, each drone starting where `starts` (id,
/// voxel) puts it — a replan's plan against the survivors' mission it was planned
/// in (`plan::Replanned`). A drone of the mission missing from `starts` is
/// reported as a wrong start. Empty means the plan is valid.
pub fn validate_rest(
    mission: &Mission,
    from_leg: usize,
    starts: &[(&str, Voxel)],
    plan: &DiscretePlan,
) -> Result<(), Vec<PlanViolation>> {
    let start_of = |drone: &Drone| {
        let live = starts.iter().find(|s| s.0 == drone.id);
        live.map(|s| Start::Live(s.1))
    };
    check(mission, from_leg, &start_of, plan)
}

/// The checks of [`validate_plan`] and [`validate_rest`], each drone's path
/// starting at `start_of` it (`None`: no start is acceptable).
fn check(
    mission: &Mission,
    from_leg: usize,
    start_of: &dyn Fn(&Drone) -> Option<Start>,
    plan: &DiscretePlan,
) -> Result<(), Vec<PlanViolation>> {
    let mut violations = Vec::new();
    let expected_len = plan.makespan_steps as usize + 1;

    let mut owners: HashMap<&str, Owner> = HashMap::new();
    for (gi, group) in mission.groups.iter().enumerate() {
        for (di, drone) in group.drones.iter().enumerate() {
            owners.insert(
                &drone.id,
                Owner {
                    group: &group.name,
                    start: start_of(drone),
                    at: (gi, di),
                },
            );
        }
    }
    let mut seen = HashSet::new();
    let mut latest_arrival = 0u32;
    let mut arrivals_total = 0u64;
    for d in &plan.drones {
        let Some(owner) = owners.get(d.id.as_str()) else {
            violations.push(PlanViolation::UnknownDrone(d.id.clone()));
            continue;
        };
        if !seen.insert(d.id.as_str()) {
            violations.push(PlanViolation::UnknownDrone(d.id.clone()));
            continue;
        }
        if d.group != owner.group {
            violations.push(PlanViolation::WrongGroup {
                id: d.id.clone(),
                expected: owner.group.to_string(),
                found: d.group.clone(),
            });
        }
        if let Some(arrival) = path(mission, d, owner, expected_len, &mut violations) {
            latest_arrival = latest_arrival.max(arrival as u32);
            arrivals_total += arrival as u64;
        }
    }
    for group in &mission.groups {
        for drone in &group.drones {
            if !seen.contains(drone.id.as_str()) {
                violations.push(PlanViolation::MissingDrone(drone.id.clone()));
            }
        }
    }
    legs(mission, from_leg, plan, &owners, &mut violations);

    // Collisions, step by step, over paths of the common length.
    let common: Vec<_> = plan
        .drones
        .iter()
        .filter(|d| d.path.len() == expected_len)
        .collect();
    // Only steps the paths really hold: a hostile `makespan_steps` of 4e9 with short
    // paths must not spin here for hours.
    let expected_len = if common.is_empty() { 0 } else { expected_len };
    violations.extend(meetings_and_swaps(&common, expected_len));
    violations.extend(rotations(&common, expected_len));
    if let Some(reach_m) = vertical_reach_m(mission) {
        violations.extend(stacking(mission, reach_m, &common, expected_len));
    }

    if latest_arrival != plan.makespan_steps {
        violations.push(PlanViolation::Makespan {
            reported: plan.makespan_steps,
            actual: latest_arrival,
        });
    }
    if arrivals_total != plan.sum_of_costs_steps {
        violations.push(PlanViolation::SumOfCosts {
            reported: plan.sum_of_costs_steps,
            actual: arrivals_total,
        });
    }
    if violations.is_empty() {
        Ok(())
    } else {
        Err(violations)
    }
}

/// What the mission says about one drone.
/// Where a drone's path must begin.
#[derive(Clone, Copy)]
enum Start {
    /// The pad-layer cell above its pad.
    Pad(Voxel),
    /// Where a replan found it.
    Live(Voxel),
}

struct Owner<'m> {
    group: &'m str,
    /// Where its path must begin (`None`: nowhere given).
    start: Option<Start>,
    /// Its group's and its own index in the mission.
    at: (usize, usize),
}

/// Every leg of the mission, in order, against the plan's: the same names and holds,
/// steps that add up, and at each leg's last step every drone on a target the leg
/// allows it (shared targets: any of the group's; own targets: its own, where own
/// targets may depend on where the previous leg left it).
fn legs(
    mission: &Mission,
    from_leg: usize,
    plan: &DiscretePlan,
    owners: &HashMap<&str, Owner>,
    violations: &mut Vec<PlanViolation>,
) {
    let wanted: Vec<_> = mission.legs().into_iter().skip(from_leg).collect();
    let names = |v: Vec<&str>| v.join(", ");
    if wanted.len() != plan.legs.len()
        || wanted
            .iter()
            .zip(&plan.legs)
            .any(|(w, p)| w.name != p.name || w.kind != p.kind)
    {
        violations.push(PlanViolation::Legs(format!(
            "the mission flies [{}], the plan [{}]",
            names(wanted.iter().map(|l| l.name.as_str()).collect()),
            names(plan.legs.iter().map(|l| l.name.as_str()).collect())
        )));
        return;
    }
    let mut previous_end = 0usize;
    for (w, p) in wanted.iter().zip(&plan.legs) {
        let end = p.end_step as usize;
        if end < previous_end || end > plan.makespan_steps as usize {
            violations.push(PlanViolation::Legs(format!(
                "leg {:?} ends at step {end}, before the previous leg (step {previous_end}) or after the makespan",
                p.name
            )));
            return;
        }
        if (w.hold_s - p.hold_s).abs() > 1e-9 {
            violations.push(PlanViolation::Legs(format!(
                "leg {:?} holds {} s in the plan but {} s in the mission",
                p.name, p.hold_s, w.hold_s
            )));
        }
        let mut taken: HashSet<(usize, Voxel)> = HashSet::new();
        for d in &plan.drones {
            let Some(owner) = owners.get(d.id.as_str()) else {
                continue;
            };
            let (gi, di) = owner.at;
            let (Some(&found), Some(&before)) = (d.path.get(end), d.path.get(previous_end)) else {
                continue;
            };
            let expected = match &w.targets[gi] {
                crate::mission::Targets::Any(set) => (!set.contains(&found))
                    .then(|| format!("not a target of group {:?}", owner.group)),
                crate::mission::Targets::Own(own) => own
                    .get(di)
                    .filter(|&&v| v != found)
                    .map(|v| format!("not its own target {v}")),
                crate::mission::Targets::Stay => (found != before)
                    .then(|| format!("not where it was at step {previous_end}, {before}")),
                crate::mission::Targets::BelowCurrent => {
                    let below = Voxel::new(before.x, before.y, -1);
                    (found != below)
                        .then(|| format!("not the pad-layer cell below {before}, {below}"))
                }
            };
            let expected = expected.or_else(|| {
                (!taken.insert((gi, found)))
                    .then(|| "a target another drone also ends on".to_string())
            });
            if let Some(expected) = expected {
                violations.push(PlanViolation::MissesLegTarget {
                    id: d.id.clone(),
                    leg: p.name.clone(),
                    step: end,
                    found,
                    expected,
                });
            }
            if !w.pad_layer_open {
                // The pad layer is z = -1 (below voxel layer 0), whatever the grid.
                let low = (previous_end..=end)
                    .find_map(|step| d.path.get(step).filter(|v| v.z < 0).map(|&v| (step, v)));
                if let Some((step, voxel)) = low {
                    violations.push(PlanViolation::InPadLayer {
                        id: d.id.clone(),
                        leg: p.name.clone(),
                        step,
                        voxel,
                    });
                }
            }
        }
        previous_end = end;
    }
    if previous_end != plan.makespan_steps as usize {
        violations.push(PlanViolation::Legs(format!(
            "the last leg ends at step {previous_end}, the plan's makespan is {}",
            plan.makespan_steps
        )));
    }
}

/// The drone's path on its own: length, start, end, free voxels, unit moves. Returns
/// the step from which it stays at its last voxel (`None` for an empty path).
fn path(
    mission: &Mission,
    d: &DronePlan,
    owner: &Owner,
    expected_len: usize,
    violations: &mut Vec<PlanViolation>,
) -> Option<usize> {
    let id = &d.id;
    if d.path.len() != expected_len {
        violations.push(PlanViolation::PathLength {
            id: id.clone(),
            len: d.path.len(),
            expected: expected_len,
        });
    }
    let (Some(&first), Some(&last)) = (d.path.first(), d.path.last()) else {
        return None;
    };
    match owner.start {
        None => violations.push(PlanViolation::NoStart(id.clone())),
        Some(Start::Pad(expected)) if first != expected => {
            violations.push(PlanViolation::WrongStart {
                id: id.clone(),
                expected,
                found: first,
            });
        }
        Some(Start::Live(expected)) if first != expected => {
            violations.push(PlanViolation::WrongLiveStart {
                id: id.clone(),
                expected,
                found: first,
            });
        }
        Some(_) => {}
    }
    if last != d.goal {
        violations.push(PlanViolation::MissesGoal {
            id: id.clone(),
            goal: d.goal,
            found: last,
        });
    }
    for (step, &voxel) in d.path.iter().enumerate() {
        if !mission.airspace.is_free(voxel) {
            violations.push(PlanViolation::NotFree {
                id: id.clone(),
                step,
                voxel,
                in_obstacle: mission.airspace.contains(voxel),
            });
        }
    }
    for (step, pair) in d.path.windows(2).enumerate() {
        let (from, to) = (pair[0], pair[1]);
        let moved = from.x.abs_diff(to.x) + from.y.abs_diff(to.y) + from.z.abs_diff(to.z);
        if moved > 1 {
            violations.push(PlanViolation::Jump {
                id: id.clone(),
                step,
                from,
                to,
            });
        }
    }
    let mut arrival = d.path.len();
    while arrival > 0 && d.path[arrival - 1] == last {
        arrival -= 1;
    }
    Some(arrival)
}

/// Two drones in one voxel at a step, or trading places within a step.
fn meetings_and_swaps(common: &[&DronePlan], len: usize) -> Vec<PlanViolation> {
    let mut violations = Vec::new();
    for step in 0..len {
        let mut here: HashMap<Voxel, &str> = HashMap::new();
        for d in common {
            if let Some(other) = here.insert(d.path[step], &d.id) {
                violations.push(PlanViolation::VertexConflict {
                    a: other.to_string(),
                    b: d.id.clone(),
                    voxel: d.path[step],
                    step,
                });
            }
        }
        if step + 1 == len {
            break;
        }
        let moves: HashMap<(Voxel, Voxel), &str> = common
            .iter()
            .filter(|d| d.path[step] != d.path[step + 1])
            .map(|d| ((d.path[step], d.path[step + 1]), d.id.as_str()))
            .collect();
        for (&(from, to), &a) in &moves {
            if let Some(&b) = moves.get(&(to, from)).filter(|&&b| a < b) {
                violations.push(PlanViolation::SwapConflict {
                    a: a.to_string(),
                    b: b.to_string(),
                    from,
                    to,
                    step,
                });
            }
        }
    }
    violations
}

/// Cycles of three or more drones moving in one step, each into the voxel the next
/// one leaves (two-drone cycles are swaps, reported above).
fn rotations(drones: &[&DronePlan], len: usize) -> Vec<PlanViolation> {
    let mut found = Vec::new();
    for step in 0..len.saturating_sub(1) {
        let at_step: HashMap<Voxel, usize> = drones
            .iter()
            .enumerate()
            .map(|(i, d)| (d.path[step], i))
            .collect();
        // successor[i] = the drone whose voxel drone i moves into, if that one moves too.
        let successor = |i: usize| -> Option<usize> {
            let d = drones[i];
            let target = d.path[step + 1];
            if target == d.path[step] {
                return None;
            }
            let j = *at_step.get(&target)?;
            (drones[j].path[step + 1] != drones[j].path[step]).then_some(j)
        };
        let mut reported: HashSet<usize> = HashSet::new();
        for i in 0..drones.len() {
            // Walk at most n successors; a cycle through i returns to i.
            let mut members = vec![i];
            let mut current = i;
            while let Some(next) = successor(current) {
                if next == i || members.len() > drones.len() {
                    break;
                }
                members.push(next);
                current = next;
            }
            let closes = successor(current) == Some(i);
            if closes && members.len() >= 3 && members.iter().all(|m| reported.insert(*m)) {
                found.push(PlanViolation::Rotation {
                    drones: members.iter().map(|&m| drones[m].id.clone()).collect(),
                    step,
                });
            }
        }
    }
    found
}

/// Under an ellipsoid of setpoint radii `H'`, `V'` (the mission's plus twice its
/// tracking error): how close two cell centres of one column may be for drones
/// to hold them at once. The schedule's argument lets a drone on a vertical move
/// hold a cell up to `σ = max(0, (c − V') / 2)` beyond its position, `c` the
/// closest vertical spacing of cell centres, so two drones `V'` apart may hold
/// cells `V' + 2σ` apart. `None` for a sphere.
fn vertical_reach_m(mission: &Mission) -> Option<f64> {
    let v = mission.limits.vertical_separation_m? + 2.0 * mission.limits.tracking_error_m;
    let grid = &mission.airspace;
    let layer0 = grid.center_m(Voxel::new(0, 0, 0)).z;
    let mut closest = grid.voxel_size_m();
    if let Some(pad) = grid.pad_layer_z_m() {
        closest = closest.min(layer0 - pad);
    }
    Some(v + (closest - v).max(0.0))
}

/// Drones in one column closer than `reach_m` at a step, and cycles of movers
/// each entering the reach of what the next leaves.
fn stacking(
    mission: &Mission,
    reach_m: f64,
    drones: &[&DronePlan],
    len: usize,
) -> Vec<PlanViolation> {
    let height = |v: Voxel| mission.airspace.center_m(v).z;
    let close = |a: Voxel, b: Voxel| {
        a.x == b.x && a.y == b.y && (height(a) - height(b)).abs() < reach_m - 1e-9
    };
    let mut found = Vec::new();
    for step in 0..len {
        let mut columns: HashMap<(i32, i32), Vec<usize>> = HashMap::new();
        for (i, d) in drones.iter().enumerate() {
            let v = d.path[step];
            columns.entry((v.x, v.y)).or_default().push(i);
        }
        for members in columns.values() {
            for (k, &i) in members.iter().enumerate() {
                for &j in &members[k + 1..] {
                    let (a, b) = (drones[i].path[step], drones[j].path[step]);
                    if a != b && close(a, b) {
                        found.push(PlanViolation::Stacked {
                            a: drones[i].id.clone(),
                            b: drones[j].id.clone(),
                            a_voxel: a,
                            b_voxel: b,
                            step,
                            apart_m: (height(a) - height(b)).abs(),
                            reach_m,
                        });
                    }
                }
            }
        }
        if step + 1 == len {
            continue;
        }
        // Movers waiting for movers: i waits for j when i enters j's cell or one
        // close to it. Peel off movers that wait for nobody still standing; what
        // cannot be peeled waits in a cycle.
        let movers: Vec<usize> = (0..drones.len())
            .filter(|&i| drones[i].path[step] != drones[i].path[step + 1])
            .collect();
        let waits: Vec<Vec<usize>> = movers
            .iter()
            .map(|&i| {
                let to = drones[i].path[step + 1];
                (0..drones.len())
                    .filter(|&j| j != i)
                    .filter(|&j| {
                        let here = drones[j].path[step];
                        here == to || close(here, to)
                    })
                    .collect()
            })
            .collect();
        let mut standing: HashSet<usize> = movers.iter().copied().collect();
        loop {
            let free: Vec<usize> = movers
                .iter()
                .zip(&waits)
                .filter(|(i, w)| standing.contains(i) && !w.iter().any(|j| standing.contains(j)))
                .map(|(&i, _)| i)
                .collect();
            if free.is_empty() {
                break;
            }
            for i in free {
                standing.remove(&i);
            }
        }
        if !standing.is_empty() {
            let mut names: Vec<String> = standing.iter().map(|&i| drones[i].id.clone()).collect();
            names.sort();
            found.push(PlanViolation::StackedCycle {
                drones: names,
                step,
            });
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{self, PlanOptions};

    /// A hostile plan file may claim any makespan; the check must stay bounded by
    /// the data it was given.
    #[test]
    fn absurd_makespan_with_short_paths_is_refused_at_once() {
        let mission = crate::mission::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/missions/swap-corridor.yaml"
        )))
        .expect("mission");
        let mut plan = plan::solve(&mission, &PlanOptions::default())
            .expect("plan")
            .plan;
        plan.makespan_steps = u32::MAX - 1;
        // Before the fix this looped ~4e9 times over the steps.
        let violations = validate_plan(&mission, &plan).expect_err("refused");
        assert!(
            violations
                .iter()
                .any(|v| matches!(v, PlanViolation::PathLength { .. })),
            "{violations:?}"
        );
    }
}
