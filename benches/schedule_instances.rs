//! Synthetic discrete plans for scheduling benchmarks: lane traffic with lots of
//! following and crossing, at any scale, without the TAPF solver.
//!
//! Each z layer is an independent corridor `width × 100` voxels. Drones start on the
//! west face (x = 0) and end on the east face (x = width − 1), both private to their
//! owner; each flies east, turns north or south at a random column, flies to its goal
//! row, turns east again and finishes. Drones are planned one after another
//! (prioritised planning): each picks the earliest departure from its start voxel for
//! which its whole path is free of vertex conflicts and swaps with the drones planned
//! before it. Following (entering a voxel another drone is just leaving) is allowed and
//! frequent; rotations cannot occur since no drone ever flies west.

#![allow(dead_code)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::HashSet;
use swarmctl::mission::Limits;
use swarmctl::plan::{DiscretePlan, DronePlan};
use swarmctl::world::{Voxel, VoxelGrid};

/// Rows per layer; drones per layer is half of it.
const ROWS: u32 = 100;
const DRONES_PER_LAYER: usize = 50;
const WIDTH: u32 = 24;

/// A lane-traffic instance with `drones` drones: world, limits and plan.
pub fn lanes(drones: usize, seed: u64) -> (VoxelGrid, Limits, DiscretePlan) {
    let layers = drones.div_ceil(DRONES_PER_LAYER) as u32;
    let world = VoxelGrid::new([WIDTH, ROWS, layers], 1.0, [0.0, 0.0, 1.0]);
    let limits = Limits {
        max_speed_mps: 1.0,
        max_accel_mps2: 2.0,
        max_jerk_mps3: 5.0,
        safety_distance_m: 0.25,
        vertical_separation_m: None,
        tracking_error_m: 0.0,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut paths: Vec<Vec<Voxel>> = Vec::with_capacity(drones);
    for z in 0..layers {
        let count = DRONES_PER_LAYER.min(drones - paths.len());
        let starts = sample_rows(&mut rng, count);
        let goals = sample_rows(&mut rng, count);
        let mut occupied: HashSet<(Voxel, u32)> = HashSet::new();
        let mut moves: HashSet<(Voxel, Voxel, u32)> = HashSet::new();
        for (&y0, &y1) in starts.iter().zip(&goals) {
            let turn = rng.random_range(1..WIDTH - 1);
            let route = route(y0, y1, z, turn);
            let path = place(&route, &mut occupied, &mut moves);
            paths.push(path);
        }
    }
    let makespan = paths.iter().map(|p| p.len() as u32 - 1).max().unwrap_or(0);
    let drones = paths
        .into_iter()
        .enumerate()
        .map(|(i, mut path)| {
            // Every lane path starts at its start voxel, so it is never empty.
            let Some(&goal) = path.last() else {
                unreachable!("lane paths start at their start voxel")
            };
            path.resize(makespan as usize + 1, goal);
            DronePlan {
                id: format!("d{i}"),
                group: "g".into(),
                goal,
                path,
            }
        })
        .collect();
    (
        world,
        limits,
        DiscretePlan {
            makespan_steps: makespan,
            sum_of_costs_steps: 0,
            drones,
            legs: Vec::new(),
        },
    )
}

fn sample_rows(rng: &mut ChaCha8Rng, count: usize) -> Vec<u32> {
    let mut rows: Vec<u32> = (0..ROWS).collect();
    for i in (1..rows.len()).rev() {
        rows.swap(i, rng.random_range(0..=i));
    }
    rows.truncate(count);
    rows
}

/// East to `turn`, north/south to `y1`, east to the goal face.
fn route(y0: u32, y1: u32, z: u32, turn: u32) -> Vec<Voxel> {
    let v = |x: u32, y: u32| Voxel::new(x as i32, y as i32, z as i32);
    let mut r = vec![v(0, y0)];
    for x in 1..=turn {
        r.push(v(x, y0));
    }
    let mut y = y0;
    while y != y1 {
        y = if y1 > y { y + 1 } else { y - 1 };
        r.push(v(turn, y));
    }
    for x in turn + 1..WIDTH {
        r.push(v(x, y1));
    }
    r
}

/// The earliest departure at which `route` conflicts with nobody placed before.
fn place(
    route: &[Voxel],
    occupied: &mut HashSet<(Voxel, u32)>,
    moves: &mut HashSet<(Voxel, Voxel, u32)>,
) -> Vec<Voxel> {
    let mut delay = 0u32;
    loop {
        let free = route.iter().enumerate().skip(1).all(|(k, &v)| {
            let t = delay + k as u32;
            // Vertex conflict, and the swap: someone moving v → route[k-1] at t.
            !occupied.contains(&(v, t)) && !moves.contains(&(v, route[k - 1], t))
        });
        // The goal face is private, so the last voxel stays free afterwards.
        if free {
            let mut path = vec![route[0]; delay as usize];
            path.extend_from_slice(route);
            for (t, &v) in path.iter().enumerate() {
                occupied.insert((v, t as u32));
                if t > 0 && path[t - 1] != v {
                    moves.insert((path[t - 1], v, t as u32));
                }
            }
            return path;
        }
        delay += 1;
    }
}
