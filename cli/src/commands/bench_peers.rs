//! `swarmctl bench peers`: swarmctl side by side with LaCAM3 (one drone per
//! group) and tswap's TSWAP and FlowNetwork (one group) on the same MovingAI
//! instances, each solver a whole process on this machine. The runner and its
//! table are the harness's ([`swarmctl_harness::peers`]); this parses the flags,
//! prints progress and the table.

use anyhow::Context;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;
use swarmctl_harness::peers::{PeerOptions, Problem, run_peers};

/// What `bench peers` takes.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// MovingAI `.map` files (e.g. random-64-64-20.map, den520d.map from
    /// movingai.com or the peers' repositories).
    #[arg(long = "map", value_name = "MAP", required = true)]
    maps: Vec<PathBuf>,
    /// Agent counts, each tried on every map (repeat or comma-separate).
    #[arg(long, value_delimiter = ',', default_value = "1000")]
    agents: Vec<usize>,
    /// Seeds 1..=N of the random starts and goals.
    #[arg(long, default_value_t = 1)]
    seeds: u64,
    /// Which problem: `per-agent` (each agent its own goal; against LaCAM3),
    /// `one-group` (any agent may take any goal; against tswap), or `both`.
    #[arg(long, value_parser = ["per-agent", "one-group", "both"], default_value = "both")]
    problem: String,
    /// LaCAM3's binary (`build/main` of github.com/Kei18/lacam3, built as its
    /// README says).
    #[arg(long, value_name = "BINARY")]
    lacam3: Option<PathBuf>,
    /// tswap's binary (`build/app` of github.com/Kei18/tswap, built as its
    /// README says).
    #[arg(long, value_name = "BINARY")]
    tswap: Option<PathBuf>,
    /// The `map/` folder tswap was built to read maps from (default: `map`
    /// beside the folder holding its binary); the instance's map is copied in.
    #[arg(long, value_name = "DIR")]
    tswap_maps: Option<PathBuf>,
    /// Every solver's time limit, seconds (swarmctl's --deadline).
    #[arg(long, default_value_t = 60.0)]
    limit: f64,
    /// Where instances, results and each run's log are written.
    #[arg(long, value_name = "DIR")]
    work_dir: Option<PathBuf>,
}

/// Runs the comparison and prints its table; fails if swarmctl answered no
/// instance it was given.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let swarmctl = std::env::current_exe().context("finding this swarmctl binary")?;
    let problems = match args.problem.as_str() {
        "per-agent" => vec![Problem::PerAgent],
        "one-group" => vec![Problem::OneGroup],
        _ => vec![Problem::PerAgent, Problem::OneGroup],
    };
    let mut options = PeerOptions::new(swarmctl, args.maps, args.agents);
    options.seeds = args.seeds;
    options.problems = problems;
    options.lacam3 = args.lacam3;
    options.tswap = args.tswap;
    options.tswap_maps = args.tswap_maps;
    options.limit = Duration::try_from_secs_f64(args.limit).context("--limit")?;
    if let Some(dir) = args.work_dir {
        options.work_dir = dir;
    }
    if options.lacam3.is_none() && options.tswap.is_none() {
        eprintln!(
            "no peer given (--lacam3, --tswap): swarmctl runs alone; build the peers from their repositories to compare"
        );
    }
    eprintln!(
        "instances, results and logs in {}",
        options.work_dir.display()
    );
    let report = run_peers(&options, &mut |line| eprintln!("running {line} …"))?;
    print!("{report}");
    let unanswered = report
        .instances
        .iter()
        .filter(|i| i.runs.first().is_none_or(|ours| ours.answer.is_none()))
        .count();
    if unanswered > 0 {
        eprintln!(
            "swarmctl answered {} of {} instances (its logs are in {})",
            report.instances.len() - unanswered,
            report.instances.len(),
            options.work_dir.display()
        );
        return Ok(ExitCode::FAILURE);
    }
    Ok(ExitCode::SUCCESS)
}
