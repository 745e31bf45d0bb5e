//! Planner suites: the paper's setting, a larger scale, plain MAPF and one big group.

use std::time::{Duration, Instant};
use swarmctl::generate::{GenerateOptions, generate};
use swarmctl::mission::validate;
use swarmctl::plan::{PlanOptions, solve, validate_plan};

/// A family of random instances (`swarmctl bench plan --suite`, by its lowercase
/// name).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum PlanSuite {
    /// 10×10×5 voxels, 150 obstacles, 100 drones in 5 groups (the paper's setting).
    Paper,
    /// 32×32×8 voxels, 10% obstacles, 400 drones in 10 groups.
    Scale,
    /// 32×32 grid, 10% obstacles, 50 agents each its own group (plain MAPF).
    Mapf,
    /// 32×32×8 voxels, 10% obstacles, 500 drones in one anonymous group.
    Anonymous,
    /// 5×5×2 voxels, 12 obstacles, 16 drones in 4 groups: small and tight, where a
    /// conflict tree alone explodes (`swarmctl gen --size 5x5x2 --obstacles 12
    /// --drones 16 --groups 4 --seed S`).
    Dense,
    /// The same world with 22 drones: 22 of its 38 free voxels taken, where the
    /// conflict tree's heavy tail shows today.
    Crowded,
}

impl PlanSuite {
    /// The generator settings for instance `seed` of this suite: every seed
    /// gives the same sizes, only the random layout differs.
    pub fn options(self, seed: u64) -> GenerateOptions {
        let (dimensions, obstacles, drones, groups) = match self {
            PlanSuite::Paper => ([10, 10, 5], 150, 100, 5),
            PlanSuite::Scale => ([32, 32, 8], 819, 400, 10),
            PlanSuite::Mapf => ([32, 32, 1], 102, 50, 50),
            PlanSuite::Anonymous => ([32, 32, 8], 819, 500, 1),
            PlanSuite::Dense => ([5, 5, 2], 12, 16, 4),
            PlanSuite::Crowded => ([5, 5, 2], 12, 22, 4),
        };
        GenerateOptions {
            dimensions,
            obstacles,
            drones,
            groups,
            seed,
            voxel_size_m: 1.0,
            ..GenerateOptions::default()
        }
    }
}

/// Figures for one suite.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanSuiteReport {
    /// The suite that was run.
    pub suite: PlanSuite,
    /// Instances attempted (one per seed).
    pub instances: usize,
    /// Instances planned within the deadline with a valid plan.
    pub solved: usize,
    /// Wall time of each solved instance, seconds.
    pub times_s: Vec<f64>,
    /// (makespan, lower bound) of each solved instance, pad to pad (the lower bound
    /// is the sum of the legs' bounds).
    pub makespans: Vec<(u32, u32)>,
    /// Per solved instance, per leg: (name, makespan, lower bound).
    pub legs: Vec<Vec<(String, u32, u32)>>,
    /// Conflict-tree nodes expanded for each solved instance: the planner's work,
    /// independent of the machine's speed.
    pub ct_nodes: Vec<u64>,
}

/// Plans seeds `1..=seeds` of `suite`, each within `deadline`, handing a conflict
/// tree to the exact SAT encoding after `exact_after_ct_nodes` nodes (`None`: CBM
/// alone); every plan is validated. `on_instance` hears each seed as it finishes:
/// (time s, makespan, lower bound, conflict-tree nodes), or why it failed.
pub fn run_plan_suite(
    suite: PlanSuite,
    seeds: u64,
    deadline: Duration,
    exact_after_ct_nodes: Option<u64>,
    mut on_instance: impl FnMut(u64, Result<(f64, u32, u32, u64), String>),
) -> PlanSuiteReport {
    let mut report = PlanSuiteReport {
        suite,
        instances: 0,
        solved: 0,
        times_s: Vec::new(),
        makespans: Vec::new(),
        legs: Vec::new(),
        ct_nodes: Vec::new(),
    };
    for seed in 1..=seeds {
        report.instances += 1;
        let mission = match generate(&suite.options(seed)).map(|f| validate(&f)) {
            Ok(Ok(m)) => m,
            Ok(Err(problems)) => {
                on_instance(
                    seed,
                    Err(format!("generated an invalid mission: {problems:?}")),
                );
                continue;
            }
            Err(e) => {
                on_instance(seed, Err(e.to_string()));
                continue;
            }
        };
        let started = Instant::now();
        let options = PlanOptions {
            deadline,
            exact_after_ct_nodes,
            ..PlanOptions::default()
        };
        let result = solve(&mission, &options);
        let time_s = started.elapsed().as_secs_f64();
        match result {
            Ok(solution) => {
                if let Err(v) = validate_plan(&mission, &solution.plan) {
                    on_instance(seed, Err(format!("invalid plan: {v:?}")));
                    continue;
                }
                let makespan = solution.plan.makespan_steps;
                let lower_bound = solution.stats.initial_lower_bound_steps;
                report.solved += 1;
                report.times_s.push(time_s);
                report.makespans.push((makespan, lower_bound));
                report.legs.push(
                    solution
                        .plan
                        .legs
                        .iter()
                        .map(|l| (l.name.clone(), l.makespan_steps, l.lower_bound_steps))
                        .collect(),
                );
                report.ct_nodes.push(solution.stats.ct_nodes_expanded);
                on_instance(
                    seed,
                    Ok((
                        time_s,
                        makespan,
                        lower_bound,
                        solution.stats.ct_nodes_expanded,
                    )),
                );
            }
            Err(e) => on_instance(seed, Err(e.to_string())),
        }
    }
    report
}
