//! Downwash-aware separation: an ellipsoid in the mission, the planner, the
//! schedule and the checker. Hand-made instances where the sphere lets two drones
//! pass one above the other and the ellipsoid must not, the makespan rising only
//! where it has to, validation, and a property over random missions.

use crate::support::repo_path;
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt::Write as _;
use std::path::Path;
use swarmctl::compiled;
use swarmctl::mission::{self, Mission, MissionError};
use swarmctl::plan::{self, PlanOptions, PlanViolation};

fn mission(yaml: &str) -> Mission {
    mission::from_yaml(yaml, Path::new("test.yaml")).unwrap()
}

fn problems(yaml: &str) -> String {
    match mission::from_yaml(yaml, Path::new("test.yaml")) {
        Err(MissionError::Invalid { problems, .. }) => problems
            .iter()
            .map(|p| format!("{}: {}", p.path, p.message))
            .collect::<Vec<_>>()
            .join("\n"),
        other => panic!("expected the mission to be refused, got {other:?}"),
    }
}

/// Two drones in a slot one voxel wide, one layer apart, flying past each other:
/// a sphere of 0.3 m lets them pass one above the other, 1 m apart; an ellipsoid of
/// 1.2 m height (1.8 m with the tracking error) does not.
fn pass_under(separation: &str) -> String {
    format!(
        "name: pass-under\n\
         world: {{ dimensions: [5, 1, 3], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 2.0] }}\n\
         limits: {{ max_speed_mps: 1.0, max_accel_mps2: 2.0, {separation} }}\n\
         groups:\n\
         \x20 - {{ name: low, drones: [{{ id: a, start: [0, 0, 0] }}], goals: [[4, 0, 0]] }}\n\
         \x20 - {{ name: high, drones: [{{ id: b, start: [4, 0, 1] }}], goals: [[0, 0, 1]] }}\n"
    )
}

const ELLIPSOID: &str = "separation: { horizontal_m: 0.3, vertical_m: 1.2 }";
const SPHERE: &str = "safety_distance_m: 0.3";

fn formation_steps(solution: &plan::Solution) -> u32 {
    solution
        .plan
        .legs
        .iter()
        .find(|l| l.name == "formation")
        .map(|l| l.makespan_steps)
        .unwrap()
}

#[test]
fn the_ellipsoid_keeps_drones_from_passing_one_above_the_other() {
    let sphere = mission(&pass_under(SPHERE));
    let ellipsoid = mission(&pass_under(ELLIPSOID));
    let options = PlanOptions::default();
    let by_sphere = plan::solve(&sphere, &options).unwrap();
    let by_ellipsoid = plan::solve(&ellipsoid, &options).unwrap();
    // The sphere passes straight under, in the bound's 4 steps; the ellipsoid makes
    // one drone climb out of reach and back (or wait), 2 steps more.
    assert_eq!(formation_steps(&by_sphere), 4);
    assert_eq!(formation_steps(&by_ellipsoid), 6);

    // The independent validator refuses the sphere's plan under the ellipsoid,
    // naming the stacked pair, and accepts the ellipsoid's.
    let refused = plan::validate_plan(&ellipsoid, &by_sphere.plan).unwrap_err();
    assert!(
        refused
            .iter()
            .any(|v| matches!(v, PlanViolation::Stacked { .. })),
        "{refused:?}"
    );
    plan::validate_plan(&ellipsoid, &by_ellipsoid.plan).unwrap();

    // Scheduled, the setpoints stay outside each other's grown cylinder (scaled ≥ 1).
    let compiled = compiled::compile(&ellipsoid, &by_ellipsoid).unwrap();
    let scaled = compiled.check.scaled.as_ref().unwrap();
    assert!(scaled.min_bound >= 1.0, "{scaled:?}");
    assert!((scaled.vertical_m - (1.2 + 2.0 * ellipsoid.limits.tracking_error_m)).abs() < 1e-9);
    // The sphere's plan under the ellipsoid's limits does not schedule: the TPG
    // finds the stacked drones.
    let err = swarmctl::schedule::build(&ellipsoid, &by_sphere.plan).unwrap_err();
    assert!(err.to_string().contains("stacked"), "{err}");
}

#[test]
fn an_ellipsoid_that_never_binds_costs_no_makespan() {
    // Paper scale: 0.25 m beside, 0.75 m above and below, 1 m voxels. The default
    // tracking error keeps the grown height within a voxel, so only the pad layer
    // and layer 0 of a column are in reach; the plan is as short as the sphere's.
    let sphere = mission::load(&repo_path("missions/paper-scale.yaml")).unwrap();
    let downwash = mission::load(&repo_path("missions/paper-scale-downwash.yaml")).unwrap();
    assert_eq!(downwash.limits.vertical_separation_m, Some(0.75));
    let options = PlanOptions::default();
    let by_sphere = plan::solve(&sphere, &options).unwrap();
    let by_ellipsoid = plan::solve(&downwash, &options).unwrap();
    assert_eq!(
        by_ellipsoid.plan.makespan_steps,
        by_sphere.plan.makespan_steps
    );
    plan::validate_plan(&downwash, &by_ellipsoid.plan).unwrap();
    let compiled = compiled::compile(&downwash, &by_ellipsoid).unwrap();
    assert!(compiled.check.scaled.as_ref().unwrap().min_bound >= 1.0);
}

#[test]
fn separation_is_a_sphere_or_an_ellipsoid_never_both_nor_neither() {
    let both =
        pass_under("safety_distance_m: 0.3, separation: { horizontal_m: 0.3, vertical_m: 1.2 }");
    assert!(problems(&both).contains("not both"), "{}", problems(&both));
    let neither = pass_under("max_jerk_mps3: 2.5");
    assert!(
        problems(&neither).contains("missing the separation"),
        "{}",
        problems(&neither)
    );
    let tall = pass_under("separation: { horizontal_m: 0.3, vertical_m: 4.5 }");
    assert!(
        problems(&tall).contains("more than 4 voxel sizes"),
        "{}",
        problems(&tall)
    );
    let wide =
        pass_under("separation: { horizontal_m: 0.9, vertical_m: 1.2 }, tracking_error_m: 0.2");
    assert!(
        problems(&wide).contains("does not fit"),
        "{}",
        problems(&wide)
    );
    let flat = pass_under("separation: { horizontal_m: 0.3, vertical_m: -1.0 }");
    assert!(
        problems(&flat).contains("limits.separation.vertical_m"),
        "{}",
        problems(&flat)
    );
}

#[test]
fn a_formation_stacked_within_reach_is_refused_naming_both_cells() {
    let stacked = pass_under(ELLIPSOID).replace("goals: [[0, 0, 1]]", "goals: [[4, 0, 1]]");
    let stacked = stacked.replace("start: [4, 0, 1]", "start: [0, 0, 1]");
    let text = problems(&stacked);
    assert!(text.contains("[0, 0, 0] and [0, 0, 1]"), "{text}");
    assert!(text.contains("stacked 1.00 m apart"), "{text}");
    // The same formation with a sphere is fine.
    mission(&stacked.replace(ELLIPSOID, SPHERE));
}

#[test]
fn a_flat_ellipsoid_defaults_its_tracking_error_to_fit_a_voxel() {
    let m = mission(&pass_under(
        "separation: { horizontal_m: 0.25, vertical_m: 0.75 }",
    ));
    // 0.75 + 2e ≤ 1 − 0.02 margin: e = 0.115 m, not the usual 0.30 m.
    assert!(
        (m.limits.tracking_error_m - 0.115).abs() < 1e-9,
        "{:?}",
        m.limits
    );
    let tall = mission(&pass_under(ELLIPSOID));
    assert!((tall.limits.tracking_error_m - 0.30).abs() < 1e-9);
}

/// A random mission in a small world: two or three groups of one or two drones,
/// starts and goals drawn apart from every other start (goal) by more than the
/// vertical reach in their column, an ellipsoid 1.2 m tall in 1 m voxels.
fn random_mission(seed: u64) -> String {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let dims = [4, 3, 4];
    let mut yaml = String::new();
    let _ = writeln!(
        yaml,
        "name: random-{seed}\nworld: {{ dimensions: [4, 3, 4], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 2.0] }}\nlimits: {{ max_speed_mps: 1.0, max_accel_mps2: 2.0, separation: {{ horizontal_m: 0.3, vertical_m: 1.2 }} }}\ngroups:"
    );
    // Cells taken per formation; two cells of one column need 2 layers between.
    let pick = |rng: &mut ChaCha8Rng, taken: &mut Vec<[i32; 3]>| -> [i32; 3] {
        loop {
            let c = [
                rng.random_range(0..dims[0]),
                rng.random_range(0..dims[1]),
                rng.random_range(0..dims[2]),
            ];
            if taken
                .iter()
                .all(|t| t[0] != c[0] || t[1] != c[1] || (t[2] - c[2]).abs() >= 2)
            {
                taken.push(c);
                return c;
            }
        }
    };
    let (mut starts, mut goals) = (Vec::new(), Vec::new());
    let groups = rng.random_range(2..=3);
    for g in 0..groups {
        let drones = rng.random_range(1..=2);
        let _ = writeln!(yaml, "  - name: g{g}\n    drones:");
        let mut goal_list = Vec::new();
        for d in 0..drones {
            let s = pick(&mut rng, &mut starts);
            let _ = writeln!(yaml, "      - {{ id: d{g}-{d}, start: {s:?} }}");
            goal_list.push(format!("{:?}", pick(&mut rng, &mut goals)));
        }
        let _ = writeln!(yaml, "    goals: [{}]", goal_list.join(", "));
    }
    yaml
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Every plan the planner returns under an ellipsoid passes the independent
    /// validator, schedules, and keeps the scaled separation of setpoints at 1 or
    /// more in the checker, interpolation bound included.
    #[test]
    fn every_plan_keeps_the_scaled_separation(seed in 0u64..10_000) {
        let m = mission(&random_mission(seed));
        let solution = plan::solve(&m, &PlanOptions::default()).unwrap();
        plan::validate_plan(&m, &solution.plan).unwrap();
        let compiled = compiled::compile(&m, &solution).unwrap();
        let scaled = compiled.check.scaled.as_ref().unwrap();
        prop_assert!(scaled.min_bound >= 1.0 - 1e-6, "seed {seed}: {scaled:?}");
        prop_assert!(compiled.check.ok());
    }
}
