//! `swarmctl fly`: plan (or load a plan), compose and check it, then fly exactly
//! that over MAVLink — against the mission's endpoints, or the bundled SITL when
//! the mission names none.

use anyhow::Context;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use swarmctl::compiled::{self, CheckedPlan, CompiledPlan};
use swarmctl::fly::{self, FaultSpec, FlyOptions, VehicleLink};
use swarmctl::import;
use swarmctl::link::SigningKey;
use swarmctl::mission::{KeySource, Mission};
use swarmctl::plan::{self, DiscretePlan};
use swarmctl_cli::record::{LiveFlight, RecorderOptions, Sink};
use swarmctl_cli::status::{StatusMode, StatusView};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mission file (YAML), or an instance `swarmctl plan` imports.
    mission: PathBuf,
    /// Fly this plan (JSON from `swarmctl plan -o`) instead of planning now.
    #[arg(long)]
    plan: Option<PathBuf>,
    /// Autopilot the bundled SITL imitates (default: the mission's `link.autopilot`).
    #[arg(long, value_parser = ["px4", "ardupilot"])]
    autopilot: Option<String>,
    /// Seconds pre-flight waits for every vehicle to report a position and pass its
    /// pre-arm checks (default 60: real autopilots need about 40 s after boot for
    /// EKF and GPS; 5 on the bundled simulator, whose vehicles are ready at once).
    #[arg(long, value_name = "SECONDS")]
    ready_timeout: Option<f64>,
    /// Every vehicle reports in the mission's frame (vehicles given a common EKF
    /// origin by hand; the bundled SITL then shares one frame). By default each
    /// vehicle has its own local frame, placed at pre-flight from its GPS origin
    /// (with `world.geo_origin`) or from standing on its pad.
    #[arg(long)]
    shared_frame: bool,
    /// Horizontal distance, metres, allowed between where a vehicle is found (its
    /// GPS with `world.geo_origin`, or its report in a shared frame) and its pad.
    #[arg(long, value_name = "METRES", default_value_t = 0.3)]
    pad_tolerance: f64,
    /// Bundled SITL fault, repeatable: link-wide loss=10%, latency=50ms, dup=5%,
    /// reorder=10%; per drone slow=DRONE_ID:0.5, drop=DRONE_ID@5s+3s (link cut
    /// 5 s after takeoff for 3 s), lose=DRONE_ID@5s (cut for good), crash=DRONE_ID@5s
    /// (motors stop, it falls, silent), refuse-arm=DRONE_ID,
    /// low-battery=DRONE_ID@10s, critical-battery=DRONE_ID@10s (after arming).
    #[arg(long = "fault", value_name = "FAULT", value_parser = parse_fault)]
    faults: Vec<FaultSpec>,
    /// Flight log (JSON); default flights/<mission file name>-<unix time>.json.
    // The comment above is `--help` text, shown as written: the placeholders
    // are not HTML.
    #[allow(rustdoc::invalid_html_tags)]
    #[arg(long)]
    log: Option<PathBuf>,
    /// Planner deadline in seconds (when no --plan is given).
    #[arg(long, default_value_t = 60.0)]
    deadline: f64,
    /// Seconds a replan in flight may take (after a drone is lost, or retires and
    /// is down) while every drone holds; past it the flight falls back to holding
    /// the lost drone's dependants while the rest finish and land.
    #[arg(long, value_name = "SECONDS", default_value_t = 3.0)]
    replan_deadline: f64,
    /// Replans allowed per flight; later losses fall back.
    #[arg(long, value_name = "COUNT", default_value_t = 3)]
    max_replans: usize,
    /// Never replan in flight: a lost drone's dependants hold for the rest of the
    /// flight, the other drones finish and land.
    #[arg(long)]
    no_replan: bool,
    /// Print a plain status line every few seconds instead of a spinner.
    #[arg(long)]
    plain: bool,
    /// MAVLink 2 signing key file (64 hex digits), overriding the mission's
    /// `link.signing`. The bundled SITL then enforces signatures too.
    #[arg(long, value_name = "FILE")]
    signing_key_file: Option<PathBuf>,
    /// How the controller reaches the vehicles: `mavlink` (its own sockets, or
    /// the bundled SITL) or `zenoh` (through `swarmctl relay` processes). Default:
    /// zenoh when the mission has `link.relays`, else mavlink.
    #[arg(long, value_parser = ["mavlink", "zenoh"])]
    via: Option<String>,
    /// With --via zenoh: where the controller accepts Zenoh sessions, repeatable
    /// (default: the mission's `link.zenoh.listen`, else tcp/127.0.0.1:7447,
    /// where relays connect by default).
    #[arg(long, value_name = "ENDPOINT")]
    zenoh_listen: Vec<String>,
    /// With --via zenoh: routers or relays to connect to, repeatable (default:
    /// the mission's `link.zenoh.connect`).
    #[arg(long, value_name = "ENDPOINT")]
    zenoh_connect: Vec<String>,
    /// With --via zenoh: seconds to wait for relays to announce every drone.
    #[arg(long, value_name = "SECONDS", default_value_t = 30.0)]
    relay_wait: f64,
    /// Where the Rerun recording goes (default: beside the flight log).
    #[command(flatten)]
    viewer: swarmctl_cli::record::ViewerArgs,
}

/// What stands behind the vehicle links for the flight, stopped after it.
enum Backing {
    /// The mission's own endpoints: nothing to stop.
    Endpoints,
    /// The bundled SITL, started here.
    Sitl(swarmctl_sitl::Swarm),
    /// Links through relays over Zenoh.
    Relays(swarmctl_relay::RelayLinks),
}

impl Backing {
    async fn shutdown(self) {
        match self {
            Backing::Endpoints => {}
            Backing::Sitl(swarm) => swarm.shutdown().await,
            Backing::Relays(links) => links.close().await,
        }
    }
}

fn parse_fault(s: &str) -> Result<FaultSpec, String> {
    fly::parse_fault(s).map_err(|e| e.reason)
}

/// The flags' durations, read once.
struct Durations {
    /// `--ready-timeout`, if given.
    ready: Option<std::time::Duration>,
    /// `--replan-deadline`.
    replan_deadline: std::time::Duration,
}

/// Refuses flags no flight can use, before anything is planned, started or
/// recorded; returns their durations.
fn check_args(args: &Args) -> anyhow::Result<Durations> {
    let seconds = |value: f64| std::time::Duration::try_from_secs_f64(value).ok();
    let ready = match args.ready_timeout {
        Some(ready_s) => Some(seconds(ready_s).with_context(|| {
            format!("--ready-timeout must be a non-negative number of seconds, got {ready_s}")
        })?),
        None => None,
    };
    if !(args.pad_tolerance.is_finite() && args.pad_tolerance > 0.0) {
        anyhow::bail!(
            "--pad-tolerance must be a positive number of metres, got {}",
            args.pad_tolerance
        );
    }
    let replan_deadline = seconds(args.replan_deadline).with_context(|| {
        format!(
            "--replan-deadline must be a non-negative number of seconds, got {}",
            args.replan_deadline
        )
    })?;
    if !(args.relay_wait.is_finite() && args.relay_wait > 0.0) {
        anyhow::bail!(
            "--relay-wait must be a positive number of seconds, got {}",
            args.relay_wait
        );
    }
    Ok(Durations {
        ready,
        replan_deadline,
    })
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let durations = check_args(&args)?;
    // The same inputs `swarmctl plan` accepts: mission YAML or an imported instance.
    let mission = import::load_any(&args.mission, None)?;
    if let Some(usage) = super::refuse_unknown_fault_drones(&args.faults, &mission) {
        return Ok(usage);
    }
    // Composed and checked before anything starts; what flies is exactly this.
    let checked = match &args.plan {
        Some(path) => load_plan(path, &mission)?,
        None => plan_now(&mission, args.deadline)?,
    };
    let plan = checked.discrete();
    let path = args
        .log
        .clone()
        .unwrap_or_else(|| default_log_path(&args.mission));
    // Recorded live; flying never depends on it (a recorder that fails only warns).
    let recording = start_recording(&args, &mission, checked.compiled(), &path);
    let observer = recording.as_ref().map(|(r, _)| r.observer());
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    let flight = Flight {
        mission: &mission,
        checked: &checked,
        plan: &plan,
    };
    let log = match runtime.block_on(fly_async(&args, &durations, flight, observer)) {
        Ok(log) => log,
        Err(refused) => {
            if let Some(recording) = recording {
                discard_recording(recording);
            }
            return Err(refused);
        }
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    std::fs::write(&path, serde_json::to_string(&log)?)
        .with_context(|| format!("cannot write {}", path.display()))?;
    println!("{}: flew {} drones", mission.name, log.drones.len());
    for line in log.summary.lines() {
        println!("{line}");
    }
    for e in &log.events {
        println!(
            "  event {:6.1} s {}{}",
            e.t_s,
            e.drone
                .as_deref()
                .map(|d| format!("{d}: "))
                .unwrap_or_default(),
            e.message
        );
    }
    println!("  log                  {}", path.display());
    if let Some(recording) = recording {
        finish_recording(recording, &log);
    }
    // Exit 0 only when every drone landed (README, exit codes): survivors that
    // completed after a loss do not make a drone lost in the air a success, and a
    // broken limit never exits 0.
    Ok(if log.summary.succeeded() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// What is flown: the mission, its checked plan and that plan's discrete part.
#[derive(Clone, Copy)]
struct Flight<'a> {
    mission: &'a Mission,
    checked: &'a CheckedPlan,
    plan: &'a DiscretePlan,
}

/// Flies the checked plan with the live status view (and `observer`, the
/// recording), on the mission's vehicles or the bundled SITL; Ctrl-C lands
/// everyone.
async fn fly_async(
    args: &Args,
    durations: &Durations,
    flight: Flight<'_>,
    observer: Option<Arc<dyn fly::FlightObserver>>,
) -> anyhow::Result<fly::FlightLog> {
    let Flight {
        mission,
        checked,
        plan,
    } = flight;
    let (abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    abort_on_ctrl_c(abort_tx);
    let source = match &args.signing_key_file {
        Some(file) => Some(KeySource::File(file.clone())),
        None => mission.link.signing.clone(),
    };
    let signing_key = source.as_ref().map(SigningKey::load).transpose()?;
    let (vehicles, backing) = vehicles(args, mission, plan, signing_key.as_ref()).await?;
    let mut options = FlyOptions::new(vehicles);
    let bundled = matches!(backing, Backing::Sitl(_));
    options.ready_timeout = durations
        .ready
        .unwrap_or(std::time::Duration::from_secs(if bundled { 5 } else { 60 }));
    options.frames = frame_source(args);
    options.start_tolerance_m = args.pad_tolerance;
    options.replan = fly::replan::ReplanOptions {
        enabled: !args.no_replan,
        deadline: durations.replan_deadline,
        max_replans: args.max_replans,
    };
    options.observers.extend(observer);
    let status = Arc::new(StatusView::new(if args.plain {
        StatusMode::Plain
    } else {
        StatusMode::Auto
    }));
    options.observers.push(status.clone());
    if signing_key.is_some() {
        eprintln!("MAVLink 2 signing on: unsigned or wrongly signed messages are refused");
    }
    options.signing_key = signing_key;
    let result = fly::fly_checked(mission, checked, &options, abort_rx).await;
    status.finish();
    backing.shutdown().await;
    Ok(result?)
}

/// On Ctrl-C every drone holds, then lands (the flight sees `abort_tx`); a second
/// Ctrl-C quits at once.
fn abort_on_ctrl_c(abort_tx: tokio::sync::watch::Sender<bool>) {
    tokio::spawn(async move {
        if tokio::signal::ctrl_c().await.is_ok() {
            eprintln!("Ctrl-C: every drone holds, then lands (Ctrl-C again to quit at once)");
            let _ = abort_tx.send(true);
            if tokio::signal::ctrl_c().await.is_ok() {
                std::process::exit(130);
            }
        }
    });
}

/// How to reach each drone of `plan` (plan order): the mission's endpoints, or,
/// when it names none, the bundled SITL started here (returned too, to shut it
/// down after the flight).
async fn vehicles(
    args: &Args,
    mission: &Mission,
    plan: &DiscretePlan,
    signing_key: Option<&SigningKey>,
) -> anyhow::Result<(Vec<VehicleLink>, Backing)> {
    let via_zenoh = match args.via.as_deref() {
        Some(via) => via == "zenoh",
        None => !mission.link.relays.is_empty(),
    };
    if via_zenoh {
        if !args.faults.is_empty() || args.autopilot.is_some() {
            anyhow::bail!(
                "--fault and --autopilot apply to the bundled SITL this process starts; through relays, give them to `swarmctl relay --sitl`"
            );
        }
        let links = super::fly_relays::connect(
            mission,
            plan,
            &super::fly_relays::ZenohArgs {
                listen: &args.zenoh_listen,
                connect: &args.zenoh_connect,
                wait_s: args.relay_wait,
            },
        )
        .await?;
        return Ok((links.vehicle_links(), Backing::Relays(links)));
    }
    let endpoints = mission_endpoints(mission, plan);
    if endpoints.iter().all(Option::is_none) {
        let (links, swarm) = start_bundled_sitl(args, mission, plan, signing_key).await?;
        return Ok((links, Backing::Sitl(swarm)));
    }
    if !args.faults.is_empty() || args.autopilot.is_some() {
        anyhow::bail!(
            "--fault and --autopilot apply to the bundled SITL only, but the mission names endpoints"
        );
    }
    let links = endpoints
        .into_iter()
        .zip(&plan.drones)
        .map(|(e, d)| {
            e.with_context(|| {
                format!(
                    "drone {} has no endpoint (give all drones one, or none)",
                    d.id
                )
            })
        })
        .collect::<anyhow::Result<_>>()?;
    Ok((links, Backing::Endpoints))
}

/// The endpoint the mission gives each drone of `plan` (plan order), if any; a
/// drone without a system id gets its 1-based position in the plan.
fn mission_endpoints(mission: &Mission, plan: &DiscretePlan) -> Vec<Option<VehicleLink>> {
    plan.drones
        .iter()
        .enumerate()
        .map(|(i, d)| {
            mission
                .drones()
                .find(|(_, m)| m.id == d.id)
                .and_then(|(_, m)| {
                    m.endpoint.clone().map(|endpoint| {
                        VehicleLink::mavlink(endpoint, m.system_id.unwrap_or(i as u8 + 1))
                    })
                })
        })
        .collect()
}

/// Starts one bundled SITL vehicle per drone with the `--fault`s, the autopilot
/// `--autopilot` or the mission names, and the signing key if there is one.
async fn start_bundled_sitl(
    args: &Args,
    mission: &Mission,
    plan: &DiscretePlan,
    signing_key: Option<&SigningKey>,
) -> anyhow::Result<(Vec<VehicleLink>, swarmctl_sitl::Swarm)> {
    let flavour = swarmctl_harness::bundled_sitl::flavour(args.autopilot.as_deref(), mission);
    let mut configs = swarmctl_harness::bundled_sitl::vehicle_configs_in(
        mission,
        plan,
        flavour,
        &args.faults,
        frame_source(args),
    )?;
    for c in &mut configs {
        c.signing_key = signing_key.map(SigningKey::bytes);
    }
    let (swarm, links) =
        swarmctl_harness::bundled_sitl::start(configs, mission.link.setpoint_rate_hz).await?;
    eprintln!(
        "started the bundled simulator: {} mock {flavour} {} on 127.0.0.1",
        links.len(),
        if links.len() == 1 {
            "vehicle"
        } else {
            "vehicles"
        }
    );
    Ok((links, swarm))
}

/// Per-vehicle frames unless `--shared-frame`.
fn frame_source(args: &Args) -> fly::FrameSource {
    if args.shared_frame {
        fly::FrameSource::Shared
    } else {
        fly::FrameSource::PerVehicle
    }
}

/// The plan file, refused before anything starts unless it is a valid plan for
/// `mission` whose composition passes the checker and is what the file holds
/// (see `swarmctl::compiled::file`).
fn load_plan(path: &Path, mission: &Mission) -> anyhow::Result<CheckedPlan> {
    Ok(swarmctl::compiled::file::load(path, mission)?)
}

/// Plans the mission now, then composes and checks the plan as `swarmctl plan`
/// does; refused, naming the violation, before anything starts.
fn plan_now(mission: &Mission, deadline_s: f64) -> anyhow::Result<CheckedPlan> {
    let options = plan::PlanOptions {
        deadline: std::time::Duration::try_from_secs_f64(deadline_s)
            .ok()
            .filter(|d| !d.is_zero())
            .context("--deadline must be a positive number of seconds")?,
        ..plan::PlanOptions::default()
    };
    let solution = plan::solve(mission, &options).with_context(|| {
        format!(
            "planning {}{}",
            mission.name,
            super::plan::reach_hint(mission)
        )
    })?;
    let lower_bound_steps = solution.stats.initial_lower_bound_steps;
    compiled::compile_plan(mission, &solution.plan, lower_bound_steps).with_context(|| {
        format!(
            "checking the plan of {} before flight (nothing was started)",
            mission.name
        )
    })
}

/// `flights/<mission file name>-<unix time>.json`: named after the file the user
/// typed (`missions/formation-change.yaml` → `flights/formation-change-….json`),
/// with anything but letters, digits, `-` and `_` replaced.
fn default_log_path(mission_file: &Path) -> PathBuf {
    let unix_s = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let stem = mission_file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mission".into());
    let name: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    PathBuf::from("flights").join(format!("{name}-{unix_s}.json"))
}

/// Opens the flight's Rerun recording (beside the log unless --rrd, --spawn or
/// --connect say otherwise); `None`, with a warning, if it cannot be opened.
fn start_recording(
    args: &Args,
    mission: &Mission,
    plan: &CompiledPlan,
    log_path: &Path,
) -> Option<(LiveFlight, Sink)> {
    let sink = args.viewer.sink_or_beside(log_path);
    match LiveFlight::start(mission, plan, &sink, RecorderOptions::for_sink(&sink)) {
        Ok(recording) => Some((recording, sink)),
        Err(e) => {
            eprintln!("warning: flying without a Rerun recording: {e:#}");
            None
        }
    }
}

/// Removes the recording of a flight that never flew (refused before arming, or
/// failed): a recording with no flight log beside it only misleads. A viewer
/// the recording streamed to keeps what it was sent.
fn discard_recording((recording, sink): (LiveFlight, Sink)) {
    drop(recording);
    if let Sink::File(path) = sink
        && let Err(e) = std::fs::remove_file(&path)
        && e.kind() != std::io::ErrorKind::NotFound
    {
        eprintln!(
            "warning: cannot remove the recording of the refused flight, {}: {e}",
            path.display()
        );
    }
}

/// Finishes the live recording and reports it, with samples dropped to keep the
/// setpoint streams on time.
fn finish_recording((recording, sink): (LiveFlight, Sink), log: &fly::FlightLog) {
    match recording.finish(log) {
        Ok(stats) => println!(
            "  recording            {} ({} samples live, {} dropped)",
            super::replay::describe(&sink),
            stats.samples_logged,
            stats.samples_dropped
        ),
        Err(e) => eprintln!("warning: the Rerun recording is incomplete: {e:#}"),
    }
}
