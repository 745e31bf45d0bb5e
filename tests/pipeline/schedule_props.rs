//! Property tests: random small plans full of following and crossing give trajectories
//! that keep the safety distance and the kinematic limits, and the STN's longest-path
//! schedule equals brute force on small networks.

use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use swarmctl::mission::Limits;
use swarmctl::plan::{DiscretePlan, DronePlan};
use swarmctl::schedule::{self, Stn};
use swarmctl::trajectory;
use swarmctl::verify;
use swarmctl::world::{Voxel, VoxelGrid};

/// A random valid plan: drones decide one after another each step; a drone may move
/// into a voxel that is free at the next step and either empty now or being left by a
/// drone that already decided (following), never swapping. Waiting is always safe.
/// Deciding in a fixed order rules out rotations, so the TPG is acyclic.
fn random_plan(rng: &mut ChaCha8Rng, world: &VoxelGrid, drones: usize, steps: u32) -> DiscretePlan {
    let dims = world.dimensions();
    let mut cells: Vec<Voxel> = (0..world.len()).map(|c| world.voxel(c)).collect();
    for i in (1..cells.len()).rev() {
        cells.swap(i, rng.random_range(0..=i));
    }
    let mut paths: Vec<Vec<Voxel>> = cells[..drones].iter().map(|&v| vec![v]).collect();
    for _ in 0..steps {
        let now: Vec<Voxel> = paths.iter().map(|p| *p.last().unwrap()).collect();
        let mut next: Vec<Option<Voxel>> = vec![None; drones];
        for i in 0..drones {
            let here = now[i];
            let mut choice = here;
            if rng.random_bool(0.8) {
                let axis = rng.random_range(0..3);
                let up = rng.random_bool(0.5);
                let mut c = [here.x, here.y, here.z];
                let ok = if up {
                    c[axis] + 1 < dims[axis] as i32
                } else {
                    c[axis] > 0
                };
                if ok {
                    if up {
                        c[axis] += 1
                    } else {
                        c[axis] -= 1
                    }
                    let to = Voxel::from(c);
                    let taken_next = next.contains(&Some(to));
                    let occupant = now.iter().position(|&v| v == to);
                    let free_now = match occupant {
                        None => true,
                        // Following: the occupant already decided to leave, not towards us.
                        Some(j) => matches!(next[j], Some(n) if n != to && n != here),
                    };
                    if !taken_next && free_now {
                        choice = to;
                    }
                }
            }
            next[i] = Some(choice);
        }
        for (p, n) in paths.iter_mut().zip(next) {
            p.push(n.unwrap());
        }
    }
    DiscretePlan {
        makespan_steps: steps,
        sum_of_costs_steps: 0,
        drones: paths
            .into_iter()
            .enumerate()
            .map(|(i, path)| DronePlan {
                id: format!("d{i}"),
                group: "g".into(),
                goal: *path.last().unwrap(),
                path,
            })
            .collect(),
        legs: Vec::new(),
    }
}

fn min_distance_dense(t: &trajectory::Trajectories, rate_hz: f64) -> f64 {
    let n = (t.makespan_s * rate_hz).ceil() as usize + 1;
    let mut best = f64::INFINITY;
    for k in 0..n {
        let time = k as f64 / rate_hz;
        let p: Vec<[f64; 3]> = t.drones.iter().map(|d| d.position_m(time)).collect();
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                let d = (0..3)
                    .map(|c| (p[i][c] - p[j][c]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                best = best.min(d);
            }
        }
    }
    best
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn random_plans_keep_separation_and_limits(
        seed in any::<u64>(),
        drones in 2usize..7,
        steps in 4u32..14,
        voxel_m in prop::sample::select(vec![0.5, 1.0, 2.0]),
        ratio in 0.05f64..0.95,
        speed in 0.5f64..3.0,
        accel in 0.5f64..4.0,
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let world = VoxelGrid::new([3, 3, 2], voxel_m, [0.0, 0.0, 1.0]);
        let plan = random_plan(&mut rng, &world, drones, steps);
        let limits = Limits { max_speed_mps: speed, max_accel_mps2: accel, max_jerk_mps3: 5.0, safety_distance_m: ratio * voxel_m, vertical_separation_m: None, tracking_error_m: 0.0 };
        let tpg = schedule::build_with(&world, &limits, &plan).expect("valid plan");
        let s = schedule::solve(&tpg).expect("acyclic plan");
        let t = trajectory::from_schedule(&s);

        // Independent checker on the streamed samples.
        let samples = t.sample(20.0);
        let report = verify::check(&samples, &limits).unwrap();
        prop_assert!(report.ok(), "{:?}", report.violations);
        // Dense brute force on the continuous trajectories, no margins.
        let dense = min_distance_dense(&t, 400.0);
        prop_assert!(dense >= limits.safety_distance_m - 1e-9, "dense min {dense}");

        // Events are passed exactly at their times, and the makespan is the last arrival.
        for (d, drone) in tpg.drones.iter().enumerate() {
            for (e, times) in drone.events.iter().zip(&s.drones[d].events) {
                prop_assert!(times.leave_s >= times.reach_s - 1e-12);
                prop_assert!(times.slack_s >= -1e-9);
                for time in [times.reach_s, times.leave_s] {
                    let p = t.drones[d].position_m(time);
                    let err: f64 = (0..3).map(|c| (p[c] - e.position_m[c]).abs()).sum();
                    prop_assert!(err < 1e-9);
                }
            }
        }
        let last = t.drones.iter().map(|d| d.arrival_s()).fold(0.0, f64::max);
        prop_assert!((last - s.makespan_s).abs() < 1e-9);
        // Every type-2 edge holds in the schedule.
        for e in &tpg.cross_edges {
            let from = s.drones[e.from.drone as usize].events[e.from.index as usize].reach_s;
            let to = s.drones[e.to.drone as usize].events[e.to.index as usize].leave_s;
            prop_assert!(to >= from - 1e-9);
        }
        // The STN's longest path equals the general Bellman-Ford solution.
        let general = s.stn.solve_general().unwrap();
        let dag = s.stn.earliest_dag().unwrap();
        for (a, b) in general.iter().zip(&dag) {
            prop_assert!((a - b).abs() < 1e-9);
        }
    }

    #[test]
    fn type2_edges_are_not_implied_by_another_edge_of_the_same_pair(
        seed in any::<u64>(), drones in 2usize..6, steps in 4u32..14,
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let world = VoxelGrid::new([3, 3, 1], 1.0, [0.0; 3]);
        let plan = random_plan(&mut rng, &world, drones, steps);
        let limits = Limits { max_speed_mps: 1.0, max_accel_mps2: 1.0, max_jerk_mps3: 5.0, safety_distance_m: 0.5, vertical_separation_m: None, tracking_error_m: 0.0 };
        let tpg = schedule::build_with(&world, &limits, &plan).unwrap();
        for a in &tpg.cross_edges {
            for b in &tpg.cross_edges {
                if a != b && a.from.drone == b.from.drone && a.to.drone == b.to.drone {
                    let implies = b.from.index >= a.from.index && b.to.index <= a.to.index;
                    prop_assert!(!implies, "{a:?} is implied by {b:?}");
                }
            }
        }
    }

    #[test]
    fn longest_path_matches_brute_force(seed in any::<u64>(), n in 2u32..8, density in 0.1f64..0.8) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        // A random DAG over timepoints 0..n in index order, lower bounds of any sign.
        let mut stn = Stn::new(n);
        for from in 0..n {
            for to in from + 1..n {
                if rng.random_bool(density) {
                    stn.add(from, to, rng.random_range(-3.0..5.0), f64::INFINITY);
                }
            }
        }
        let dag = stn.earliest_dag().unwrap();
        let general = stn.solve_general().unwrap();
        // Brute force: every timepoint is at least 0 and at least the heaviest path from
        // the origin, enumerated over all paths.
        let mut brute = vec![0.0f64; n as usize];
        fn walk(stn: &Stn, at: u32, len: f64, best: &mut [f64]) {
            best[at as usize] = best[at as usize].max(len);
            for c in stn.constraints.iter().filter(|c| c.from == at) {
                walk(stn, c.to, len + c.lower_s, best);
            }
        }
        for start in 0..n {
            // Timepoints are also bounded below by 0 individually (after the origin).
            walk(&stn, start, 0.0, &mut brute);
        }
        for i in 0..n as usize {
            prop_assert!((dag[i] - brute[i]).abs() < 1e-9, "{i}: dag {} brute {}", dag[i], brute[i]);
            prop_assert!((general[i] - brute[i]).abs() < 1e-9, "{i}: bf {} brute {}", general[i], brute[i]);
        }
    }
}
