use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;
use swarmctl::{mission, plan};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mission file (YAML).
    mission: PathBuf,
    /// Write the plan (JSON) here.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Give up after this many seconds, reporting the best lower bound proven.
    #[arg(long, default_value_t = 60.0)]
    deadline: f64,
    /// Seed for tie-breaking; the same seed gives the same plan.
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mission = mission::load(&args.mission)?;
    let deadline = Duration::try_from_secs_f64(args.deadline)
        .ok()
        .filter(|d| !d.is_zero())
        .context("--deadline must be a positive number of seconds")?;
    let options = plan::PlanOptions {
        deadline,
        seed: args.seed,
    };
    let spinner = ProgressBar::new_spinner();
    spinner.set_style(ProgressStyle::with_template("{spinner} {msg}").expect("static template"));
    spinner.set_message(format!("planning {} drones", mission.drone_count()));
    spinner.enable_steady_tick(Duration::from_millis(120));
    let result = plan::solve_with_progress(&mission, &options, &mut |p| {
        spinner.set_message(format!(
            "planning: {} conflict-tree nodes, {} open, makespan ≥ {} steps, {:.1} s",
            p.ct_nodes_expanded,
            p.open_nodes,
            p.best_lower_bound_steps,
            p.elapsed.as_secs_f64()
        ));
    });
    spinner.finish_and_clear();
    let solution = result.with_context(|| format!("planning {}", args.mission.display()))?;
    if let Err(violations) = plan::validate_plan(&mission, &solution.plan) {
        let list: Vec<String> = violations.iter().map(|v| format!("  {v}")).collect();
        anyhow::bail!(
            "the planner produced an invalid plan (a bug):\n{}",
            list.join("\n")
        );
    }
    let s = &solution.stats;
    let p = &solution.plan;
    println!(
        "{}: planned {} drones in {} groups",
        args.mission.display(),
        p.drones.len(),
        mission.groups.len()
    );
    println!(
        "  makespan        {} steps (lower bound {}{})",
        p.makespan_steps,
        s.initial_lower_bound_steps,
        if p.makespan_steps == s.initial_lower_bound_steps {
            ", optimal by the bound"
        } else {
            "; optimal by search"
        }
    );
    println!("  sum of costs    {} steps", p.sum_of_costs_steps);
    println!(
        "  conflict tree   {} nodes expanded, {} generated; {} flow augmentations",
        s.ct_nodes_expanded, s.ct_nodes_generated, s.flow_augmentations
    );
    println!(
        "  time            {:.3} s ({:.3} s low level, {:.3} s high level)",
        s.total_time.as_secs_f64(),
        s.low_level_time.as_secs_f64(),
        s.high_level_time().as_secs_f64()
    );
    if let Some(path) = &args.output {
        let json = serde_json::to_string_pretty(p)?;
        std::fs::write(path, json).with_context(|| format!("cannot write {}", path.display()))?;
        println!("  wrote           {}", path.display());
    }
    Ok(ExitCode::SUCCESS)
}
