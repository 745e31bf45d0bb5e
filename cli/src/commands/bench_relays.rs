//! `swarmctl bench load --via zenoh --relays K`: the load mission flown through
//! K relay processes (this binary's `relay --sitl`, each with its share of the
//! bundled vehicles) by a controller in this process, over Zenoh on loopback.
//!
//! Measured as `bench load` measures, each where it happens: setpoint intervals
//! where the vehicles receive them (each relay reports its vehicles'), separation
//! from telemetry (the flight log) and from the simulators' truth (the relays
//! publish it; a [`TruthWatch`] here compares the whole swarm), CPU time and peak
//! memory per process. With `--baseline` (at most 254 drones) the same mission
//! is first flown the way `bench load` flies it — controller and vehicles in one
//! process, no relays — and both are printed side by side.

use anyhow::Context;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, Stdio};
use std::time::{Duration, Instant};
use swarmctl::fly::{self, FlightLog};
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;
use swarmctl_harness::load::{self, LoadOptions, LoadReport};
use swarmctl_harness::{median, resources};
use swarmctl_relay::truth::{TruthReport, TruthWatch};
use swarmctl_relay::{KeySpace, RelayLinks, Role, ZenohEndpoints};

/// A relay's MAVLink network holds at most this many vehicles (system ids 1–254).
const RELAY_CAPACITY: usize = 254;

/// What a relay wrote to its `--report` file.
#[derive(Debug, Default, serde::Deserialize)]
struct RelayReport {
    relay: String,
    drones: usize,
    setpoint_interval_ms: Option<Intervals>,
    cpu_s: Option<f64>,
    peak_rss_bytes: Option<u64>,
}

#[derive(Debug, Default, serde::Deserialize)]
struct Intervals {
    count: u64,
    p50_ms: f64,
    p99_ms: f64,
    max_ms: f64,
}

/// The flight through relays, measured.
struct RelayRun {
    drones: usize,
    relays: Vec<RelayReport>,
    log: Option<FlightLog>,
    truth: TruthReport,
    plan_times_s: Vec<f64>,
    controller_cpu_s: f64,
    controller_peak_rss_bytes: u64,
    wall_s: f64,
}

/// Runs the benchmark and prints its table; fails when the flight through the
/// relays did not complete or broke a limit in the truth.
pub fn load(options: &LoadOptions, relays: usize, baseline: bool) -> anyhow::Result<ExitCode> {
    let vehicles = options.vehicles;
    if relays == 0 || vehicles.div_ceil(relays) > RELAY_CAPACITY {
        anyhow::bail!(
            "{vehicles} drones in {relays} relays is more than {RELAY_CAPACITY} per relay (one MAVLink network each): give --relays {} or more",
            vehicles.div_ceil(RELAY_CAPACITY)
        );
    }
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
    let run = fly_through_relays(&mission, &plan, plan_times_s, relays, options)?;
    println!("{}", table(&run, &mission, base.as_ref()));
    let ok = run.log.as_ref().is_some_and(|l| {
        let s = &l.summary;
        s.completed && s.safety_held && s.speed_held
    }) && truth_held(&run.truth, &mission);
    Ok(if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// The truth kept the separation (scaled, under an ellipsoid) and the speed limit.
fn truth_held(truth: &TruthReport, mission: &Mission) -> bool {
    let l = &mission.limits;
    let separated = match truth.min_scaled_separation {
        Some(scaled) => scaled >= 1.0,
        None => truth.min_separation_m >= l.safety_distance_m,
    };
    separated && truth.top_speed_mps <= l.max_speed_mps * 1.05
}

/// Starts the relays, flies, stops the relays and reads their reports.
fn fly_through_relays(
    mission: &Mission,
    plan: &DiscretePlan,
    plan_times_s: Vec<f64>,
    relays: usize,
    options: &LoadOptions,
) -> anyhow::Result<RelayRun> {
    let dir = std::env::temp_dir().join(format!("swarmctl-bench-relays-{}", std::process::id()));
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mission_path = dir.join("mission.yaml");
    let file = load::load_mission(
        options.vehicles,
        options.seed,
        options.vertical_separation_m,
    )?;
    std::fs::write(&mission_path, swarmctl::mission::to_yaml(&file))?;
    let port = free_port()?;
    let ids: Vec<String> = plan.drones.iter().map(|d| d.id.clone()).collect();
    let shares: Vec<&[String]> = ids.chunks(ids.len().div_ceil(relays)).collect();
    let mut children = Vec::new();
    for (k, share) in shares.iter().enumerate() {
        children.push(RelayProcess::start(
            &mission_path,
            &dir,
            k,
            share,
            port,
            options,
        )?);
    }
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    let cpu_before_s = resources::process_cpu_s().unwrap_or(0.0);
    let started = Instant::now();
    let flown = runtime.block_on(fly_watched(mission, plan, &ids, port, options));
    let wall_s = started.elapsed().as_secs_f64();
    let controller_cpu_s = resources::process_cpu_s().unwrap_or(0.0) - cpu_before_s;
    let mut reports = Vec::new();
    for child in children {
        reports.push(child.stop()?);
    }
    let _ = std::fs::remove_dir_all(&dir);
    let (log, truth) = flown?;
    Ok(RelayRun {
        drones: ids.len(),
        relays: reports,
        log,
        truth,
        plan_times_s,
        controller_cpu_s,
        controller_peak_rss_bytes: resources::peak_rss_bytes().unwrap_or(0),
        wall_s,
    })
}

/// The controller: waits for the relays, flies with the truth watched.
async fn fly_watched(
    mission: &Mission,
    plan: &DiscretePlan,
    ids: &[String],
    port: u16,
    options: &LoadOptions,
) -> anyhow::Result<(Option<FlightLog>, TruthReport)> {
    let zenoh = ZenohEndpoints {
        role: Role::Router,
        listen: vec![format!("tcp/127.0.0.1:{port}")],
        connect: Vec::new(),
    };
    let links = RelayLinks::connect(
        &zenoh,
        &mission.name,
        ids,
        Duration::from_secs(120),
        |_, _| {},
    )
    .await?;
    let l = &mission.limits;
    let ellipsoid = l.is_ellipsoid().then(|| l.separation());
    let truth = TruthWatch::start(
        links.session(),
        &KeySpace::new(&mission.name),
        ellipsoid,
        10.0,
    )
    .await?;
    let mut fly_options = fly::FlyOptions::new(links.vehicle_links());
    fly_options.ready_timeout = Duration::from_secs(60);
    let (_abort, abort_rx) = tokio::sync::watch::channel(false);
    let flown = tokio::time::timeout(
        options.limit,
        fly::fly(mission, plan, &fly_options, abort_rx),
    )
    .await;
    let report = truth.report();
    drop(truth);
    links.close().await;
    let log = match flown {
        Ok(result) => Some(result?),
        Err(_) => None,
    };
    Ok((log, report))
}

/// One `swarmctl relay --sitl` child.
struct RelayProcess {
    child: Child,
    report: PathBuf,
}

impl RelayProcess {
    fn start(
        mission: &Path,
        dir: &Path,
        k: usize,
        drones: &[String],
        port: u16,
        options: &LoadOptions,
    ) -> anyhow::Result<RelayProcess> {
        let report = dir.join(format!("relay-{k}.json"));
        let autopilot = match options.flavour {
            swarmctl_sitl::Flavour::ArduPilot => "ardupilot",
            swarmctl_sitl::Flavour::Px4 => "px4",
        };
        let child = Command::new(std::env::current_exe()?)
            .arg("relay")
            .arg(mission)
            .args([
                "--name",
                &format!("r{}", k + 1),
                "--sitl",
                "--autopilot",
                autopilot,
            ])
            .args(["--drones", &drones.join(",")])
            .args(["--connect", &format!("tcp/127.0.0.1:{port}")])
            .arg("--report")
            .arg(&report)
            .stdout(Stdio::null())
            .stderr(Stdio::inherit())
            .spawn()
            .context("starting a relay process")?;
        Ok(RelayProcess { child, report })
    }

    /// SIGTERM, wait (bounded), and read what the relay reported.
    fn stop(mut self) -> anyhow::Result<RelayReport> {
        // SAFETY: kill(2) on our own child's pid.
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM);
        }
        let deadline = Instant::now() + Duration::from_secs(30);
        while self.child.try_wait()?.is_none() {
            if Instant::now() > deadline {
                let _ = self.child.kill();
                let _ = self.child.wait();
                anyhow::bail!("a relay did not stop within 30 s of SIGTERM");
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let text = std::fs::read_to_string(&self.report)
            .with_context(|| format!("the relay wrote no report to {}", self.report.display()))?;
        Ok(serde_json::from_str(&text)?)
    }
}

impl Drop for RelayProcess {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

fn free_port() -> anyhow::Result<u16> {
    let listener = std::net::TcpListener::bind("127.0.0.1:0")?;
    Ok(listener.local_addr()?.port())
}

/// Rows of the table: a metric, its value through relays, and the baseline's.
#[derive(Default)]
struct Table {
    rows: Vec<(String, String, String)>,
}

impl Table {
    fn row(&mut self, name: &str, relayed: String, baseline: Option<String>) {
        self.rows.push((
            name.to_string(),
            relayed,
            baseline.unwrap_or_else(|| "—".into()),
        ));
    }
}

/// The table: the run through relays, and the baseline beside it when flown.
fn table(run: &RelayRun, mission: &Mission, base: Option<&LoadReport>) -> String {
    let mut t = Table::default();
    flight_rows(&mut t, run, mission, base);
    resource_rows(&mut t, run, base);
    let mut out = String::from(
        "| Metric | through relays (Zenoh) | one process (baseline) |\n|---|---|---|\n",
    );
    for (name, relayed, baseline) in t.rows {
        out.push_str(&format!("| {name} | {relayed} | {baseline} |\n"));
    }
    out
}

/// Completion, timing, setpoint intervals, separation and speed.
fn flight_rows(t: &mut Table, run: &RelayRun, mission: &Mission, base: Option<&LoadReport>) {
    let mut row =
        |name: &str, relayed: String, baseline: Option<String>| t.row(name, relayed, baseline);
    let summary = run.log.as_ref().map(|l| &l.summary);
    row(
        "planning (median)",
        format!("{:.2} s", median(&run.plan_times_s)),
        base.map(|b| format!("{:.2} s", median(&b.plan_times_s))),
    );
    row(
        "completed",
        summary.map_or("no (time limit)".into(), |s| yes(s.completed)),
        base.map(|b| yes(b.completed())),
    );
    row(
        "plan execution vs planned",
        summary.map_or("—".into(), |s| {
            format!(
                "{:.1} s vs {:.1} s",
                s.executed_makespan_s.unwrap_or(f64::NAN),
                s.planned_makespan_s
            )
        }),
        base.and_then(|b| b.log.as_ref()).map(|l| {
            format!(
                "{:.1} s vs {:.1} s",
                l.summary.executed_makespan_s.unwrap_or(f64::NAN),
                l.summary.planned_makespan_s
            )
        }),
    );
    let intervals: Vec<&Intervals> = run
        .relays
        .iter()
        .filter_map(|r| r.setpoint_interval_ms.as_ref())
        .collect();
    let worst = |f: fn(&Intervals) -> f64| intervals.iter().map(|i| f(i)).fold(0.0, f64::max);
    row(
        "setpoint interval at the vehicles p50 / p99 / max (worst relay)",
        format!(
            "{:.1} / {:.1} / {:.1} ms ({} setpoints)",
            worst(|i| i.p50_ms),
            worst(|i| i.p99_ms),
            worst(|i| i.max_ms),
            intervals.iter().map(|i| i.count).sum::<u64>()
        ),
        base.map(|b| {
            format!(
                "{:.1} / {:.1} / {:.1} ms ({} setpoints)",
                b.setpoints.quantile_s(0.5) * 1e3,
                b.setpoints.quantile_s(0.99) * 1e3,
                b.setpoints.max_s() * 1e3,
                b.setpoints.count()
            )
        }),
    );
    row(
        "min separation telemetry / truth",
        format!(
            "{} / {:.3} m (limit {:.2} m)",
            summary.map_or("—".into(), |s| format!("{:.3}", s.min_separation_m)),
            run.truth.min_separation_m,
            mission.limits.safety_distance_m
        ),
        base.map(|b| {
            format!(
                "{:.3} / {:.3} m",
                b.min_separation_telemetry_m, b.min_separation_truth_m
            )
        }),
    );
    if let Some(scaled) = run.truth.min_scaled_separation {
        row(
            "min scaled separation telemetry / truth (separated at 1)",
            format!(
                "{} / {scaled:.3}",
                summary
                    .and_then(|s| s.min_scaled_separation)
                    .map_or("—".into(), |v| format!("{v:.3}"))
            ),
            base.and_then(|b| b.scaled_telemetry_truth)
                .map(|(t, u)| format!("{t:.3} / {u:.3}")),
        );
    }
    row(
        "top speed telemetry / truth",
        format!(
            "{} / {:.2} m/s (limit {:.2} + 5 %)",
            summary.map_or("—".into(), |s| format!("{:.2}", s.max_speed_mps)),
            run.truth.top_speed_mps,
            mission.limits.max_speed_mps
        ),
        None,
    );
}

/// Processes, their CPU time and peak memory.
fn resource_rows(t: &mut Table, run: &RelayRun, base: Option<&LoadReport>) {
    let mut row =
        |name: &str, relayed: String, baseline: Option<String>| t.row(name, relayed, baseline);
    row(
        "drones / processes",
        format!(
            "{} / 1 controller + {} relays",
            run.drones,
            run.relays.len()
        ),
        base.map(|b| format!("{} / 1", b.vehicles)),
    );
    row(
        "CPU, controller (% of one core over the flight)",
        format!(
            "{:.0} % ({:.1} s in {:.0} s)",
            100.0 * run.controller_cpu_s / run.wall_s.max(1e-9),
            run.controller_cpu_s,
            run.wall_s
        ),
        base.map(|b| {
            format!(
                "{:.0} % (controller threads)",
                b.cpu.percent(b.cpu.controller_s())
            )
        }),
    );
    for r in &run.relays {
        row(
            &format!(
                "CPU, relay {} ({} vehicles; process lifetime)",
                r.relay, r.drones
            ),
            r.cpu_s.map_or("—".into(), |c| format!("{c:.1} s")),
            None,
        );
    }
    row(
        "peak memory, controller / relays",
        format!(
            "{} / {}",
            mib(run.controller_peak_rss_bytes),
            run.relays
                .iter()
                .map(|r| mib(r.peak_rss_bytes.unwrap_or(0)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        base.map(|b| mib(b.peak_rss_bytes)),
    );
}

fn yes(b: bool) -> String {
    if b { "yes".into() } else { "no".into() }
}

fn mib(bytes: u64) -> String {
    format!("{:.0} MiB", bytes as f64 / (1024.0 * 1024.0))
}
