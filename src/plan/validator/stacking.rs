//! Stacking under an ellipsoidal separation: drones in one column closer than the
//! separation's vertical reach, and movers that wait for one another in a cycle.

use super::violation::PlanViolation;
use crate::mission::Mission;
use crate::plan::discrete_plan::DronePlan;
use crate::world::Voxel;
use std::collections::{HashMap, HashSet};

/// Under an ellipsoid of setpoint radii `H'`, `V'` (the mission's plus twice its
/// tracking error): how close two cell centres of one column may be for drones
/// to hold them at once. The schedule's argument lets a drone on a vertical move
/// hold a cell up to `σ = max(0, (c − V') / 2)` beyond its position, `c` the
/// closest vertical spacing of cell centres, so two drones `V'` apart may hold
/// cells `V' + 2σ` apart. `None` for a sphere.
pub(super) fn vertical_reach_m(mission: &Mission) -> Option<f64> {
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
pub(super) fn stacking(
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
