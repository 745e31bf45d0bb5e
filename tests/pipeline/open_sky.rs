//! Open sky: where nothing stands between the formations, the planner flies
//! straight lines instead of searching, and what it returns is still proven by
//! the validator and the trajectory checker, with its gap stated truthfully.

use super::plan_optimality::generated;
use proptest::prelude::*;
use std::time::Duration;
use swarmctl::compiled;
use swarmctl::generate::GenerateOptions;
use swarmctl::plan::{self, PlanOptions};

/// A show on a lattice `spacing` voxels apart in an empty world.
fn lattice_show(
    drones: usize,
    groups: usize,
    dimensions: [u32; 3],
    spacing: u32,
    seed: u64,
) -> swarmctl::mission::Mission {
    generated(GenerateOptions {
        dimensions,
        obstacles: 0,
        drones,
        groups,
        seed,
        spacing: Some(spacing),
        ..GenerateOptions::default()
    })
}

/// A carpet of 100 drones two voxels apart rises six layers and shifts two
/// voxels east: no drone can arrive sooner than its straight line takes, so the
/// formation leg flies straight lines, proven optimal by the bound without a
/// search, and the flight is valid, schedules and keeps every limit in the
/// checker.
#[test]
fn a_carpet_that_rises_and_shifts_flies_straight_lines_proven_optimal() {
    let lattice = |z: i32, shift: i32| -> Vec<String> {
        (0..10)
            .flat_map(|y| (0..10).map(move |x| format!("[{}, {}, {z}]", 2 * x + shift, 2 * y)))
            .collect()
    };
    let drones: Vec<String> = lattice(0, 0)
        .iter()
        .enumerate()
        .map(|(i, start)| format!("{{ id: d{i}, start: {start} }}"))
        .collect();
    let yaml = format!(
        "name: carpet
world: {{ dimensions: [22, 20, 8], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 1.5] }}
limits: {{ max_speed_mps: 1.0, max_accel_mps2: 2.0, safety_distance_m: 0.25 }}
groups:
  - name: carpet
    drones: [{}]
    goals: [{}]
",
        drones.join(", "),
        lattice(6, 2).join(", ")
    );
    let m = swarmctl::mission::from_yaml(&yaml, "carpet.yaml".as_ref()).expect("valid");
    let solution = plan::solve(&m, &PlanOptions::default()).expect("planned");
    let formation = solution
        .stats
        .legs
        .iter()
        .find(|l| l.name == "formation")
        .expect("a formation leg");
    assert!(formation.straight_lines, "{formation:?}");
    assert_eq!(formation.makespan_steps, 8, "six up and two east");
    assert_eq!(formation.proven_bound_steps, 8);
    assert_eq!(formation.ct_nodes_expanded, 0, "no search");
    plan::validate_plan(&m, &solution.plan).expect("valid");
    let compiled = compiled::compile(&m, &solution).expect("checked");
    assert!(compiled.check.ok());
}

/// Where the exact search finishes, straight lines change no leg's makespan:
/// they are an incumbent, kept only where nothing beats them.
#[test]
fn lattice_shows_keep_the_exact_searchs_makespans() {
    let m = lattice_show(120, 6, [16, 16, 6], 2, 3);
    let anytime = plan::solve(&m, &PlanOptions::default()).expect("planned");
    let exact = plan::solve(
        &m,
        &PlanOptions {
            first_plan: false,
            ..PlanOptions::default()
        },
    )
    .expect("planned");
    plan::validate_plan(&m, &anytime.plan).expect("valid");
    let legs =
        |s: &plan::Solution| -> Vec<u32> { s.plan.legs.iter().map(|l| l.makespan_steps).collect() };
    assert_eq!(legs(&anytime), legs(&exact));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Any lattice show, any deadline: the plan returned is valid, passes the
    /// checker, and its proven bound never exceeds its makespan.
    #[test]
    fn every_lattice_show_plans_valid_and_checked(
        drones in 2usize..60,
        groups in 1usize..4,
        spacing in 1u32..4,
        seed in 0u64..1_000,
        deadline_ms in prop_oneof![Just(5u64), Just(5_000)],
    ) {
        let groups = groups.min(drones);
        let dimensions = [12, 12, 8];
        let lattice_points: usize = dimensions.iter().map(|&d| (d as usize).div_ceil(spacing as usize)).product();
        prop_assume!(drones <= lattice_points);
        let m = lattice_show(drones, groups, dimensions, spacing, seed);
        let options = PlanOptions {
            seed,
            deadline: Duration::from_millis(deadline_ms),
            ..PlanOptions::default()
        };
        let Ok(solution) = plan::solve(&m, &options) else {
            prop_assume!(deadline_ms < 5_000);
            return Ok(());
        };
        prop_assert!(plan::validate_plan(&m, &solution.plan).is_ok());
        let compiled = compiled::compile(&m, &solution).expect("checked");
        prop_assert!(compiled.check.ok());
        for leg in &solution.stats.legs {
            prop_assert!(leg.proven_bound_steps <= leg.makespan_steps, "{:?}", leg);
        }
    }
}
