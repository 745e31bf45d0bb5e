use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};
use swarmctl::{compiled, import, plan};

#[derive(Debug, clap::Args)]
#[command(group = clap::ArgGroup::new("input").required(true).args(["mission", "scen"]))]
pub struct Args {
    /// Mission file (YAML), or an instance in a community format: a
    /// libMultiRobotPlanning YAML, a MovingAI `.scen` or a MovingAI 3D `.3dscen`.
    mission: Option<PathBuf>,
    /// A MovingAI scenario (its map is looked up next to it); same as giving it as MISSION.
    #[arg(long)]
    scen: Option<PathBuf>,
    /// How many agents to take from a scenario (default: all rows).
    #[arg(long)]
    agents: Option<usize>,
    /// Plan a community instance's agents as one team: any agent may take any
    /// agent's goal (the unlabeled problem TSWAP solves on the same files).
    #[arg(long)]
    one_group: bool,
    /// Write the plan (JSON) here.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Write the planner's figures here (JSON): per leg its makespan, lower
    /// bound, proven bound, first plan and time; for scripts and benchmarks.
    #[arg(long, value_name = "FILE")]
    stats: Option<PathBuf>,
    /// Answer within this many seconds (plus a margin: the deadline is kept
    /// within 10 % when the plan's schedule takes what it usually does): the best
    /// plan found by then, scheduled and checked, with its gap to the lower bound
    /// (or, with --optimal, a failure naming the bound proven).
    #[arg(long, default_value_t = 60.0)]
    deadline: f64,
    /// Accept only a plan proven makespan-optimal: fail at the deadline rather
    /// than return a plan above the lower bound.
    #[arg(long)]
    optimal: bool,
    /// Seed for tie-breaking; the same seed gives the same plan.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    #[command(flatten)]
    viewer: swarmctl_cli::record::ViewerArgs,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let began = Instant::now();
    let input = args.mission.or(args.scen).context("no mission given")?;
    let mission = if args.one_group {
        import::load_as_one_group(&input, args.agents)?
    } else {
        import::load_any(&input, args.agents)?
    };
    let options = plan::PlanOptions {
        seed: args.seed,
        ..deadline_options(args.deadline, began, args.optimal)?
    };
    let solution = solve_with_spinner(&mission, &options)
        .with_context(|| format!("planning {}{}", input.display(), reach_hint(&mission)))?;
    if let Err(violations) = plan::validate_plan(&mission, &solution.plan) {
        let list: Vec<String> = violations.iter().map(|v| format!("  {v}")).collect();
        anyhow::bail!(
            "the planner produced an invalid plan (a bug):\n{}",
            list.join("\n")
        );
    }
    print_solution(&input, &mission, &solution);
    if let Some(path) = &args.stats {
        let json = serde_json::to_vec_pretty(&solution.stats).context("encoding the figures")?;
        std::fs::write(path, json).with_context(|| format!("cannot write {}", path.display()))?;
    }
    super::pads::print_pads_and_legs(&mission);
    let compiled = compiled::compile(&mission, &solution)
        .with_context(|| format!("scheduling {} (no plan file written)", input.display()))?;
    let c = &compiled.check;
    let ideal_s = f64::from(solution.plan.makespan_steps) * mission.world.voxel_size_m()
        / mission.limits.max_speed_mps;
    println!(
        "  schedule        {:.2} s to the last arrival ({:.2} s if every drone cruised at top speed in lockstep)",
        compiled.makespan_s, ideal_s
    );
    println!(
        "  checked         min separation ≥ {:.3} m (safety {:.3} m), max speed {:.3} m/s (limit {}), max accel {:.3} m/s² (limit {}), max jerk {:.2} m/s³ (limit {})",
        c.min_separation_bound_m,
        mission.limits.safety_distance_m,
        c.max_speed_mps,
        mission.limits.max_speed_mps,
        c.max_accel_mps2,
        mission.limits.max_accel_mps2,
        c.max_jerk_mps3,
        mission.limits.max_jerk_mps3
    );
    if let Some(scaled) = &c.scaled {
        println!(
            "  ellipsoid       scaled separation ≥ {:.3} of setpoints (separated at 1: outside each other's cylinder {:.3} m across, {:.3} m up and down — the ellipsoid {:.3} × {:.3} m grown by twice the tracking error {:.3} m)",
            scaled.min_bound,
            scaled.horizontal_m,
            scaled.vertical_m,
            mission.limits.safety_distance_m,
            mission
                .limits
                .vertical_separation_m
                .unwrap_or(mission.limits.safety_distance_m),
            mission.limits.tracking_error_m
        );
    }
    if let Some(path) = &args.output {
        // Streamed: a 5,000-drone plan is about 900 MB of JSON, which need not
        // sit in memory as one string first.
        let cannot = || format!("cannot write {}", path.display());
        let file = std::fs::File::create(path).with_context(cannot)?;
        let mut out = std::io::BufWriter::new(file);
        serde_json::to_writer(&mut out, &compiled).with_context(cannot)?;
        std::io::Write::flush(&mut out).with_context(cannot)?;
        println!("  wrote           {}", path.display());
    } else {
        println!(
            "  plan file       none written: give -o PLAN.json to keep the plan, then `swarmctl fly {} --plan PLAN.json` flies it without planning again",
            input.display()
        );
    }
    if let Some(sink) = args.viewer.sink() {
        swarmctl_cli::record::record_plan(&mission, &compiled, &sink)
            .context("recording the plan")?;
        println!("  recording       {}", super::replay::describe(&sink));
    }
    Ok(ExitCode::SUCCESS)
}

/// The planner's options for an answer `deadline_s` seconds after `began` (when
/// the command started): what is already spent (reading the mission) comes off,
/// and the planner keeps back the time to schedule and check what it plans
/// ([`compiled::COMPILE_TIME_PER_DRONE_STEP`]). With `optimal`, only a plan proven
/// makespan-optimal is accepted.
pub(crate) fn deadline_options(
    deadline_s: f64,
    began: Instant,
    optimal: bool,
) -> anyhow::Result<plan::PlanOptions> {
    let deadline = Duration::try_from_secs_f64(deadline_s)
        .ok()
        .filter(|d| !d.is_zero())
        .context("--deadline must be a positive number of seconds")?;
    Ok(plan::PlanOptions {
        deadline: deadline.saturating_sub(began.elapsed()),
        require_optimal: optimal,
        reserve_per_drone_step: compiled::COMPILE_TIME_PER_DRONE_STEP,
        ..plan::PlanOptions::default()
    })
}

/// Plans `mission`, showing the planner's progress on a spinner.
fn solve_with_spinner(
    mission: &swarmctl::mission::Mission,
    options: &plan::PlanOptions,
) -> Result<plan::Solution, plan::PlanError> {
    let spinner = ProgressBar::new_spinner();
    // The template is fixed; were it ever refused, the default spinner does as well.
    if let Ok(style) = ProgressStyle::with_template("{spinner} {msg}") {
        spinner.set_style(style);
    }
    spinner.set_message(format!("planning {} drones", mission.drone_count()));
    // A step is one voxel at top speed: the bound in seconds, for a sense of scale.
    let step_s = mission.world.voxel_size_m() / mission.limits.max_speed_mps;
    spinner.enable_steady_tick(Duration::from_millis(120));
    let result = plan::solve_with_progress(mission, options, &mut |p| {
        let work = match p.phase {
            plan::PlanPhase::ConflictTree => format!(
                "conflict tree, {}, {} open",
                count(p.ct_nodes_expanded, "node"),
                p.open_nodes
            ),
            other => other.to_string(),
        };
        let best = match p.incumbent_steps {
            Some(steps) => format!(", best plan so far {}", count(u64::from(steps), "step")),
            None => String::new(),
        };
        spinner.set_message(format!(
            "planning leg {}: {work}, makespan ≥ {} (≥ {:.1} s at top speed){best}, {:.1} s so far",
            p.leg,
            count(u64::from(p.best_lower_bound_steps), "step"),
            f64::from(p.best_lower_bound_steps) * step_s,
            p.elapsed.as_secs_f64()
        ));
    });
    spinner.finish_and_clear();
    result
}

/// The plan's figures: makespan against the lower bound, the search's work and time.
fn print_solution(
    input: &std::path::Path,
    mission: &swarmctl::mission::Mission,
    solution: &plan::Solution,
) {
    let s = &solution.stats;
    let p = &solution.plan;
    println!(
        "{}: planned {} in {}",
        input.display(),
        count(p.drones.len() as u64, "drone"),
        count(mission.groups.len() as u64, "group")
    );
    let proven: u32 = s.legs.iter().map(|l| l.proven_bound_steps).sum();
    println!(
        "  makespan        {} steps pad to pad in {} legs, {}",
        p.makespan_steps,
        p.legs.len(),
        bound_and_gap(p.makespan_steps, proven, s.initial_lower_bound_steps)
    );
    for leg in &s.legs {
        let first = match leg.first_plan_steps {
            Some(steps) => format!(
                "first plan {}{} in {:.3} s",
                count(u64::from(steps), "step"),
                if leg.straight_lines {
                    " on straight lines"
                } else {
                    ""
                },
                leg.first_plan_time.as_secs_f64()
            ),
            None => "no first plan".to_string(),
        };
        println!(
            "  leg {:<11} {}, {}; {first}, {}, {:.3} s",
            leg.name,
            count(u64::from(leg.makespan_steps), "step"),
            bound_and_gap(
                leg.makespan_steps,
                leg.proven_bound_steps,
                leg.lower_bound_steps
            ),
            count(leg.ct_nodes_expanded, "node"),
            leg.time.as_secs_f64()
        );
    }
    println!("  sum of costs    {} steps", p.sum_of_costs_steps);
    println!(
        "  conflict tree   {} nodes expanded, {} generated; {} flow augmentations",
        s.ct_nodes_expanded, s.ct_nodes_generated, s.flow_augmentations
    );
    if s.sat_horizons > 0 {
        println!(
            "  exact (SAT)     {} horizons decided in {:.3} s, beside the conflict tree",
            s.sat_horizons,
            s.sat_time.as_secs_f64()
        );
    }
    println!(
        "  time            {:.3} s ({:.3} s low level, {:.3} s high level)",
        s.total_time.as_secs_f64(),
        s.low_level_time.as_secs_f64(),
        s.high_level_time().as_secs_f64()
    );
}

/// `optimal (lower bound 30)` or `lower bound 29 (gap 2 steps, 6.9 %)`: the
/// proven bound against the makespan, and the bottleneck bound when it is less.
pub(crate) fn bound_and_gap(
    makespan_steps: u32,
    proven_steps: u32,
    bottleneck_steps: u32,
) -> String {
    let gap = makespan_steps.saturating_sub(proven_steps);
    if gap == 0 {
        let how = if bottleneck_steps >= makespan_steps {
            "by the bound"
        } else {
            "by search"
        };
        return format!("optimal {how} (lower bound {bottleneck_steps})");
    }
    format!(
        "lower bound {proven_steps} (gap {}, {:.1} %)",
        count(u64::from(gap), "step"),
        100.0 * f64::from(gap) / f64::from(proven_steps.max(1))
    )
}

/// Under an ellipsoid whose vertical reach relates cells of a column, what the
/// planner then also has to keep apart and how to lift it: said with a planning
/// failure, since such conflicts can make a tight leg much harder to solve.
pub(super) fn reach_hint(mission: &swarmctl::mission::Mission) -> String {
    let l = &mission.limits;
    let reach = l.vertical_reach(&mission.airspace);
    if !l.is_ellipsoid() || reach.is_trivial(&mission.airspace) {
        return String::new();
    }
    format!(
        " (under the separation ellipsoid no two drones may be in cells of one column closer than {:.2} m — vertical separation plus twice the tracking error — which can make a crowded leg much harder; cells further apart, e.g. a pad layer at least that far below layer 0 (world.origin_m z, world.pad_height_m), or a smaller vertical separation or tracking error, lift it)",
        reach.reach_m
    )
}

/// `1 node`, `2 nodes`.
pub fn count(n: u64, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}
