use std::process::ExitCode;
use std::time::Duration;
use swarmctl_harness::{PlanSuite, median, peak_memory_bytes, run_plan_suite};

#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    target: Target,
}

#[derive(Debug, clap::Subcommand)]
enum Target {
    /// Time the planner on seeded random instances.
    Plan {
        /// Which instance family.
        #[arg(long, value_enum, default_value = "paper")]
        suite: PlanSuite,
        /// Number of seeds (1..=N).
        #[arg(long, default_value_t = 20)]
        seeds: u64,
        /// Per-instance deadline in seconds.
        #[arg(long, default_value_t = 10.0)]
        deadline: f64,
        /// Conflict tree alone, never the exact SAT encoding: the baseline the
        /// default is compared with.
        #[arg(long)]
        cbm_only: bool,
    },
    /// Plan the same MovingAI instances with swarmctl and with the public
    /// solvers (LaCAM3, tswap), each a whole process; print one table.
    Peers(super::bench_peers::Args),
    /// Fly the fault matrix on the bundled SITL and print the results table.
    Faults {
        /// Mission to fly (the scenarios name drones b1 and r1, r2 of it).
        #[arg(long, default_value = "missions/formation-change.yaml")]
        mission: std::path::PathBuf,
        /// Only the scenarios CI runs (those no other end-to-end test covers).
        #[arg(long)]
        reduced: bool,
        /// Only scenarios whose name contains this text.
        #[arg(long)]
        only: Option<String>,
    },
    /// Fly missions on the bundled SITL and time plan execution against the
    /// schedule: median ratio, lateness and gating waits, with separation and
    /// speed measured from the simulator's truth.
    Timing {
        /// Missions to fly (default: every example with at most 100 drones).
        #[arg(value_name = "MISSION")]
        missions: Vec<std::path::PathBuf>,
        /// Flights per mission (the table gives the median).
        #[arg(long, default_value_t = 3)]
        runs: usize,
    },
    /// Fly missions back to back in one process; report memory and open files.
    Soak {
        #[arg(long, default_value = "missions/formation-change.yaml")]
        mission: std::path::PathBuf,
        /// How many flights.
        #[arg(long, default_value_t = 10)]
        flights: usize,
    },
    /// Plan and fly an N-drone mission on N bundled SITL vehicles in one process;
    /// report planning time, CPU, setpoint timing, link, separation and memory.
    Load {
        /// Drones, one SITL vehicle each (1–254 in one process; up to 5000
        /// through relays).
        #[arg(long, default_value_t = 200)]
        vehicles: usize,
        /// Seeds the generated mission and the planner.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Planning runs (the table gives the median time).
        #[arg(long, default_value_t = 3)]
        plan_runs: usize,
        /// Give up on the flight after this many seconds.
        #[arg(long, default_value_t = 600.0)]
        limit: f64,
        /// Also write the generated mission here (YAML), for `swarmctl check`.
        #[arg(long)]
        mission_out: Option<std::path::PathBuf>,
        /// Separate the drones by an ellipsoid this many metres high (0.25 m
        /// across) instead of the 0.25 m sphere; separations are judged scaled.
        #[arg(long, value_name = "METRES")]
        vertical_separation: Option<f64>,
        /// `mavlink`: controller and vehicles in this process (at most 254).
        /// `zenoh`: the vehicles behind `--relays` relay processes (254 each),
        /// the controller here, over Zenoh on loopback.
        #[arg(long, value_parser = ["mavlink", "zenoh"], default_value = "mavlink")]
        via: String,
        /// With --via zenoh: how many relay processes share the vehicles.
        #[arg(long, default_value_t = 4)]
        relays: usize,
        /// With --via zenoh: first fly the same mission in one process, no
        /// relays, and print both side by side (at most 254 drones).
        #[arg(long)]
        baseline: bool,
    },
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    match args.target {
        Target::Plan {
            suite,
            seeds,
            deadline,
            cbm_only,
        } => plan(suite, seeds, deadline, cbm_only),
        Target::Peers(peers) => super::bench_peers::run(peers),
        Target::Faults {
            mission,
            reduced,
            only,
        } => super::bench_flight::faults(&mission, reduced, only.as_deref()),
        Target::Soak { mission, flights } => super::bench_flight::soak(&mission, flights),
        Target::Timing { missions, runs } => super::bench_flight::timing(&missions, runs),
        Target::Load {
            vehicles,
            seed,
            plan_runs,
            limit,
            mission_out,
            vertical_separation,
            via,
            relays,
            baseline,
        } => {
            let mut options = swarmctl_harness::load::LoadOptions::new(vehicles, seed);
            options.plan_runs = plan_runs;
            options.limit = Duration::try_from_secs_f64(limit)?;
            options.vertical_separation_m = vertical_separation;
            if via == "zenoh" {
                return super::bench_relays::load(&options, relays, baseline);
            }
            if vehicles > 254 {
                anyhow::bail!(
                    "one process flies at most 254 vehicles (MAVLink system ids 1–254): fly {vehicles} through relays with --via zenoh --relays {}",
                    vehicles.div_ceil(254)
                );
            }
            load(&options, mission_out.as_deref())
        }
    }
}

fn load(
    options: &swarmctl_harness::load::LoadOptions,
    mission_out: Option<&std::path::Path>,
) -> anyhow::Result<ExitCode> {
    use swarmctl_harness::load;
    let (vehicles, plan_runs) = (options.vehicles, options.plan_runs);
    if let Some(path) = mission_out {
        let file = load::load_mission(vehicles, options.seed, options.vertical_separation_m)?;
        std::fs::write(path, swarmctl::mission::to_yaml(&file))?;
        eprintln!("mission written to {}", path.display());
    }
    eprintln!("planning {vehicles} drones ({plan_runs} runs) …");
    let (mission, plan, times) = load::plan_load(options)?;
    eprintln!(
        "planned in {:.3} s (median), makespan {} steps; flying on {vehicles} bundled SITL vehicles …",
        median(&times),
        plan.makespan_steps
    );
    let report = load::fly_load(&mission, &plan, times, options)?;
    eprintln!("{}", report.observed);
    if !report.passed()
        && let Some(log) = &report.log
    {
        for e in &log.events {
            eprintln!(
                "{:7.1} s {} {}",
                e.t_s,
                e.drone.as_deref().unwrap_or("-"),
                e.message
            );
        }
    }
    println!("{}", load::markdown_table(std::slice::from_ref(&report)));
    Ok(if report.passed() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// Per leg name, over all solved instances: how often the leg's makespan met its
/// lower bound, and its median makespan against the median bound.
fn print_legs(legs: &[Vec<(String, u32, u32)>]) {
    let mut names: Vec<&str> = Vec::new();
    for (name, _, _) in legs.iter().flatten() {
        if !names.contains(&name.as_str()) {
            names.push(name);
        }
    }
    for name in names {
        let of: Vec<(u32, u32)> = legs
            .iter()
            .flatten()
            .filter(|(n, _, _)| n == name)
            .map(|&(_, m, lb)| (m, lb))
            .collect();
        let at_bound = of.iter().filter(|(m, lb)| m == lb).count();
        let makespans: Vec<f64> = of.iter().map(|&(m, _)| f64::from(m)).collect();
        let bounds: Vec<f64> = of.iter().map(|&(_, lb)| f64::from(lb)).collect();
        println!(
            "  leg {name:<10}  {at_bound}/{} at the lower bound; median makespan {} (bound {})",
            of.len(),
            median(&makespans),
            median(&bounds)
        );
    }
}

fn plan(suite: PlanSuite, seeds: u64, deadline: f64, cbm_only: bool) -> anyhow::Result<ExitCode> {
    let deadline = Duration::try_from_secs_f64(deadline)?;
    let o = suite.options(1);
    let exact_after = if cbm_only {
        None
    } else {
        swarmctl::plan::PlanOptions::default().exact_after_ct_nodes
    };
    println!(
        "suite {suite:?}: {}×{}×{} voxels, {} obstacles, {} drones in {} groups, seeds 1..={seeds}, deadline {deadline:?}, {}",
        o.dimensions[0],
        o.dimensions[1],
        o.dimensions[2],
        o.obstacles,
        o.drones,
        o.groups,
        exact_after.map_or("conflict tree alone".to_string(), |n| format!(
            "exact SAT encoding after {n} conflict-tree nodes"
        ))
    );
    let report = run_plan_suite(
        suite,
        seeds,
        deadline,
        exact_after,
        |seed, result| match result {
            Ok((time_s, makespan, lb, nodes)) => {
                println!(
                    "  seed {seed:>3}: {time_s:>8.3} s  makespan {makespan:>3} (lower bound {lb:>3})  {nodes:>6} CT nodes"
                )
            }
            Err(e) => println!("  seed {seed:>3}: FAILED: {e}"),
        },
    );
    let at_bound = report.makespans.iter().filter(|(m, lb)| m == lb).count();
    let excess: u32 = report.makespans.iter().map(|(m, lb)| m - lb).sum();
    println!("solved          {}/{}", report.solved, report.instances);
    if !report.times_s.is_empty() {
        let max = report.times_s.iter().copied().fold(0.0, f64::max);
        println!("median time     {:.4} s", median(&report.times_s));
        println!("max time        {max:.4} s");
        println!(
            "makespan        {at_bound}/{} at the lower bound; {excess} steps above it in total",
            report.solved
        );
        let nodes: Vec<f64> = report.ct_nodes.iter().map(|&n| n as f64).collect();
        println!("median CT nodes {}", median(&nodes));
        print_legs(&report.legs);
    }
    if let Some(bytes) = peak_memory_bytes() {
        println!(
            "peak memory     {:.1} MiB",
            bytes as f64 / (1024.0 * 1024.0)
        );
    }
    Ok(if report.solved == report.instances {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
