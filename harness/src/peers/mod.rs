//! swarmctl side by side with the public solvers, on the same instances, each a
//! whole process on the same machine: `swarmctl bench peers`.
//!
//! The peers are LaCAM3 for one drone per group (labeled MAPF) and tswap's
//! TSWAP and FlowNetwork for one group (every agent free to take any goal).
//! They are built by the user from their own repositories, as their READMEs say,
//! and named by path; swarmctl builds and fetches nothing. Each instance is a
//! MovingAI map with seeded random starts and goals ([`random_instance`]),
//! written once and given to every solver; each run is a child process bounded
//! in time, measured from `exec` to exit ([`ChildRun`]).
//!
//! ```no_run
//! use swarmctl_harness::peers::{PeerOptions, run_peers};
//! let options = PeerOptions {
//!     lacam3: Some("lacam3/build/main".into()),
//!     ..PeerOptions::new("target/release/swarmctl", vec!["random-64-64-20.map".into()], vec![1000])
//! };
//! let report = run_peers(&options, &mut |line| eprintln!("{line}")).unwrap();
//! print!("{report}");
//! ```

mod child;
mod instance;
mod lacam3;
mod report;
mod result_file;
mod subject;
mod tswap;

pub use child::{ChildRun, Exit};
pub use instance::{GridInstance, random_instance};
pub use report::PeersReport;

use crate::HarnessError;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// Which problem an instance is solved as.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Problem {
    /// Every agent its own group, with its own goal (labeled MAPF): against LaCAM3.
    PerAgent,
    /// Every agent in one group, free to take any goal: against tswap.
    OneGroup,
}

impl Problem {
    /// Its short name in the table and in file names.
    pub fn name(self) -> &'static str {
        match self {
            Problem::PerAgent => "per-agent",
            Problem::OneGroup => "one-group",
        }
    }
}

/// What to run: maps, agent counts and seeds, and where the solvers are.
#[derive(Debug, Clone)]
pub struct PeerOptions {
    /// MovingAI `.map` files.
    pub maps: Vec<PathBuf>,
    /// Agent counts, each tried on every map.
    pub agents: Vec<usize>,
    /// Seeds `1..=seeds` for the random starts and goals.
    pub seeds: u64,
    /// The problems to solve each instance as.
    pub problems: Vec<Problem>,
    /// The `swarmctl` binary measured (the running one, as a rule).
    pub swarmctl: PathBuf,
    /// LaCAM3's `main` binary, if built.
    pub lacam3: Option<PathBuf>,
    /// tswap's `app` binary, if built.
    pub tswap: Option<PathBuf>,
    /// The `map/` folder tswap was built to read maps from (by default the
    /// `map` folder beside the `build` folder holding `app`).
    pub tswap_maps: Option<PathBuf>,
    /// Every solver's time limit (swarmctl's `--deadline`).
    pub limit: Duration,
    /// Where instances, results and logs are written.
    pub work_dir: PathBuf,
}

impl PeerOptions {
    /// Both problems, seed 1, a 60 s limit, no peers, files under the system's
    /// temporary folder.
    pub fn new(swarmctl: impl Into<PathBuf>, maps: Vec<PathBuf>, agents: Vec<usize>) -> Self {
        PeerOptions {
            maps,
            agents,
            seeds: 1,
            problems: vec![Problem::PerAgent, Problem::OneGroup],
            swarmctl: swarmctl.into(),
            lacam3: None,
            tswap: None,
            tswap_maps: None,
            limit: Duration::from_secs(60),
            work_dir: std::env::temp_dir().join("swarmctl-peers"),
        }
    }

    /// The folder tswap reads maps from.
    fn tswap_map_dir(&self, tswap: &std::path::Path) -> PathBuf {
        self.tswap_maps.clone().unwrap_or_else(|| {
            let build = tswap.parent().unwrap_or(std::path::Path::new("."));
            build.parent().unwrap_or(build).join("map")
        })
    }
}

/// A solver's first solution, and its final one where it improves on it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Answer {
    /// Its own time to its first solution, seconds (swarmctl: the formation
    /// leg's first plan).
    pub first_solution_s: f64,
    /// The first solution's makespan, steps.
    pub first_makespan_steps: u64,
    /// The makespan it ended with, steps.
    pub makespan_steps: u64,
    /// The lower bound it states, steps, if it states one.
    pub lower_bound_steps: Option<u64>,
    /// Whether it proved its makespan optimal.
    pub optimal: bool,
}

/// One solver on one instance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeerRun {
    /// `swarmctl`, `LaCAM3`, `TSWAP` or `FlowNetwork`.
    pub solver: &'static str,
    /// What the process cost and how it ended.
    pub process: ChildRun,
    /// What it answered (`None`: no solution within its limit, or a failure;
    /// its log says which).
    pub answer: Option<Answer>,
}

/// One instance solved as one problem: swarmctl first, then its peers.
#[derive(Debug, Clone, PartialEq)]
pub struct InstanceRuns {
    /// The map's file name.
    pub map: String,
    /// How many agents.
    pub agents: usize,
    /// The seed of its starts and goals.
    pub seed: u64,
    /// The problem solved.
    pub problem: Problem,
    /// swarmctl's run, then each peer's.
    pub runs: Vec<PeerRun>,
}

/// Runs every solver on every instance, telling `progress` what starts.
pub fn run_peers(
    options: &PeerOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<PeersReport, HarnessError> {
    std::fs::create_dir_all(&options.work_dir).map_err(|source| HarnessError::Io {
        what: format!("creating {}", options.work_dir.display()),
        source,
    })?;
    let mut instances = Vec::new();
    for map in &options.maps {
        for &agents in &options.agents {
            for seed in 1..=options.seeds {
                let instance = random_instance(map, agents, seed, &options.work_dir)?;
                for &problem in &options.problems {
                    progress(&format!(
                        "{}, {agents} agents, seed {seed}, {}",
                        instance.map_name,
                        problem.name()
                    ));
                    instances.push(InstanceRuns {
                        map: instance.map_name.clone(),
                        agents,
                        seed,
                        problem,
                        runs: solve(options, problem, &instance)?,
                    });
                }
            }
        }
    }
    Ok(PeersReport { instances })
}

/// swarmctl and the peers of `problem` on `instance`.
fn solve(
    options: &PeerOptions,
    problem: Problem,
    instance: &GridInstance,
) -> Result<Vec<PeerRun>, HarnessError> {
    let (limit, dir) = (options.limit, &options.work_dir);
    let mut runs = vec![subject::run(
        &options.swarmctl,
        problem,
        instance,
        limit,
        dir,
    )?];
    match problem {
        Problem::PerAgent => {
            if let Some(lacam3) = &options.lacam3 {
                runs.push(lacam3::run(lacam3, instance, limit, dir)?);
            }
        }
        Problem::OneGroup => {
            if let Some(tswap) = &options.tswap {
                let maps = options.tswap_map_dir(tswap);
                for solver in [tswap::Solver::Tswap, tswap::Solver::FlowNetwork] {
                    runs.push(tswap::run(tswap, &maps, solver, instance, limit, dir)?);
                }
            }
        }
    }
    Ok(runs)
}

/// Runs `solver` as `command`, which writes its answer to `result`, killed at
/// `limit` with its output in `log`; the answer is `parse` of the result file
/// when the process exited with status 0. A result left by an earlier run is
/// removed first, so it is never read as this run's.
fn run_solver(
    solver: &'static str,
    command: &mut Command,
    (limit, log): (Duration, &Path),
    result: &Path,
    parse: impl Fn(&str) -> Option<Answer>,
) -> Result<PeerRun, HarnessError> {
    let _ = std::fs::remove_file(result);
    let process = child::run_bounded(command, limit, log)?;
    let answer = if process.succeeded() {
        std::fs::read_to_string(result)
            .ok()
            .and_then(|text| parse(&text))
    } else {
        None
    };
    Ok(PeerRun {
        solver,
        process,
        answer,
    })
}
