//! Benchmark: what live Rerun recording costs a real flight.
//!
//! Goal: recording a 100-drone flight at 20 Hz costs under 5% of the flight's CPU.
//! The real `fly::fly` flies `missions/paper-scale.yaml` (or `FLY_RECORD_MISSION`)
//! against PX4-flavoured bundled SITL vehicles running in a child process, so only
//! the controller's CPU is measured. Flights alternate without and with live
//! recording (`swarmctl_cli::record::LiveFlight` writing an `.rrd` file, exactly as
//! `swarmctl fly` does); `FLY_RECORD_RUNS` pairs (default 3). Every flight runs in
//! a fresh controller process, as `swarmctl fly` does: rerun 0.36.3 leaks a
//! batcher thread per recording (its blueprint's memory stream holds itself), and
//! in one long-lived process those would pile up and tick during later flights.
//! (This binary re-executes itself for both roles.)
//!
//! Two measures of the recording's share, each a median over the pairs:
//!
//! - paired: (process CPU with − process CPU without) / process CPU without, from
//!   getrusage(RUSAGE_SELF) (`swarmctl_harness::resources`) around the flight (and, with recording, around
//!   starting and finishing the recorder too). Includes the observer calls on the
//!   executor's threads, but two flights differ by a few percent on their own.
//! - attributed: within the recorded flight, the CPU of the threads that only
//!   record (the recorder thread, rerun's batcher and file writer, read from
//!   /proc/self/task/* every 200 ms) plus the main thread's CPU while
//!   starting and finishing the recorder, over the rest of the process's CPU.
//!
//! Run: `cargo bench --bench fly_record` (Linux only). `FLY_RECORD_FLUSH_S`,
//! `FLY_RECORD_ROW_S` and `FLY_RECORD_SERIES_S` override the recorder's periods.

use anyhow::{Context, bail};
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use swarmctl::fly::{self, FlyOptions, VehicleLink};
use swarmctl::mission::Mission;
use swarmctl::plan::{self, DiscretePlan};
use swarmctl_cli::record::{LiveFlight, RecorderOptions, Sink};
use swarmctl_harness::{median, resources};

const ROLE_ENV: &str = "FLY_RECORD_ROLE";
const MISSION_ENV: &str = "FLY_RECORD_MISSION";
const PLAN_ENV: &str = "FLY_RECORD_PLAN";
const RRD_ENV: &str = "FLY_RECORD_RRD";
const DEFAULT_MISSION: &str = "missions/paper-scale.yaml";
const GOAL_SHARE: f64 = 0.05;
/// Threads that exist only to record (names as the kernel keeps them, 15 bytes).
const RECORDING_THREADS: [&str; 5] = [
    "rerun-recorder",
    "RecordingStream",
    "ChunkBatcher::c",
    "file_writer",
    "message_proxy_c",
];

fn main() -> anyhow::Result<()> {
    match std::env::var(ROLE_ENV).as_deref() {
        Ok("vehicles") => return vehicles_main(),
        Ok("controller") => return controller_main(),
        _ => {}
    }
    let mission_path =
        PathBuf::from(std::env::var(MISSION_ENV).unwrap_or_else(|_| DEFAULT_MISSION.into()));
    let mission = swarmctl::import::load_any(&mission_path, None)?;
    let plan = plan::solve(&mission, &plan::PlanOptions::default())
        .with_context(|| format!("planning {}", mission.name))?
        .plan;
    let dir = tempfile::tempdir()?;
    let plan_file = dir.path().join("plan.json");
    std::fs::write(&plan_file, serde_json::to_string(&plan)?)?;
    let runs: usize = env_parse("FLY_RECORD_RUNS").unwrap_or(3);
    let options = recorder_options();
    println!(
        "fly_record: {} ({} drones, {} Hz), {runs} pairs of flights; recorder: flush {} s, rows {} s, series {} s",
        mission.name,
        plan.drones.len(),
        mission.link.setpoint_rate_hz,
        options.flush_period_s,
        options.row_period_s,
        options.series_period_s
    );
    let mut pairs = Vec::new();
    for i in 0..runs {
        // Alternate which of the pair flies first, so drift in the machine's load
        // does not favour one side.
        let order = if i % 2 == 0 {
            [false, true]
        } else {
            [true, false]
        };
        let mut pair = [None, None];
        for record in order {
            let rrd = dir.path().join(format!("flight-{i}.rrd"));
            let run = controller(&mission_path, &plan_file, record.then_some(&rrd))?;
            println!("  pair {i} {}", run.describe());
            pair[usize::from(record)] = Some(run);
        }
        if let [Some(without), Some(with)] = pair {
            pairs.push((without, with));
        }
    }
    report(&pairs);
    Ok(())
}

fn env_parse<T: std::str::FromStr>(name: &str) -> Option<T> {
    std::env::var(name).ok().and_then(|s| s.parse().ok())
}

fn recorder_options() -> RecorderOptions {
    // What `swarmctl fly` uses for its default sink, a file beside the log.
    let mut options = RecorderOptions::for_sink(&Sink::File(PathBuf::new()));
    if let Some(s) = env_parse("FLY_RECORD_FLUSH_S") {
        options.flush_period_s = s;
    }
    if let Some(s) = env_parse("FLY_RECORD_ROW_S") {
        options.row_period_s = s;
    }
    if let Some(s) = env_parse("FLY_RECORD_SERIES_S") {
        options.series_period_s = s;
    }
    options
}

/// Runs one flight in a fresh controller process and reads back its measurements.
fn controller(mission_path: &Path, plan_file: &Path, rrd: Option<&PathBuf>) -> anyhow::Result<Run> {
    let mut cmd = Command::new(std::env::current_exe()?);
    cmd.env(ROLE_ENV, "controller")
        .env(MISSION_ENV, mission_path)
        .env(PLAN_ENV, plan_file)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit());
    if let Some(rrd) = rrd {
        cmd.env(RRD_ENV, rrd);
    }
    let out = cmd.output().context("running the controller process")?;
    if !out.status.success() {
        bail!("the controller process failed ({})", out.status);
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix("RESULT "))
        .context("the controller process reported nothing")?;
    Ok(serde_json::from_str(line)?)
}

/// Controller role: flies once (recording if `FLY_RECORD_RRD` is set) and prints
/// its measurements as one `RESULT` line of JSON.
fn controller_main() -> anyhow::Result<()> {
    let mission_path = PathBuf::from(std::env::var(MISSION_ENV)?);
    let plan_file = PathBuf::from(std::env::var(PLAN_ENV)?);
    let mission = swarmctl::import::load_any(&mission_path, None)?;
    let plan: DiscretePlan = serde_json::from_str(&std::fs::read_to_string(&plan_file)?)?;
    let rrd = std::env::var_os(RRD_ENV).map(PathBuf::from);
    let options = recorder_options();
    let run = fly_once(
        &mission_path,
        &plan_file,
        &mission,
        &plan,
        rrd.as_ref().map(|r| (r, &options)),
    )?;
    println!("RESULT {}", serde_json::to_string(&run)?);
    Ok(())
}

/// One flight's measurements.
#[derive(serde::Serialize, serde::Deserialize)]
struct Run {
    recorded: bool,
    wall_s: f64,
    /// Process CPU over the flight (and the recorder's start and finish).
    process_cpu_s: f64,
    /// CPU of the recording-only threads plus the main thread's recorder start/finish.
    recording_cpu_s: f64,
    /// Where `recording_cpu_s` went: the main thread starting and finishing the
    /// recorder, then each recording thread by name.
    breakdown: Vec<(String, f64)>,
    samples_logged: u64,
    samples_dropped: u64,
    rrd_mb: f64,
    completed: bool,
}

impl Run {
    fn describe(&self) -> String {
        let mut s = format!(
            "{:<14} {:5.1} s wall, process CPU {:.3} s ({:.1}% of a core)",
            if self.recorded {
                "with recording"
            } else {
                "without"
            },
            self.wall_s,
            self.process_cpu_s,
            100.0 * self.process_cpu_s / self.wall_s
        );
        if self.recorded {
            s += &format!(
                "; recording {:.3} s; {} samples, {} dropped; {:.1} MB\n      recording CPU:",
                self.recording_cpu_s, self.samples_logged, self.samples_dropped, self.rrd_mb
            );
            for (what, cpu_s) in &self.breakdown {
                s += &format!(" {what} {cpu_s:.3} s,");
            }
            s.pop();
        }
        if !self.completed {
            s += " (flight NOT completed)";
        }
        s
    }
}

/// The median of what `pairs` give.
fn median_of(values: impl Iterator<Item = f64>) -> f64 {
    median(&values.collect::<Vec<_>>())
}

fn report(pairs: &[(Run, Run)]) {
    let flight = median_of(pairs.iter().map(|(w, _)| w.process_cpu_s));
    let with = median_of(pairs.iter().map(|(_, r)| r.process_cpu_s));
    let paired = median_of(
        pairs
            .iter()
            .map(|(w, r)| (r.process_cpu_s - w.process_cpu_s) / w.process_cpu_s),
    );
    let attributed = median_of(
        pairs
            .iter()
            .map(|(_, r)| r.recording_cpu_s / (r.process_cpu_s - r.recording_cpu_s)),
    );
    let recording = median_of(pairs.iter().map(|(_, r)| r.recording_cpu_s));
    println!(
        "  flight CPU (median) without recording {flight:.3} s, with {with:.3} s; recording threads {recording:.3} s"
    );
    println!(
        "  recording / flight CPU, median of {} pairs: attributed {:.2}%, paired difference {:+.2}% (goal < {:.0}%: {})",
        pairs.len(),
        100.0 * attributed,
        100.0 * paired,
        100.0 * GOAL_SHARE,
        if attributed < GOAL_SHARE && paired < GOAL_SHARE {
            "met"
        } else {
            "MISSED"
        }
    );
}

/// Flies the plan once against a fresh vehicle process; records to `rrd` if given.
fn fly_once(
    mission_path: &Path,
    plan_file: &Path,
    mission: &Mission,
    plan: &DiscretePlan,
    record: Option<(&PathBuf, &RecorderOptions)>,
) -> anyhow::Result<Run> {
    let mut child = Command::new(std::env::current_exe()?)
        .env(ROLE_ENV, "vehicles")
        .env(MISSION_ENV, mission_path)
        .env(PLAN_ENV, plan_file)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .context("starting the vehicle process")?;
    let result = fly_against(&mut child, mission, plan, record);
    if let Some(mut stdin) = child.stdin.take() {
        let _ = writeln!(stdin, "done");
    }
    let _ = child.wait();
    result
}

fn fly_against(
    child: &mut std::process::Child,
    mission: &Mission,
    plan: &DiscretePlan,
    record: Option<(&PathBuf, &RecorderOptions)>,
) -> anyhow::Result<Run> {
    let mut from_child = BufReader::new(child.stdout.take().context("child stdout")?);
    let links = read_links(&mut from_child)?;
    if links.len() != plan.drones.len() {
        bail!("{} vehicles for {} drones", links.len(), plan.drones.len());
    }
    let mut options = FlyOptions::new(links);
    // Composed and checked as `swarmctl fly` does, before the measured part.
    let checked = swarmctl::compiled::compile_plan(mission, plan, 0)?;
    let runtime = tokio::runtime::Runtime::new()?;
    let threads = ThreadSampler::start();
    let (cpu0_s, main0_s, wall0) = (process_cpu_s()?, main_cpu_s()?, Instant::now());
    let mut breakdown = Vec::new();
    let live = match record {
        Some((rrd, recorder_options)) => {
            let live = LiveFlight::start(
                mission,
                checked.compiled(),
                &Sink::File(rrd.clone()),
                recorder_options.clone(),
            )?;
            options.observers = vec![live.observer()];
            breakdown.push(("start (main thread)".to_string(), main_cpu_s()? - main0_s));
            Some(live)
        }
        None => None,
    };
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let log = runtime.block_on(fly::fly_checked(mission, &checked, &options, abort_rx))?;
    options.observers.clear();
    let stats = match live {
        Some(live) => {
            let before = main_cpu_s()?;
            let stats = live.finish(&log)?;
            breakdown.push(("finish (main thread)".to_string(), main_cpu_s()? - before));
            Some(stats)
        }
        None => None,
    };
    let (process_cpu_s, wall_s) = (process_cpu_s()? - cpu0_s, wall0.elapsed().as_secs_f64());
    let (by_name, sampler_cpu_s) = threads.stop();
    let process_cpu_s = process_cpu_s - sampler_cpu_s;
    drop(runtime);
    if record.is_some() {
        breakdown.extend(
            by_name
                .into_iter()
                .filter(|(name, _)| RECORDING_THREADS.contains(&name.as_str())),
        );
    }
    let recording_cpu_s = breakdown.iter().map(|(_, cpu_s)| cpu_s).sum();
    Ok(Run {
        recorded: record.is_some(),
        wall_s,
        process_cpu_s,
        recording_cpu_s,
        breakdown,
        samples_logged: stats.map_or(0, |s| s.samples_logged),
        samples_dropped: stats.map_or(0, |s| s.samples_dropped),
        rrd_mb: record
            .and_then(|(rrd, _)| std::fs::metadata(rrd).ok())
            .map_or(0.0, |m| m.len() as f64 / 1e6),
        completed: log.summary.completed,
    })
}

fn read_links(from_child: &mut impl BufRead) -> anyhow::Result<Vec<VehicleLink>> {
    let mut line = String::new();
    loop {
        line.clear();
        if from_child.read_line(&mut line)? == 0 {
            bail!("the vehicle process exited before reporting its addresses");
        }
        if let Some(addresses) = line.trim().strip_prefix("ADDRESSES") {
            return Ok(addresses
                .split_whitespace()
                .enumerate()
                .map(|(i, a)| VehicleLink::mavlink(format!("udpout:{a}"), i as u8 + 1))
                .collect());
        }
    }
}

/// User + system CPU of the whole process, seconds.
fn process_cpu_s() -> anyhow::Result<f64> {
    resources::process_cpu_s().context("cannot read the process's CPU time (Linux only)")
}

/// User + system CPU of the calling thread, seconds.
fn main_cpu_s() -> anyhow::Result<f64> {
    resources::this_thread_cpu_s().context("cannot read the thread's CPU time (Linux only)")
}

/// Reads every thread's CPU time every 200 ms and keeps the latest per thread, so
/// threads that end during the flight (rerun's, when the recorder finishes) count
/// (all but their last moments).
struct ThreadSampler {
    stop: Arc<AtomicBool>,
    /// Returns the latest reading per thread and the sampler's own CPU.
    thread: std::thread::JoinHandle<(ThreadCpu, f64)>,
    start: HashMap<u32, f64>,
}

/// Thread id to (name, CPU seconds).
type ThreadCpu = HashMap<u32, (String, f64)>;

impl ThreadSampler {
    fn start() -> Self {
        let start = read_threads()
            .into_iter()
            .map(|(t, (_, c))| (t, c))
            .collect();
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let thread = std::thread::spawn(move || {
            let mut latest = HashMap::new();
            while !flag.load(Ordering::Relaxed) {
                latest.extend(read_threads());
                std::thread::sleep(Duration::from_millis(200));
            }
            latest.extend(read_threads());
            // The sampler's own CPU (0 if unreadable, which `main_cpu_s` ruled out).
            (latest, resources::this_thread_cpu_s().unwrap_or(0.0))
        });
        Self {
            stop,
            thread,
            start,
        }
    }

    /// CPU seconds per thread name since `start` (threads that existed then count
    /// from there), and the sampler's own CPU, which is no part of the flight.
    fn stop(self) -> (Vec<(String, f64)>, f64) {
        self.stop.store(true, Ordering::Relaxed);
        let (latest, own_cpu_s) = self.thread.join().unwrap_or_default();
        let mut by_name: HashMap<String, f64> = HashMap::new();
        for (tid, (name, cpu)) in latest {
            *by_name.entry(name).or_default() += cpu - self.start.get(&tid).copied().unwrap_or(0.0);
        }
        (by_name.into_iter().collect(), own_cpu_s)
    }
}

/// (name, CPU seconds) of every live thread of this process, by thread id.
fn read_threads() -> ThreadCpu {
    resources::threads_cpu()
        .unwrap_or_default()
        .into_iter()
        .map(|t| (t.tid, (t.name, t.cpu_s)))
        .collect()
}

/// Child role: the bundled SITL for the mission's drones; prints their addresses,
/// runs until a line (or EOF) on stdin.
fn vehicles_main() -> anyhow::Result<()> {
    let mission_path = PathBuf::from(std::env::var(MISSION_ENV)?);
    let mission = swarmctl::import::load_any(&mission_path, None)?;
    let plan: DiscretePlan =
        serde_json::from_str(&std::fs::read_to_string(std::env::var(PLAN_ENV)?)?)?;
    let configs =
        swarmctl_bundled::vehicle_configs(&mission, &plan, swarmctl_sitl::Flavour::Px4, &[])?;
    let runtime = tokio::runtime::Runtime::new()?;
    let (swarm, _) = runtime.block_on(swarmctl_bundled::start(
        configs,
        mission.link.setpoint_rate_hz,
    ))?;
    let addresses: Vec<String> = swarm.addresses().iter().map(|a| a.to_string()).collect();
    let mut out = std::io::stdout().lock();
    writeln!(out, "ADDRESSES {}", addresses.join(" "))?;
    out.flush()?;
    let mut line = String::new();
    std::io::stdin().read_line(&mut line)?;
    runtime.block_on(swarm.shutdown());
    Ok(())
}
