//! Planning under a downwash ellipsoid beside the sphere, in one run.
//!
//! `cargo bench --bench plan_ellipsoid` — the paper's setting (100 drones in 5
//! groups, 10×10×5, 150 obstacles, `swarmctl gen` seeds 1–5, 1 m voxels) planned
//! pad to pad with its sphere (`safety_distance_m: 0.25`) and with the ellipsoid
//! `{ horizontal_m: 0.25, vertical_m: 0.75 }` (its default tracking error 0.115 m:
//! the pad layer and layer 0 of a column are within reach). Prints each makespan
//! beside the sphere's; an instance the ellipsoid does not plan within
//! [`PROBE_S`] is reported and left out of the timings (seed 5's takeoff leg:
//! see the README's Downwash section).

// A benchmark whose instance cannot be built should stop at once, loudly.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use swarmctl::generate::{GenerateOptions, generate};
use swarmctl::mission::{self, MissionFile, schema::SeparationSpec};
use swarmctl::plan::{self, PlanOptions};

/// The generated paper-setting mission for `seed` with `separation` (`None`: the
/// sphere it was generated with).
fn paper(seed: u64, separation: Option<SeparationSpec>) -> MissionFile {
    let mut file = generate(&GenerateOptions {
        seed,
        ..GenerateOptions::default()
    })
    .expect("mission");
    if let Some(s) = separation {
        file.limits.safety_distance_m = None;
        file.limits.separation = Some(s);
    }
    file
}

/// Seconds an instance may take to plan once before it is left out.
const PROBE_S: u64 = 20;

fn bench(c: &mut Criterion) {
    let options = PlanOptions::default();
    let probe = PlanOptions {
        deadline: std::time::Duration::from_secs(PROBE_S),
        ..PlanOptions::default()
    };
    let mut group = c.benchmark_group("plan pad to pad, paper setting");
    group.sample_size(10);
    let downwash = SeparationSpec {
        horizontal_m: 0.25,
        vertical_m: 0.75,
    };
    for seed in 1..=5 {
        let sphere = mission::validate(&paper(seed, None)).expect("valid");
        let ellipsoid = mission::validate(&paper(seed, Some(downwash))).expect("valid");
        let steps = |m| plan::solve(m, &probe).map(|s| s.plan.makespan_steps);
        let (by_sphere, by_ellipsoid) = (steps(&sphere), steps(&ellipsoid));
        println!(
            "seed {seed}: makespan {} steps with the sphere, {} with the ellipsoid 0.25 × 0.75 m",
            by_sphere
                .as_ref()
                .map_or("none".to_string(), u32::to_string),
            by_ellipsoid
                .as_ref()
                .map_or_else(|e| format!("none ({e})"), u32::to_string)
        );
        group.bench_with_input(BenchmarkId::new("sphere", seed), &sphere, |b, m| {
            b.iter(|| black_box(plan::solve(m, &options).expect("plan")));
        });
        if by_ellipsoid.is_err() {
            continue;
        }
        group.bench_with_input(
            BenchmarkId::new("ellipsoid 0.25 x 0.75", seed),
            &ellipsoid,
            |b, m| b.iter(|| black_box(plan::solve(m, &options).expect("plan"))),
        );
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
