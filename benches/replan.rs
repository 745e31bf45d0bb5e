//! Replanning latency, the computing part: the rest of a flight after a loss,
//! against planning the whole flight in the same run.
//!
//! `cargo bench --bench replan` — the paper's setting (100 drones in 5 groups,
//! 10×10×5, 150 obstacles, `swarmctl gen` seeds 1–5) and the formation change (8
//! drones). Two cases each:
//!
//! - *rest after a loss*: `plan::replan` alone, from where takeoff left the drones,
//!   the first drone whose loss there can be replanned lost and its column blocked;
//! - *splice mid-flight*: everything the flight computes between the freeze and
//!   the new plan executing (`fly::replanning::plan_splice`: replan, independent
//!   check, schedule, routes), with the swarm frozen half-way through the
//!   schedule (`fly::replanning::freeze_target`) and the first drone whose loss there can be
//!   replanned lost. The in-flight latency adds the braking to rest (about 1.5 s
//!   on the formation change, see the fault matrix).
//!
//! Prints each replan's makespan beside the whole plan's.

// A benchmark whose instance cannot be built should stop at once, loudly.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use swarmctl::fly::replanning::{
    SpliceInput, Survivor, freeze_target, lost_voxels, plan_splice, replan_from_leg, routes,
};
use swarmctl::generate::{GenerateOptions, generate};
use swarmctl::mission::{self, Mission};
use swarmctl::plan::{self, PlanOptions};
use swarmctl::world::Voxel;

/// Where takeoff left every drone.
fn after_takeoff(m: &Mission, options: &PlanOptions) -> Vec<(String, Voxel)> {
    let whole = plan::solve(m, options).expect("plan").plan;
    let step = whole.legs[0].end_step as usize;
    whole
        .drones
        .iter()
        .map(|d| (d.id.clone(), d.path[step]))
        .collect()
}

/// Everyone in `at` but drone `lost`, as `plan::replan` takes survivors.
fn survivors_without(at: &[(String, Voxel)], lost: usize) -> Vec<(&str, Voxel)> {
    at.iter()
        .enumerate()
        .filter(|&(j, _)| j != lost)
        .map(|(_, (id, v))| (id.as_str(), *v))
        .collect()
}

/// The first drone (in mission order) whose loss right after takeoff the replan
/// answers, and how many before it it could not: a loss whose column holds a
/// survivor, another group's goal or pad leaves no plan by design (`plan::replan`).
fn first_answerable_loss(
    m: &Mission,
    at: &[(String, Voxel)],
    options: &PlanOptions,
) -> (usize, usize) {
    for i in 0..at.len() {
        let survivors = survivors_without(at, i);
        if plan::replan(m, 1, &survivors, &[at[i].1], options).is_ok() {
            return (i, i);
        }
    }
    panic!("no single loss can be replanned");
}

/// The swarm frozen half-way through the schedule of `m`'s plan, with the first
/// drone whose loss there can be replanned lost: what `plan_splice` gets in flight.
fn frozen_mid_flight(m: &Mission, options: &PlanOptions) -> (SpliceInput, String) {
    let plan = plan::solve(m, options).expect("plan").plan;
    let checked = swarmctl::compiled::compile_plan(m, &plan, 0).expect("checked");
    let routes = routes(&checked);
    let makespan_s = checked.compiled().execution.makespan_s;
    let t_s = makespan_s / 2.0;
    let frozen: Vec<_> = routes
        .iter()
        .map(|r| {
            let arc_m = r.scheduled_arc_m(t_s);
            (freeze_target(r, arc_m).expect("target"), arc_m)
        })
        .collect();
    for lost in 0..routes.len() {
        let survivors: Vec<Survivor> = (0..routes.len())
            .filter(|&i| i != lost)
            .map(|i| Survivor {
                id: routes[i].id.clone(),
                run_index: i,
                voxel: frozen[i].0.voxel,
                rest_m: frozen[i].0.position_m,
            })
            .collect();
        let arc_m = frozen[lost].1;
        let input = SpliceInput {
            mission: m.clone(),
            from_leg: replan_from_leg(
                m,
                &plan,
                survivors.iter().map(|s| frozen[s.run_index].0.step),
            ),
            survivors,
            lost: lost_voxels(m, &routes[lost], arc_m, arc_m, None),
            options: options.clone(),
        };
        if plan_splice(&input).is_ok() {
            return (
                input,
                format!(
                    "{} lost at {t_s:.1} s, {lost} earlier drones' losses have no plan",
                    routes[lost].id
                ),
            );
        }
    }
    panic!("no single loss mid-flight can be replanned");
}

fn replan_after_a_loss(c: &mut Criterion) {
    let options = PlanOptions::default();
    let mut missions: Vec<(String, Mission)> = (1..=5)
        .map(|seed| {
            let file = generate(&GenerateOptions {
                seed,
                ..GenerateOptions::default()
            })
            .expect("mission");
            (
                format!("paper-scale seed {seed}"),
                mission::validate(&file).expect("valid"),
            )
        })
        .collect();
    let formation = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/missions/formation-change.yaml"
    );
    missions.push((
        "formation change".into(),
        mission::load(std::path::Path::new(formation)).expect("mission"),
    ));
    let mut group = c.benchmark_group("replan");
    for (name, m) in &missions {
        let at = after_takeoff(m, &options);
        let (lost_index, unanswered) = first_answerable_loss(m, &at, &options);
        let lost = at[lost_index].1;
        let named = survivors_without(&at, lost_index);
        let re = plan::replan(m, 1, &named, &[lost], &options).expect("replan");
        plan::validate_rest(&re.mission, re.from_leg, &named, &re.solution.plan)
            .expect("the checker takes the replan");
        eprintln!(
            "{name}: {} lost ({unanswered} earlier drones' losses have no plan)",
            at[lost_index].0
        );
        let whole = plan::solve(m, &options).expect("plan").plan;
        eprintln!(
            "{name}: {} survivors; rest of the flight {} steps (legs {:?}) vs whole {} steps",
            named.len(),
            re.solution.plan.makespan_steps,
            re.solution
                .plan
                .legs
                .iter()
                .map(|l| l.makespan_steps)
                .collect::<Vec<_>>(),
            whole.makespan_steps
        );
        group.bench_with_input(BenchmarkId::new("whole flight", name), m, |b, m| {
            b.iter(|| black_box(plan::solve(m, &options).unwrap()))
        });
        group.bench_with_input(BenchmarkId::new("rest after a loss", name), m, |b, m| {
            b.iter(|| black_box(plan::replan(m, 1, &named, &[lost], &options).unwrap()))
        });
        let (frozen, which) = frozen_mid_flight(m, &options);
        let splice = plan_splice(&frozen).expect("splice");
        eprintln!(
            "{name}: {which}; the new plan runs {:.1} s; planned, checked and scheduled in {:.1} ms, the check of its spliced trajectories {}",
            splice.makespan_s,
            1e3 * splice.planning_s,
            splice.check.line()
        );
        group.bench_with_input(
            BenchmarkId::new("splice mid-flight", name),
            &frozen,
            |b, input| b.iter(|| black_box(plan_splice(input).unwrap())),
        );
    }
    group.finish();
}

criterion_group!(benches, replan_after_a_loss);
criterion_main!(benches);
