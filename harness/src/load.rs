//! The load benchmark (issue 8): plan and fly an N-drone mission on N bundled SITL
//! vehicles in one process, and measure what the load costs and whether the flight
//! stays correct under it.
//!
//! The vehicles run on their own tokio runtime (threads named [`SITL_THREAD`]) and
//! the controller on another, so the process's CPU time splits by thread: SITL
//! threads, the truth watcher ([`WATCH_THREAD`], this benchmark's own measuring),
//! and everything else, which is the controller. CPU times come from
//! `/proc/self/stat` and `/proc/self/task/*/stat` (the kernel's utime + stime, the
//! figures getrusage reports), so this is Linux-only; elsewhere they read as zero.
//!
//! Setpoint timing is measured where a vehicle receives it
//! ([`Swarm::setpoint_intervals`]). Separation is measured from telemetry (the
//! flight log) and from the simulator's true positions over the whole flight.
//!
//! The mission ([`load_mission`]) puts every start on its own x,y column in the
//! lowest layer and every goal on its own column, so vertical takeoff and landing
//! bring no two drones together and the benchmark measures load, not that known
//! limitation.

use crate::{median, peak_memory_bytes, process_resources};
use anyhow::Context;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use swarmctl::fly::{self, FlightLog, FlyOptions};
use swarmctl::link::frames;
use swarmctl::mission::schema::{LimitsSpec, LinkSpec, WorldSpec};
use swarmctl::mission::{Mission, MissionFile};
use swarmctl::plan::{self, DiscretePlan};
use swarmctl_sitl::swarm::SetpointIntervals;
use swarmctl_sitl::{Flavour, LinkStats, Swarm, TickStats};

/// Name of the SITL runtime's threads (Linux keeps 15 bytes of a thread name).
pub const SITL_THREAD: &str = "load-sitl";
/// Name of the controller runtime's worker threads.
pub const CONTROLLER_THREAD: &str = "load-controller";
/// Name of the thread that samples true positions and resources.
pub const WATCH_THREAD: &str = "load-watch";

/// Drones per group (within a group any drone may take any goal).
const DRONES_PER_GROUP: usize = 20;
/// Layers of the world above the lowest one.
const LAYERS: u32 = 3;
/// How often the watcher samples true positions.
const TRUTH_PERIOD: Duration = Duration::from_millis(20);
/// Sliding window for the busiest stretch of the flight, seconds.
const PEAK_WINDOW_S: usize = 5;
/// A vehicle resting this close (horizontally) to the point below its goal is at its goal.
const AT_GOAL_TOLERANCE_M: f64 = 0.3;
/// Linux reports process times in USER_HZ ticks, fixed at 100 by the kernel ABI.
const USER_HZ: f64 = 100.0;

/// What to fly.
#[derive(Debug, Clone)]
pub struct LoadOptions {
    /// Drones, one bundled SITL vehicle each (1–254).
    pub vehicles: usize,
    /// Seeds the mission (and the planner's tie-breaking).
    pub seed: u64,
    pub flavour: Flavour,
    /// How many times to plan (the report gives the median time); the first plan flies.
    pub plan_runs: usize,
    /// The whole flight must end within this.
    pub limit: Duration,
}

impl LoadOptions {
    pub fn new(vehicles: usize, seed: u64) -> Self {
        Self {
            vehicles,
            seed,
            flavour: Flavour::Px4,
            plan_runs: 1,
            limit: Duration::from_secs(600),
        }
    }
}

/// A seeded random mission for `vehicles` drones on a square world just large
/// enough for two free columns per drone, four layers high, no obstacles: starts
/// on distinct x,y columns in the lowest layer, goals on distinct columns at random
/// heights, groups of up to 20. The lowest layer is 1 m above the ground.
pub fn load_mission(vehicles: usize, seed: u64) -> anyhow::Result<MissionFile> {
    anyhow::ensure!(
        (1..=254).contains(&vehicles),
        "the bundled SITL flies 1–254 vehicles ({vehicles} asked)"
    );
    let side = ((2 * vehicles) as f64).sqrt().ceil().max(2.0) as u32;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut columns: Vec<[i64; 2]> = (0..side)
        .flat_map(|x| (0..side).map(move |y| [i64::from(x), i64::from(y)]))
        .collect();
    columns.shuffle(&mut rng);
    let starts: Vec<[i64; 3]> = columns[..vehicles]
        .iter()
        .map(|&[x, y]| [x, y, 0])
        .collect();
    columns.shuffle(&mut rng);
    let heights: Vec<i64> = (0..vehicles)
        .map(|_| rng.random_range(0..=i64::from(LAYERS)))
        .collect();
    let goals: Vec<[i64; 3]> = columns[..vehicles]
        .iter()
        .zip(&heights)
        .map(|(&[x, y], &z)| [x, y, z])
        .collect();
    let groups = vehicles.div_ceil(DRONES_PER_GROUP);
    let group_specs = swarmctl::generate::split_into_groups(groups, &starts, &goals);
    Ok(MissionFile {
        name: format!("load-{vehicles}-s{seed}"),
        description: Some(format!(
            "Load benchmark (swarmctl bench load --vehicles {vehicles} --seed {seed}): \
             {side}x{side}x{} voxels, starts and goals on distinct columns.",
            LAYERS + 1
        )),
        world: WorldSpec {
            dimensions: [i64::from(side), i64::from(side), i64::from(LAYERS + 1)],
            voxel_size_m: 1.0,
            origin_m: [0.0, 0.0, 1.0],
            obstacles: Vec::new(),
        },
        limits: LimitsSpec {
            max_speed_mps: 1.0,
            max_accel_mps2: 2.0,
            safety_distance_m: 0.25,
        },
        link: LinkSpec::default(),
        groups: group_specs,
    })
}

/// CPU time over the flight, seconds, split by thread.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CpuUse {
    pub wall_s: f64,
    /// The whole process.
    pub total_s: f64,
    /// The SITL runtime's threads.
    pub sitl_s: f64,
    /// The truth watcher (this benchmark's own measuring).
    pub watch_s: f64,
    /// Busiest [`PEAK_WINDOW_S`] s of the whole process, CPU s per wall s.
    pub peak_total_share: f64,
    /// Busiest [`PEAK_WINDOW_S`] s of the controller, CPU s per wall s.
    pub peak_controller_share: f64,
}

impl CpuUse {
    /// Everything but the SITL and the watcher, seconds.
    pub fn controller_s(&self) -> f64 {
        (self.total_s - self.sitl_s - self.watch_s).max(0.0)
    }

    /// Percent of one core.
    pub fn percent(&self, cpu_s: f64) -> f64 {
        if self.wall_s > 0.0 {
            100.0 * cpu_s / self.wall_s
        } else {
            0.0
        }
    }
}

/// What one load run measured.
#[derive(Debug, Clone)]
pub struct LoadReport {
    pub vehicles: usize,
    pub seed: u64,
    pub mission: String,
    /// Wall time of each planning run, seconds.
    pub plan_times_s: Vec<f64>,
    pub makespan_steps: u32,
    /// The flight log, if the flight ran to its end.
    pub log: Option<FlightLog>,
    /// How the flight ended, in words.
    pub observed: String,
    /// Vehicles resting disarmed within [`AT_GOAL_TOLERANCE_M`] of the point below
    /// their goal (simulator truth).
    pub at_goal: usize,
    /// Largest horizontal distance of a vehicle from below its goal (truth), metres.
    pub max_goal_error_m: f64,
    /// System ids still armed after the flight.
    pub still_armed: Vec<u8>,
    pub flight_wall_s: f64,
    pub cpu: CpuUse,
    /// Every vehicle's setpoint intervals together.
    pub setpoints: SetpointIntervals,
    /// The worst single vehicle's p99 interval, seconds.
    pub worst_vehicle_p99_s: f64,
    /// Link counters summed over the vehicles.
    pub link: LinkStats,
    /// Link losses the controller noticed, summed over the drones.
    pub controller_link_losses: usize,
    /// The SITL physics ticker over the flight.
    pub ticks: TickStats,
    /// Telemetry, during plan execution (∞ if fewer than two flew).
    pub min_separation_telemetry_m: f64,
    /// Telemetry, takeoff and landing.
    pub min_separation_takeoff_landing_m: f64,
    /// Simulator truth, whole flight, airborne pairs.
    pub min_separation_truth_m: f64,
    pub safety_distance_m: f64,
    /// Process peak resident memory (`VmHWM`), bytes: planning included.
    pub peak_rss_bytes: u64,
    /// Highest resident memory sampled during the flight (once a second), bytes.
    pub flight_max_rss_bytes: u64,
    pub fds_before: usize,
    /// Most open file descriptors sampled during the flight.
    pub fds_max: usize,
    /// Open file descriptors once the vehicles and runtimes are gone.
    pub fds_after: usize,
    /// What went wrong; empty if the run is correct (speed is not judged).
    pub failures: Vec<String>,
}

impl LoadReport {
    pub fn passed(&self) -> bool {
        self.failures.is_empty()
    }

    pub fn completed(&self) -> bool {
        self.log.as_ref().is_some_and(|l| l.summary.completed)
    }
}

/// Builds the mission for `options` and plans it `plan_runs` times.
pub fn plan_load(options: &LoadOptions) -> anyhow::Result<(Mission, DiscretePlan, Vec<f64>)> {
    let file = load_mission(options.vehicles, options.seed)?;
    let mission = swarmctl::mission::validate(&file).map_err(|problems| {
        anyhow::anyhow!("the generated load mission is invalid: {problems:?}")
    })?;
    let plan_options = plan::PlanOptions {
        seed: options.seed,
        ..Default::default()
    };
    let mut times = Vec::new();
    let mut first = None;
    for _ in 0..options.plan_runs.max(1) {
        let started = Instant::now();
        let solution = plan::solve(&mission, &plan_options)
            .with_context(|| format!("planning {}", mission.name))?;
        times.push(started.elapsed().as_secs_f64());
        first.get_or_insert(solution.plan);
    }
    let plan = first.context("no planning run")?;
    Ok((mission, plan, times))
}

/// Plans and flies the load mission and measures it. Call it outside any tokio
/// runtime: it builds its own two.
pub fn run_load(options: &LoadOptions) -> anyhow::Result<LoadReport> {
    let (mission, plan, plan_times_s) = plan_load(options)?;
    fly_load(&mission, &plan, plan_times_s, options)
}

/// Flies `plan` on the bundled SITL and measures it (see [`run_load`]).
pub fn fly_load(
    mission: &Mission,
    plan: &DiscretePlan,
    plan_times_s: Vec<f64>,
    options: &LoadOptions,
) -> anyhow::Result<LoadReport> {
    let fds_before = process_resources().open_fds;
    let sitl_runtime = tokio::runtime::Builder::new_multi_thread()
        .thread_name(SITL_THREAD)
        .enable_all()
        .build()
        .context("starting the SITL runtime")?;
    let controller_runtime = tokio::runtime::Builder::new_multi_thread()
        .thread_name(CONTROLLER_THREAD)
        .enable_all()
        .build()
        .context("starting the controller runtime")?;
    let configs = crate::bundled_sitl::vehicle_configs(mission, plan, options.flavour, &[])?;
    let (swarm, links) = sitl_runtime.block_on(crate::bundled_sitl::start(
        configs,
        mission.link.setpoint_rate_hz,
    ))?;
    let swarm = Arc::new(swarm);
    let mut fly_options = FlyOptions::new(links);
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);

    let done = Arc::new(AtomicBool::new(false));
    let watch = {
        let (swarm, done) = (swarm.clone(), done.clone());
        std::thread::Builder::new()
            .name(WATCH_THREAD.into())
            .spawn(move || watch(&swarm, &done))
            .context("starting the watcher")?
    };
    let ticks_before = swarm.tick_stats();
    let (wall0, cpu0, sitl0) = (Instant::now(), process_cpu_s(), threads_cpu_s(SITL_THREAD));
    let result = controller_runtime.block_on(async {
        let flight = fly::fly(mission, plan, &fly_options, abort_rx);
        tokio::time::timeout(options.limit, flight).await
    });
    let (wall_s, total_s, sitl_s) = (
        wall0.elapsed().as_secs_f64(),
        process_cpu_s() - cpu0,
        threads_cpu_s(SITL_THREAD) - sitl0,
    );
    let ticks_after = swarm.tick_stats();
    done.store(true, Ordering::Relaxed);
    let watched = watch
        .join()
        .map_err(|_| anyhow::anyhow!("the watcher panicked"))?;

    // What the vehicles saw, before they go.
    let safety = mission.limits.safety_distance_m;
    let mut setpoints = SetpointIntervals::default();
    let mut worst_vehicle_p99_s: f64 = 0.0;
    let mut link = LinkStats::default();
    let mut still_armed = Vec::new();
    let mut at_goal = 0;
    let mut max_goal_error_m: f64 = 0.0;
    for (i, drone) in plan.drones.iter().enumerate() {
        let intervals = swarm.setpoint_intervals(i);
        worst_vehicle_p99_s = worst_vehicle_p99_s.max(intervals.quantile_s(0.99));
        setpoints.merge(&intervals);
        let s = swarm.snapshot(i);
        add_link_stats(&mut link, &s.link);
        if s.armed {
            still_armed.push(s.system_id);
        }
        let goal = mission.world.center_m(drone.goal);
        let below_goal = frames::ned_f32_from_enu([goal.x, goal.y, 0.0]);
        let error_m = f64::from(
            ((s.position_ned_m[0] - below_goal[0]).powi(2)
                + (s.position_ned_m[1] - below_goal[1]).powi(2))
            .sqrt(),
        );
        max_goal_error_m = max_goal_error_m.max(error_m);
        if !s.armed && s.landed && error_m <= AT_GOAL_TOLERANCE_M {
            at_goal += 1;
        }
    }
    let fds_max = watched.max_fds;
    let flight_max_rss_bytes = watched.max_rss_bytes;
    drop(fly_options);
    match Arc::try_unwrap(swarm) {
        Ok(swarm) => sitl_runtime.block_on(swarm.shutdown()),
        Err(_) => anyhow::bail!("the swarm is still shared after the flight"),
    }
    drop(controller_runtime);
    drop(sitl_runtime);
    let fds_after = process_resources().open_fds;

    let mut failures = Vec::new();
    let (observed, log) = match result {
        Err(_) => {
            failures.push(format!("did not finish within {:?}", options.limit));
            ("timed out".to_string(), None)
        }
        Ok(Err(e)) => {
            let text = e.to_string();
            failures.push(format!("flight failed: {text}"));
            (
                format!("failed: {}", text.lines().next().unwrap_or_default()),
                None,
            )
        }
        Ok(Ok(log)) => (describe(&log), Some(log)),
    };
    if let Some(log) = &log {
        if !log.summary.completed {
            failures.push("not every drone reached its goal".into());
        }
        for (what, names) in [
            ("lost", &log.summary.lost),
            ("retired", &log.summary.retired),
            ("handed over", &log.summary.handed_over),
        ] {
            if !names.is_empty() {
                failures.push(format!("{what}: {}", names.join(", ")));
            }
        }
    }
    if at_goal != plan.drones.len() {
        failures.push(format!(
            "{at_goal}/{} vehicles landed disarmed below their goal (worst {max_goal_error_m:.2} m off)",
            plan.drones.len()
        ));
    }
    if !still_armed.is_empty() {
        failures.push(format!("systems {still_armed:?} still armed"));
    }
    if link.tx_errors > 0 {
        failures.push(format!("{} vehicle send errors", link.tx_errors));
    }
    let telemetry_m = log
        .as_ref()
        .map_or(f64::INFINITY, |l| l.summary.min_separation_m);
    let takeoff_landing_m = log.as_ref().map_or(f64::INFINITY, |l| {
        l.summary.min_separation_takeoff_landing_m
    });
    for (what, m) in [
        ("telemetry", telemetry_m),
        ("takeoff/landing telemetry", takeoff_landing_m),
        ("true", watched.min_separation_m),
    ] {
        if m < safety {
            failures.push(format!("{what} separation {m:.3} m < {safety} m"));
        }
    }
    let controller_link_losses = log
        .as_ref()
        .map_or(0, |l| l.drones.iter().map(|d| d.link_losses).sum());
    let cpu = CpuUse {
        wall_s,
        total_s,
        sitl_s,
        watch_s: watched.own_cpu_s,
        peak_total_share: watched.peak_total_share,
        peak_controller_share: watched.peak_controller_share,
    };
    Ok(LoadReport {
        vehicles: plan.drones.len(),
        seed: options.seed,
        mission: mission.name.clone(),
        plan_times_s,
        makespan_steps: plan.makespan_steps,
        log,
        observed,
        at_goal,
        max_goal_error_m,
        still_armed,
        flight_wall_s: wall_s,
        cpu,
        setpoints,
        worst_vehicle_p99_s,
        link,
        controller_link_losses,
        ticks: TickStats {
            ticks: ticks_after.ticks - ticks_before.ticks,
            steps: ticks_after.steps - ticks_before.steps,
            missed_ticks: ticks_after.missed_ticks - ticks_before.missed_ticks,
            skipped_steps: ticks_after.skipped_steps - ticks_before.skipped_steps,
        },
        min_separation_telemetry_m: telemetry_m,
        min_separation_takeoff_landing_m: takeoff_landing_m,
        min_separation_truth_m: watched.min_separation_m,
        safety_distance_m: safety,
        peak_rss_bytes: peak_memory_bytes().unwrap_or(0),
        flight_max_rss_bytes,
        fds_before,
        fds_max,
        fds_after,
        failures,
    })
}

fn add_link_stats(sum: &mut LinkStats, s: &LinkStats) {
    sum.rx_datagrams += s.rx_datagrams;
    sum.rx_dropped_by_fault += s.rx_dropped_by_fault;
    sum.rx_duplicated += s.rx_duplicated;
    sum.rx_reordered += s.rx_reordered;
    sum.rx_messages += s.rx_messages;
    sum.rx_bad_signature += s.rx_bad_signature;
    sum.rx_undecodable += s.rx_undecodable;
    sum.tx_datagrams += s.tx_datagrams;
    sum.tx_dropped_by_fault += s.tx_dropped_by_fault;
    sum.tx_duplicated += s.tx_duplicated;
    sum.tx_reordered += s.tx_reordered;
    sum.tx_errors += s.tx_errors;
}

fn describe(log: &FlightLog) -> String {
    let s = &log.summary;
    if s.completed {
        format!(
            "completed, plan {:.1} s (planned {:.1} s), {} gating waits",
            s.executed_makespan_s.unwrap_or(f64::NAN),
            s.planned_makespan_s,
            s.gating_waits
        )
    } else {
        "not completed".into()
    }
}

/// What the watcher saw.
struct Watched {
    min_separation_m: f64,
    max_rss_bytes: u64,
    max_fds: usize,
    own_cpu_s: f64,
    peak_total_share: f64,
    peak_controller_share: f64,
}

/// Until `done`: the smallest true distance between two airborne vehicles (every
/// [`TRUTH_PERIOD`]), and once a second memory, open files and CPU.
fn watch(swarm: &Swarm, done: &AtomicBool) -> Watched {
    let own0 = own_thread_cpu_s();
    let start = Instant::now();
    let mut min_m = f64::INFINITY;
    let mut max_rss_bytes = 0;
    let mut max_fds = 0;
    // (wall s, process CPU s, SITL CPU s, watcher CPU s) once a second.
    let samples: Mutex<Vec<[f64; 4]>> = Mutex::default();
    let mut next_sample = start;
    let mut airborne: Vec<[f32; 3]> = Vec::with_capacity(swarm.len());
    while !done.load(Ordering::Relaxed) {
        min_m = min_m.min(super::true_min_separation_m(swarm, &mut airborne));
        if Instant::now() >= next_sample {
            next_sample += Duration::from_secs(1);
            let usage = process_resources();
            max_rss_bytes = max_rss_bytes.max(usage.rss_bytes);
            max_fds = max_fds.max(usage.open_fds);
            samples.lock().unwrap_or_else(|e| e.into_inner()).push([
                start.elapsed().as_secs_f64(),
                process_cpu_s(),
                threads_cpu_s(SITL_THREAD),
                own_thread_cpu_s(),
            ]);
        }
        std::thread::sleep(TRUTH_PERIOD);
    }
    let samples = samples.into_inner().unwrap_or_else(|e| e.into_inner());
    let (mut peak_total_share, mut peak_controller_share) = (0.0f64, 0.0f64);
    for w in samples.windows(PEAK_WINDOW_S + 1) {
        let (a, b) = (w[0], w[PEAK_WINDOW_S]);
        let wall_s = b[0] - a[0];
        if wall_s > 0.0 {
            let total = b[1] - a[1];
            let controller = total - (b[2] - a[2]) - (b[3] - a[3]);
            peak_total_share = peak_total_share.max(total / wall_s);
            peak_controller_share = peak_controller_share.max(controller / wall_s);
        }
    }
    Watched {
        min_separation_m: min_m,
        max_rss_bytes,
        max_fds,
        own_cpu_s: own_thread_cpu_s() - own0,
        peak_total_share,
        peak_controller_share,
    }
}

/// utime + stime from a `/proc/.../stat` line, seconds, with the thread's name.
fn parse_stat(stat: &str) -> Option<(&str, f64)> {
    let open = stat.find('(')?;
    let close = stat.rfind(')')?;
    let name = stat.get(open + 1..close)?;
    let fields: Vec<&str> = stat.get(close + 1..)?.split_whitespace().collect();
    // After the name: state is field 0, utime field 11, stime field 12.
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    Some((name, (utime + stime) / USER_HZ))
}

/// User + system CPU time of the whole process (all threads, live and exited), seconds.
pub fn process_cpu_s() -> f64 {
    std::fs::read_to_string("/proc/self/stat")
        .ok()
        .and_then(|s| parse_stat(&s).map(|(_, cpu)| cpu))
        .unwrap_or(0.0)
}

/// CPU time of the calling thread, seconds.
fn own_thread_cpu_s() -> f64 {
    std::fs::read_to_string("/proc/thread-self/stat")
        .ok()
        .and_then(|s| parse_stat(&s).map(|(_, cpu)| cpu))
        .unwrap_or(0.0)
}

/// CPU time of this process's live threads named `name`, seconds.
pub fn threads_cpu_s(name: &str) -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return 0.0;
    };
    tasks
        .flatten()
        .filter_map(|task| std::fs::read_to_string(task.path().join("stat")).ok())
        .filter_map(|stat| {
            parse_stat(&stat)
                .filter(|(n, _)| *n == name)
                .map(|(_, cpu)| cpu)
        })
        .sum()
}

/// The runs side by side, one column each, as a Markdown table.
pub fn markdown_table(reports: &[LoadReport]) -> String {
    let mut rows: Vec<(String, Vec<String>)> = Vec::new();
    let mut row = |name: &str, f: &dyn Fn(&LoadReport) -> String| {
        rows.push((name.to_string(), reports.iter().map(f).collect()));
    };
    let ms = |s: f64| format!("{:.1}", s * 1e3);
    let metres = |m: f64| {
        if m.is_finite() {
            format!("{m:.2}")
        } else {
            "—".into()
        }
    };
    let pct = |r: &LoadReport, s: f64| format!("{:.1}", r.cpu.percent(s));
    row("Mission", &|r| format!("`{}`", r.mission));
    row("Planning time, median of runs (s)", &|r| {
        format!(
            "{:.3} ({} runs)",
            median(&r.plan_times_s),
            r.plan_times_s.len()
        )
    });
    row("Makespan (steps / planned s / flown s)", &|r| {
        let s = r.log.as_ref().map(|l| &l.summary);
        format!(
            "{} / {} / {}",
            r.makespan_steps,
            s.map_or("—".into(), |s| format!("{:.1}", s.planned_makespan_s)),
            s.and_then(|s| s.executed_makespan_s)
                .map_or("—".into(), |t| format!("{t:.1}"))
        )
    });
    row("Flight (wall s)", &|r| format!("{:.1}", r.flight_wall_s));
    row("Completed", &|r| {
        if r.completed() { "yes" } else { "NO" }.to_string()
    });
    row("Landed at goal (truth)", &|r| {
        format!(
            "{}/{} (worst {:.2} m)",
            r.at_goal, r.vehicles, r.max_goal_error_m
        )
    });
    row("Still armed", &|r| r.still_armed.len().to_string());
    row("CPU total (% of one core; busiest 5 s)", &|r| {
        format!(
            "{} ({:.1})",
            pct(r, r.cpu.total_s),
            100.0 * r.cpu.peak_total_share
        )
    });
    row("CPU controller (%; busiest 5 s)", &|r| {
        format!(
            "{} ({:.1})",
            pct(r, r.cpu.controller_s()),
            100.0 * r.cpu.peak_controller_share
        )
    });
    row("CPU SITL (%)", &|r| pct(r, r.cpu.sitl_s));
    row("CPU truth watcher (%)", &|r| pct(r, r.cpu.watch_s));
    row("Setpoint interval p50 / p99 / max (ms)", &|r| {
        format!(
            "{} / {} / {}",
            ms(r.setpoints.quantile_s(0.5)),
            ms(r.setpoints.quantile_s(0.99)),
            ms(r.setpoints.max_s())
        )
    });
    row("Worst vehicle's p99 (ms)", &|r| ms(r.worst_vehicle_p99_s));
    row("Setpoint intervals (> 100 ms / > 500 ms)", &|r| {
        format!(
            "{} ({} / {})",
            r.setpoints.count(),
            r.setpoints.count_above(0.1),
            r.setpoints.count_above(0.5)
        )
    });
    row("Vehicle link rx / tx datagrams", &|r| {
        format!("{} / {}", r.link.rx_datagrams, r.link.tx_datagrams)
    });
    row("Vehicle tx errors / undecodable rx", &|r| {
        format!("{} / {}", r.link.tx_errors, r.link.rx_undecodable)
    });
    row("Controller link losses", &|r| {
        r.controller_link_losses.to_string()
    });
    row("SITL physics missed / skipped steps", &|r| {
        format!(
            "{} / {} of {}",
            r.ticks.missed_ticks, r.ticks.skipped_steps, r.ticks.steps
        )
    });
    row(
        "Min separation telemetry / takeoff+landing / truth (m)",
        &|r| {
            format!(
                "{} / {} / {}",
                metres(r.min_separation_telemetry_m),
                metres(r.min_separation_takeoff_landing_m),
                metres(r.min_separation_truth_m)
            )
        },
    );
    row("Safety distance (m)", &|r| {
        format!("{:.2}", r.safety_distance_m)
    });
    row("Peak RSS, process / in flight (MiB)", &|r| {
        format!(
            "{:.1} / {:.1}",
            r.peak_rss_bytes as f64 / 1048576.0,
            r.flight_max_rss_bytes as f64 / 1048576.0
        )
    });
    row("Open fds before / max in flight / after", &|r| {
        format!("{} / {} / {}", r.fds_before, r.fds_max, r.fds_after)
    });
    row("Result", &|r| {
        if r.passed() {
            "pass".to_string()
        } else {
            format!("FAIL: {}", r.failures.join("; "))
        }
    });
    let mut out = String::from("| Metric |");
    for r in reports {
        out.push_str(&format!(" {} vehicles |", r.vehicles));
    }
    out.push_str("\n|---|");
    out.push_str(&"---|".repeat(reports.len()));
    out.push('\n');
    for (name, cells) in rows {
        out.push_str(&format!("| {name} | {} |\n", cells.join(" | ")));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_missions_keep_starts_and_goals_on_distinct_columns() {
        for (vehicles, seed) in [(1, 1), (50, 1), (200, 1), (200, 7), (254, 3)] {
            let file = load_mission(vehicles, seed).unwrap();
            let mission = swarmctl::mission::validate(&file).unwrap();
            assert_eq!(mission.drone_count(), vehicles);
            let starts: Vec<[i64; 3]> = file
                .groups
                .iter()
                .flat_map(|g| g.drones.iter().map(|d| d.start))
                .collect();
            let goals: Vec<[i64; 3]> = file.groups.iter().flat_map(|g| g.goals.clone()).collect();
            for list in [&starts, &goals] {
                let columns: std::collections::HashSet<[i64; 2]> =
                    list.iter().map(|v| [v[0], v[1]]).collect();
                assert_eq!(columns.len(), vehicles);
            }
            assert!(starts.iter().all(|s| s[2] == 0));
        }
        assert_eq!(load_mission(40, 2).unwrap(), load_mission(40, 2).unwrap());
        assert!(load_mission(0, 1).is_err() && load_mission(255, 1).is_err());
    }

    #[test]
    fn the_bundled_load_mission_is_what_the_benchmark_generates() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../missions/load-200.yaml");
        let text = std::fs::read_to_string(path).unwrap();
        let file: MissionFile = swarmctl::mission::parse_yaml(&text).unwrap();
        assert_eq!(file, load_mission(200, 1).unwrap());
    }

    #[test]
    fn stat_lines_parse_with_spaces_and_parentheses_in_names() {
        let line = "123 (a (b) c) S 1 2 3 4 5 6 7 8 9 10 250 50 0 0";
        assert_eq!(parse_stat(line), Some(("a (b) c", 3.0)));
    }
}
