//! `swarmctl bench faults`, `swarmctl bench soak` and `swarmctl bench timing`:
//! whole flights on the bundled SITL, for reliability and timekeeping rather
//! than speed.

use anyhow::Context;
use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;
use swarmctl::mission::Mission;
use swarmctl::plan::{self, DiscretePlan};
use swarmctl_harness::fault_matrix::{self, Expect, Scenario};
use swarmctl_harness::{median, process_resources};
use swarmctl_sitl::Flavour;

/// Generous: the longest scenario (lost drone) takes about a minute.
const SCENARIO_LIMIT: Duration = Duration::from_secs(240);

fn load(mission: &Path) -> anyhow::Result<(Mission, DiscretePlan)> {
    let mission = swarmctl::mission::load(mission)?;
    let plan = plan::solve(&mission, &plan::PlanOptions::default())
        .with_context(|| format!("planning {}", mission.name))?
        .plan;
    Ok((mission, plan))
}

pub fn faults(mission: &Path, reduced: bool, only: Option<&str>) -> anyhow::Result<ExitCode> {
    let (mission, plan) = load(mission)?;
    let scenarios: Vec<Scenario> = fault_matrix::scenarios(reduced)
        .into_iter()
        .filter(|s| only.is_none_or(|text| s.name.contains(text)))
        .collect();
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    let mut reports = Vec::new();
    for (i, scenario) in scenarios.iter().enumerate() {
        eprintln!(
            "[{}/{}] {} ({})",
            i + 1,
            scenarios.len(),
            scenario.name,
            scenario.faults.join(" ")
        );
        let report = runtime.block_on(fault_matrix::run_scenario(
            &mission,
            &plan,
            scenario,
            SCENARIO_LIMIT,
        ))?;
        eprintln!(
            "      {} in {:.0} s: {}",
            if report.passed { "pass" } else { "FAIL" },
            report.duration_s,
            report.observed
        );
        for f in &report.failures {
            eprintln!("      - {f}");
        }
        reports.push(report);
    }
    println!("{}", fault_matrix::markdown_table(&reports));
    let passed = reports.iter().filter(|r| r.passed).count();
    println!("{passed}/{} scenarios passed", reports.len());
    Ok(if passed == reports.len() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

pub fn soak(mission: &Path, flights: usize) -> anyhow::Result<ExitCode> {
    let (mission, plan) = load(mission)?;
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    let scenario = Scenario {
        name: "soak",
        faults: Vec::new(),
        flavour: Flavour::Px4,
        expect: Expect::Completes,
        replan: swarmctl::fly::ReplanOptions::default(),
    };
    println!("| Flight | Result | Duration | RSS after | Open fds after |\n|---|---|---|---|---|");
    let mut rss = Vec::new();
    let mut fds = Vec::new();
    let mut all_passed = true;
    for n in 1..=flights {
        let report = runtime.block_on(fault_matrix::run_scenario(
            &mission,
            &plan,
            &scenario,
            SCENARIO_LIMIT,
        ))?;
        let usage = process_resources();
        all_passed &= report.passed;
        println!(
            "| {n} | {} | {:.1} s | {:.1} MiB | {} |",
            if report.passed { "pass" } else { "FAIL" },
            report.duration_s,
            usage.rss_bytes as f64 / 1048576.0,
            usage.open_fds
        );
        rss.push(usage.rss_bytes as f64 / 1048576.0);
        fds.push(usage.open_fds as f64);
    }
    if let (Some(first), Some(last)) = (rss.first(), rss.last()) {
        println!(
            "RSS first {first:.1} MiB, last {last:.1} MiB, median {:.1} MiB; open fds first {}, last {}",
            median(&rss),
            fds[0],
            fds[fds.len() - 1]
        );
    }
    Ok(if all_passed {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// The examples `bench timing` flies by default: every mission in `missions/`
/// with at most this many drones.
const TIMING_MAX_DRONES: usize = 100;

/// Generous: the longest example flight takes about two minutes.
const TIMING_LIMIT: Duration = Duration::from_secs(600);

pub fn timing(missions: &[std::path::PathBuf], runs: usize) -> anyhow::Result<ExitCode> {
    anyhow::ensure!(runs > 0, "--runs must be at least 1");
    let mut loaded = Vec::new();
    if missions.is_empty() {
        let mut files: Vec<_> = std::fs::read_dir("missions")
            .context("reading missions/ (run from the repository, or name the missions)")?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "yaml"))
            .collect();
        files.sort();
        for file in files {
            let mission = swarmctl::mission::load(&file)?;
            let bundled = mission.drones().all(|(_, d)| d.endpoint.is_none())
                && mission.link.relays.is_empty();
            if mission.drone_count() <= TIMING_MAX_DRONES && bundled {
                loaded.push(mission);
            }
        }
    } else {
        for file in missions {
            loaded.push(swarmctl::mission::load(file)?);
        }
    }
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    let mut reports = Vec::new();
    for (i, mission) in loaded.iter().enumerate() {
        eprintln!(
            "[{}/{}] {} ({} drones, {runs} flights)",
            i + 1,
            loaded.len(),
            mission.name,
            mission.drone_count()
        );
        let report = runtime.block_on(swarmctl_harness::timing::time_mission(
            mission,
            runs,
            TIMING_LIMIT,
        ))?;
        if let Some(ratio) = report.ratio() {
            eprintln!(
                "      planned {:.1} s, executed {:.1} s median: {ratio:.3}×",
                report.planned_s,
                report.median_executed_s().unwrap_or(f64::NAN)
            );
        }
        reports.push(report);
    }
    println!("{}", swarmctl_harness::timing::markdown_table(&reports));
    let bad = reports.iter().filter(|r| !r.safe_and_complete()).count();
    Ok(if bad == 0 {
        ExitCode::SUCCESS
    } else {
        eprintln!("{bad} missions not safe and complete in every flight");
        ExitCode::FAILURE
    })
}
