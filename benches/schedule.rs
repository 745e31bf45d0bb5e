//! Scheduling benchmarks: TPG construction, STN solve and trajectories, from 100 to
//! 10,000 drones on synthetic lane traffic (see `schedule_instances.rs`).
//!
//! `cargo bench --bench schedule` — prints, per size, events, type-2 edges and the
//! makespan in seconds against the discrete makespan × voxel size / max speed.

// A benchmark whose instance cannot be built should stop at once, loudly.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod schedule_instances;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;
use swarmctl::generate::{GenerateOptions, generate};
use swarmctl::plan::{self, PlanOptions};
use swarmctl::{mission, schedule, trajectory, verify};

/// The paper's setting: 10×10×5, 150 obstacles, 100 drones in 5 groups, planned by CBM.
fn paper_scale(c: &mut Criterion) {
    let file = generate(&GenerateOptions::default()).expect("mission");
    let m = mission::validate(&file).expect("valid mission");
    let p = plan::solve(&m, &PlanOptions::default()).expect("plan").plan;
    let tpg = schedule::build(&m, &p).expect("tpg");
    let s = schedule::solve(&tpg).expect("schedule");
    let lockstep_s = f64::from(p.makespan_steps) * m.world.voxel_size_m() / m.limits.max_speed_mps;
    eprintln!(
        "paper-scale: {} events, {} type-2 edges; makespan {:.2} s vs discrete {} steps x {} m / \
         {} m/s = {lockstep_s:.2} s (ratio {:.2})",
        tpg.event_count(),
        tpg.cross_edges.len(),
        s.makespan_s,
        p.makespan_steps,
        m.world.voxel_size_m(),
        m.limits.max_speed_mps,
        s.makespan_s / lockstep_s
    );
    let mut group = c.benchmark_group("paper-scale");
    group.bench_function("build+solve+trajectories", |b| {
        b.iter(|| {
            let tpg = schedule::build(&m, black_box(&p)).unwrap();
            let s = schedule::solve(&tpg).unwrap();
            black_box(trajectory::from_schedule(&s))
        })
    });
    let t = trajectory::from_schedule(&s);
    group.bench_function("sample", |b| {
        b.iter(|| black_box(t.sample(m.link.setpoint_rate_hz)))
    });
    let samples = t.sample(m.link.setpoint_rate_hz);
    group.bench_function("verify", |b| {
        b.iter(|| black_box(verify::check(&samples, &m.limits).unwrap()))
    });
    group.finish();
}

fn scaling(c: &mut Criterion) {
    let mut group = c.benchmark_group("schedule");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(4));
    for drones in [100usize, 1_000, 10_000] {
        let (world, limits, plan) = schedule_instances::lanes(drones, 7);
        let tpg = schedule::build_with(&world, &limits, &plan).expect("tpg");
        let s = schedule::solve(&tpg).expect("schedule");
        let lockstep_s =
            f64::from(plan.makespan_steps) * world.voxel_size_m() / limits.max_speed_mps;
        eprintln!(
            "lanes {drones}: {} events, {} type-2 edges, {} STN timepoints; makespan {:.2} s vs \
             discrete {} steps × {} m / {} m/s = {lockstep_s:.2} s (ratio {:.2})",
            tpg.event_count(),
            tpg.cross_edges.len(),
            s.stn.timepoints,
            s.makespan_s,
            plan.makespan_steps,
            world.voxel_size_m(),
            limits.max_speed_mps,
            s.makespan_s / lockstep_s
        );
        group.bench_with_input(
            BenchmarkId::new("build+solve+trajectories", drones),
            &plan,
            |b, plan| {
                b.iter(|| {
                    let tpg = schedule::build_with(&world, &limits, black_box(plan)).unwrap();
                    let s = schedule::solve(&tpg).unwrap();
                    black_box(trajectory::from_schedule(&s))
                })
            },
        );
        group.bench_with_input(BenchmarkId::new("build", drones), &plan, |b, plan| {
            b.iter(|| black_box(schedule::build_with(&world, &limits, black_box(plan)).unwrap()))
        });
        group.bench_with_input(BenchmarkId::new("solve", drones), &tpg, |b, tpg| {
            b.iter(|| black_box(schedule::solve(black_box(tpg)).unwrap()))
        });
        if drones <= 1_000 {
            let t = trajectory::from_schedule(&s);
            group.bench_with_input(BenchmarkId::new("sample 20 Hz", drones), &t, |b, t| {
                b.iter(|| black_box(t.sample(20.0)))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, paper_scale, scaling);
criterion_main!(benches);
