//! Anytime planning: a first plan fast, the exact search to beat it, and the gap
//! between the plan returned and the lower bound proven, stated truthfully.

use super::plan_optimality::{
    brute_force_makespan, check_tapf, formation, generated, tiny_instance,
};
use proptest::prelude::*;
use std::time::Duration;
use swarmctl::generate::GenerateOptions;
use swarmctl::mission;
use swarmctl::plan::{self, PlanError, PlanOptions};

/// A drone-show-like mission: many groups in a world with obstacles.
fn show(drones: usize, groups: usize, dimensions: [u32; 3], seed: u64) -> mission::Mission {
    let cells = dimensions.iter().product::<u32>() as usize;
    generated(GenerateOptions {
        dimensions,
        obstacles: cells / 10,
        drones,
        groups,
        seed,
        voxel_size_m: 1.0,
        ..GenerateOptions::default()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 120, ..ProptestConfig::default() })]

    /// Whatever the deadline cuts off, a returned plan is valid, and what it says
    /// of itself is true: the proven bound is at most the optimum, the makespan at
    /// least it, and a first plan is never beaten by the answer's own makespan.
    #[test]
    fn a_plan_by_the_deadline_is_valid_and_its_gap_true(
        yaml in tiny_instance(),
        seed in 0u64..4,
        deadline_ms in prop_oneof![Just(1u64), Just(20), Just(2_000)],
    ) {
        let Ok(m) = mission::from_yaml(&yaml, "tiny.yaml".as_ref()) else { return Ok(()) };
        let optimum = brute_force_makespan(&m);
        let options = PlanOptions {
            seed,
            deadline: Duration::from_millis(deadline_ms),
            ..PlanOptions::default()
        };
        match plan::solve_tapf(&m.world, &formation(&m), &options) {
            Ok(solution) => {
                prop_assert!(check_tapf(&m, &solution).is_ok(), "{yaml}");
                let optimum = optimum.expect("a plan was found, so one exists");
                prop_assert!(solution.stats.best_lower_bound_steps <= optimum, "{yaml}");
                prop_assert!(solution.makespan_steps >= optimum, "{yaml}");
                if let Some(first) = solution.stats.first_plan_steps {
                    prop_assert!(solution.makespan_steps <= first, "{yaml}");
                }
            }
            Err(PlanError::Deadline { best_lower_bound_steps, .. }) => {
                if let Some(optimum) = optimum {
                    prop_assert!(best_lower_bound_steps <= optimum, "{yaml}");
                }
            }
            Err(e) => prop_assert_eq!(optimum, None, "{}: {}", yaml, e),
        }
    }
}

/// Where the exact search finishes, anytime planning changes nothing but the
/// time: the same optimal makespan, leg by leg, as the exact search alone, and
/// no gap.
#[test]
fn with_time_enough_anytime_planning_keeps_every_leg_optimal() {
    for seed in 1..=3 {
        let m = show(120, 6, [16, 16, 5], seed);
        let anytime = plan::solve(&m, &PlanOptions::default()).expect("planned");
        let exact = PlanOptions {
            first_plan: false,
            ..PlanOptions::default()
        };
        let exact = plan::solve(&m, &exact).expect("planned");
        plan::validate_plan(&m, &anytime.plan).expect("valid");
        let legs = |s: &plan::Solution| -> Vec<u32> {
            s.plan.legs.iter().map(|l| l.makespan_steps).collect()
        };
        assert_eq!(legs(&anytime), legs(&exact), "seed {seed}");
        assert_eq!(anytime.plan.gap_steps(), 0, "seed {seed}");
    }
}

/// A deadline far too short for the exact search still gives a valid plan, whose
/// legs state their gaps (the flight's is their sum); demanding optimality
/// instead fails with the bound proven.
#[test]
fn a_short_deadline_gives_a_valid_plan_with_its_gap_stated() {
    let m = show(400, 20, [30, 30, 8], 1);
    let options = PlanOptions {
        deadline: Duration::from_secs(4),
        ..PlanOptions::default()
    };
    let solution = plan::solve(&m, &options).expect("a plan by the deadline");
    plan::validate_plan(&m, &solution.plan).expect("valid");
    let plan = &solution.plan;
    for leg in &plan.legs {
        let proven = leg.proven_bound_steps.expect("written by this planner");
        assert!(proven >= leg.lower_bound_steps, "{}", leg.name);
        assert!(proven <= leg.makespan_steps, "{}", leg.name);
    }
    let legs_gap: u32 = plan.legs.iter().map(|l| l.gap_steps()).sum();
    assert_eq!(plan.gap_steps(), legs_gap);
    let demanding = PlanOptions {
        deadline: Duration::from_millis(300),
        require_optimal: true,
        ..PlanOptions::default()
    };
    if let Err(e) = plan::solve(&m, &demanding) {
        assert!(matches!(e, PlanError::Leg { .. }), "{e}");
        assert!(e.to_string().contains("deadline"), "{e}");
    }
}

/// A whole flight answers first with every leg's first plan (or, on a small leg,
/// the exact search's answer within its head start), then improves with the time
/// left: a caller that keeps back more time than there is (to schedule and check
/// the plan) gets exactly the first answer, valid, each leg proven optimal or its
/// makespan its first plan's; one that keeps nothing back, with time enough, the
/// optimum, no longer than the first answer.
#[test]
fn the_first_answer_is_a_whole_flight_of_first_plans_and_the_rest_improves_it() {
    let m = show(200, 10, [20, 20, 6], 2);
    let no_time_after = PlanOptions {
        reserve_per_drone_step: Duration::from_secs(3600),
        ..PlanOptions::default()
    };
    let first = plan::solve(&m, &no_time_after).expect("a first answer");
    plan::validate_plan(&m, &first.plan).expect("valid");
    for (leg, stats) in first.plan.legs.iter().zip(&first.stats.legs) {
        let kept_first = stats.first_plan_steps == Some(leg.makespan_steps);
        assert!(leg.gap_steps() == 0 || kept_first, "{}", leg.name);
    }
    let improved = plan::solve(&m, &PlanOptions::default()).expect("planned");
    plan::validate_plan(&m, &improved.plan).expect("valid");
    assert!(improved.plan.makespan_steps <= first.plan.makespan_steps);
    assert_eq!(improved.plan.gap_steps(), 0);
}
