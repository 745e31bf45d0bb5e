//! Benchmark: one process streams setpoints to 100 drones at 20 Hz.
//!
//! Goal: p99 inter-setpoint interval < 60 ms on the RECEIVING side and
//! < 25 % of one core in the sending process. The sender is the real `fly::fly`
//! flying `missions/paper-scale.yaml` (or `FLY_STREAM_MISSION`) with PX4-flavoured
//! vehicles, which stream from the ground hold before OFFBOARD until landing.
//! The vehicles (bundled SITL) and timestamping relays run in a child process (this
//! same binary, re-executed), so neither their CPU nor their scheduling counts
//! against the sender, and every interval is measured where a vehicle would see it.
//!
//! Run: `cargo bench --bench fly_stream`. CPU comes from
//! `swarmctl_harness::resources` (getrusage: user + system time), so this
//! benchmark is Linux-only.

#[path = "fly_stream/proxy.rs"]
mod proxy;

use anyhow::{Context, bail};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use swarmctl::fly::{self, VehicleLink};
use swarmctl::plan::{self, DiscretePlan};
use swarmctl_harness::resources;

const ROLE_ENV: &str = "FLY_STREAM_ROLE";
const MISSION_ENV: &str = "FLY_STREAM_MISSION";
const PLAN_ENV: &str = "FLY_STREAM_PLAN";
const DEFAULT_MISSION: &str = "missions/paper-scale.yaml";
const GOAL_P99_MS: f64 = 60.0;
const GOAL_CPU_SHARE: f64 = 0.25;
/// Sliding window for the busiest stretch of the flight.
const PEAK_WINDOW_S: usize = 5;

fn main() -> anyhow::Result<()> {
    if std::env::var(ROLE_ENV).as_deref() == Ok("vehicles") {
        return vehicles_main();
    }
    // `cargo bench -- <filter>` passes arguments; this benchmark has one case.
    let mission_path =
        PathBuf::from(std::env::var(MISSION_ENV).unwrap_or_else(|_| DEFAULT_MISSION.into()));
    let mission = swarmctl::import::load_any(&mission_path, None)?;
    let plan = plan::solve(&mission, &plan::PlanOptions::default())
        .with_context(|| format!("planning {}", mission.name))?
        .plan;
    let plan_file =
        std::env::temp_dir().join(format!("fly_stream_plan_{}.json", std::process::id()));
    std::fs::write(&plan_file, serde_json::to_string(&plan)?)?;

    let mut child = Command::new(std::env::current_exe()?)
        .env(ROLE_ENV, "vehicles")
        .env(MISSION_ENV, &mission_path)
        .env(PLAN_ENV, &plan_file)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .context("starting the vehicle process")?;
    let result = sender(&mission, &plan, &mut child);
    // The child exits after reporting; kill it if the sender failed before that.
    let _ = child.kill();
    let _ = child.wait();
    let _ = std::fs::remove_file(&plan_file);
    result
}

/// Flies the plan against the child's relays and reports intervals and CPU.
fn sender(
    mission: &swarmctl::mission::Mission,
    plan: &DiscretePlan,
    child: &mut std::process::Child,
) -> anyhow::Result<()> {
    let mut from_child = BufReader::new(child.stdout.take().context("child stdout")?);
    let mut to_child = child.stdin.take().context("child stdin")?;
    let ports = read_ports(&mut from_child)?;
    if ports.len() != plan.drones.len() {
        bail!("{} relays for {} drones", ports.len(), plan.drones.len());
    }
    let links = ports
        .iter()
        .enumerate()
        .map(|(i, port)| VehicleLink::mavlink(format!("udpout:127.0.0.1:{port}"), i as u8 + 1))
        .collect();
    let options = swarmctl_bundled::fly_options(links);

    // Same runtime as `swarmctl fly` (multi-threaded, one worker per core).
    let runtime = tokio::runtime::Runtime::new()?;
    let samples: Arc<Mutex<Vec<(f64, f64)>>> = Arc::default();
    let stop = Arc::new(AtomicBool::new(false));
    let sampler = spawn_cpu_sampler(samples.clone(), stop.clone());
    let (cpu0_s, wall0) = (process_cpu_s()?, Instant::now());
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let log = runtime.block_on(fly::fly(mission, plan, &options, abort_rx))?;
    let (cpu_s, wall_s) = (process_cpu_s()? - cpu0_s, wall0.elapsed().as_secs_f64());
    stop.store(true, Ordering::Relaxed);
    let _ = sampler.join();

    writeln!(to_child, "report")?;
    to_child.flush()?;
    let per_drone = read_intervals(&mut from_child)?;
    let mut all: Vec<f64> = per_drone.iter().flatten().copied().collect();
    all.sort_by(f64::total_cmp);
    let worst_drone_p99 = per_drone
        .iter()
        .map(|d| {
            let mut d = d.clone();
            d.sort_by(f64::total_cmp);
            quantile(&d, 0.99)
        })
        .fold(0.0, f64::max);

    let (p50, p99, max) = (
        quantile(&all, 0.5),
        quantile(&all, 0.99),
        quantile(&all, 1.0),
    );
    let share = cpu_s / wall_s;
    let peak = peak_share(&samples.lock().unwrap_or_else(|e| e.into_inner()));
    println!(
        "fly_stream: {} ({} drones, {} Hz, PX4 SITL in a child process)",
        mission.name,
        plan.drones.len(),
        mission.link.setpoint_rate_hz
    );
    println!(
        "  receiving side: {} intervals; median {p50:.1} ms, p99 {p99:.1} ms, max {max:.1} ms; worst drone p99 {worst_drone_p99:.1} ms (goal p99 < {GOAL_P99_MS} ms: {})",
        all.len(),
        verdict(p99 < GOAL_P99_MS)
    );
    println!(
        "  sender CPU: {cpu_s:.2} s over {wall_s:.1} s = {:.1}% of one core; busiest {PEAK_WINDOW_S} s {:.1}% (goal < {:.0}%: {})",
        100.0 * share,
        100.0 * peak,
        100.0 * GOAL_CPU_SHARE,
        verdict(share < GOAL_CPU_SHARE)
    );
    for line in log.summary.lines() {
        println!("{line}");
    }
    Ok(())
}

fn verdict(ok: bool) -> &'static str {
    if ok { "met" } else { "MISSED" }
}

/// Nearest-rank quantile of sorted values (0 for none).
fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[rank - 1]
}

/// Highest CPU share over any `PEAK_WINDOW_S` stretch of one-second samples.
fn peak_share(samples: &[(f64, f64)]) -> f64 {
    samples
        .windows(PEAK_WINDOW_S + 1)
        .filter_map(|w| {
            let (first, last) = (w.first()?, w.last()?);
            let wall_s = last.0 - first.0;
            (wall_s > 0.0).then(|| (last.1 - first.1) / wall_s)
        })
        .fold(0.0, f64::max)
}

/// Samples (wall s, CPU s) of this process once a second until `stop`.
fn spawn_cpu_sampler(
    samples: Arc<Mutex<Vec<(f64, f64)>>>,
    stop: Arc<AtomicBool>,
) -> std::thread::JoinHandle<()> {
    std::thread::spawn(move || {
        let start = Instant::now();
        while !stop.load(Ordering::Relaxed) {
            if let Some(cpu_s) = resources::process_cpu_s() {
                samples
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .push((start.elapsed().as_secs_f64(), cpu_s));
            }
            std::thread::sleep(Duration::from_secs(1));
        }
    })
}

/// User + system CPU time of this whole process (all threads), seconds.
fn process_cpu_s() -> anyhow::Result<f64> {
    resources::process_cpu_s().context("cannot read the process's CPU time (Linux only)")
}

fn read_ports(from_child: &mut impl BufRead) -> anyhow::Result<Vec<u16>> {
    let mut line = String::new();
    loop {
        line.clear();
        if from_child.read_line(&mut line)? == 0 {
            bail!("the vehicle process exited before reporting its ports");
        }
        if let Some(ports) = line.trim().strip_prefix("PORTS") {
            return ports
                .split_whitespace()
                .map(|p| p.parse().context("bad port"))
                .collect();
        }
    }
}

fn read_intervals(from_child: &mut impl BufRead) -> anyhow::Result<Vec<Vec<f64>>> {
    let mut out = Vec::new();
    let mut line = String::new();
    loop {
        line.clear();
        if from_child.read_line(&mut line)? == 0 {
            bail!("the vehicle process exited before reporting intervals");
        }
        let line = line.trim();
        if line == "END" {
            return Ok(out);
        }
        if let Some(values) = line.strip_prefix("INTERVALS_MS") {
            out.push(
                values
                    .split_whitespace()
                    .map(|v| v.parse::<f64>().context("bad interval"))
                    .collect::<anyhow::Result<_>>()?,
            );
        }
    }
}

/// Child role: the bundled SITL for the mission's drones behind timestamping relays.
fn vehicles_main() -> anyhow::Result<()> {
    let mission_path = PathBuf::from(std::env::var(MISSION_ENV)?);
    let mission = swarmctl::import::load_any(Path::new(&mission_path), None)?;
    let plan: DiscretePlan =
        serde_json::from_str(&std::fs::read_to_string(std::env::var(PLAN_ENV)?)?)?;
    let configs =
        swarmctl_bundled::vehicle_configs(&mission, &plan, swarmctl_sitl::Flavour::Px4, &[])?;
    let runtime = tokio::runtime::Runtime::new()?;
    let (swarm, _) = runtime.block_on(swarmctl_bundled::start(
        configs,
        mission.link.setpoint_rate_hz,
    ))?;
    let (ports, arrivals) = proxy::start(swarm.addresses())?;
    let ports: Vec<String> = ports.iter().map(u16::to_string).collect();
    let mut out = std::io::stdout().lock();
    writeln!(out, "PORTS {}", ports.join(" "))?;
    out.flush()?;

    // Wait for the sender to finish (a line, or EOF if it died).
    let mut line = String::new();
    std::io::stdin().read_line(&mut line)?;
    for list in arrivals.iter() {
        let times = list.lock().unwrap_or_else(|e| e.into_inner()).clone();
        let intervals: Vec<String> = times
            .windows(2)
            .map(|w| format!("{:.3}", (w[1] - w[0]).as_secs_f64() * 1e3))
            .collect();
        writeln!(out, "INTERVALS_MS {}", intervals.join(" "))?;
    }
    writeln!(out, "END")?;
    out.flush()?;
    runtime.block_on(swarm.shutdown());
    Ok(())
}
