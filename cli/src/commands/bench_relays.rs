//! `swarmctl bench load --via zenoh --relays K`: the load mission flown through
//! K relay processes (this binary's `relay --sitl`, each with its share of the
//! bundled vehicles) by a controller in this process, over Zenoh on loopback.
//! The runner and its table are the harness's
//! ([`swarmctl_harness::relays`]); this prints its progress and its report.
//! With `--baseline` (at most 254 drones) the same mission is first flown the
//! way `bench load` flies it — controller and vehicles in one process, no
//! relays — and both are printed side by side.

use std::process::ExitCode;
use swarmctl_harness::load::{self, LoadOptions};
use swarmctl_harness::median;
use swarmctl_harness::relays::{self, RELAY_CAPACITY};

/// Runs the benchmark and prints its table; fails when the flight through the
/// relays did not complete or broke a limit in the truth.
pub fn load(options: &LoadOptions, relays: usize, baseline: bool) -> anyhow::Result<ExitCode> {
    let vehicles = options.vehicles;
    relays::check_shares(vehicles, relays)?;
    let base = if baseline {
        if vehicles > RELAY_CAPACITY {
            anyhow::bail!(
                "--baseline flies every vehicle in one process, one MAVLink network: at most {RELAY_CAPACITY} drones"
            );
        }
        eprintln!("baseline: {vehicles} drones, controller and vehicles in one process …");
        Some(load::run_load(options)?)
    } else {
        None
    };
    eprintln!("planning {vehicles} drones ({} runs) …", options.plan_runs);
    let (mission, plan, plan_times_s) = load::plan_load(options)?;
    eprintln!(
        "planned in {:.3} s (median), makespan {} steps; flying through {relays} relays …",
        median(&plan_times_s),
        plan.makespan_steps
    );
    let swarmctl = std::env::current_exe()?;
    let run =
        relays::fly_through_relays(&mission, &plan, plan_times_s, relays, options, &swarmctl)?;
    println!("{}", relays::markdown_table(&run, &mission, base.as_ref()));
    Ok(if run.passed(&mission) {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
