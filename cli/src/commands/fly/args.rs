//! The flags of `swarmctl fly`, and the checks that refuse flags no flight can
//! use before anything is planned, started or recorded.

use anyhow::Context;
use std::path::PathBuf;
use swarmctl::fly;
use swarmctl::mission::Autopilot;
use swarmctl_sitl::FaultSpec;
use swarmctl_sitl::faults::FAULT_HELP;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mission file (YAML), or an instance `swarmctl plan` imports.
    pub(super) mission: PathBuf,
    /// Fly this plan (JSON from `swarmctl plan -o`) instead of planning now.
    #[arg(long)]
    pub(super) plan: Option<PathBuf>,
    /// Autopilot the bundled SITL imitates (default: the mission's `link.autopilot`).
    #[arg(long, value_name = "AUTOPILOT", value_parser = crate::commands::autopilot::parser())]
    pub(super) autopilot: Option<Autopilot>,
    /// Seconds pre-flight waits for every vehicle to report a position and pass its
    /// pre-arm checks (default 60: real autopilots need about 40 s after boot for
    /// EKF and GPS; 5 on the bundled simulator, whose vehicles are ready at once).
    #[arg(long, value_name = "SECONDS")]
    pub(super) ready_timeout: Option<f64>,
    /// Every vehicle reports in the mission's frame (vehicles given a common EKF
    /// origin by hand; the bundled SITL then shares one frame). By default each
    /// vehicle has its own local frame, placed at pre-flight from its GPS origin
    /// (with `world.geo_origin`) or from standing on its pad.
    #[arg(long)]
    pub(super) shared_frame: bool,
    /// Horizontal distance, metres, allowed between where a vehicle is found (its
    /// GPS with `world.geo_origin`, or its report in a shared frame) and its pad.
    #[arg(long, value_name = "METRES", default_value_t = 0.3)]
    pub(super) pad_tolerance: f64,
    // The help text lists every kind; it is the simulator's, which parses them.
    #[arg(long = "fault", value_name = "FAULT", value_parser = parse_fault, help = FAULT_HELP)]
    pub(super) faults: Vec<FaultSpec>,
    /// Flight log (JSON); default flights/<mission file name>-<unix time>.json.
    // The comment above is `--help` text, shown as written: the placeholders
    // are not HTML.
    #[allow(rustdoc::invalid_html_tags)]
    #[arg(long)]
    pub(super) log: Option<PathBuf>,
    /// Planning deadline in seconds (when no --plan is given), its schedule and
    /// check included: the best plan found by then flies, its gap to the lower
    /// bound stated.
    #[arg(long, default_value_t = 60.0)]
    pub(super) deadline: f64,
    /// Fly only a plan proven makespan-optimal (when no --plan is given): fail at
    /// the deadline rather than fly a plan above the lower bound.
    #[arg(long)]
    pub(super) optimal: bool,
    /// Seconds a replan in flight may take (after a drone is lost, or retires and
    /// is down) while every drone holds; past it the flight falls back to holding
    /// the lost drone's dependants while the rest finish and land.
    #[arg(long, value_name = "SECONDS", default_value_t = 3.0)]
    pub(super) replan_deadline: f64,
    /// Replans allowed per flight; later losses fall back.
    #[arg(long, value_name = "COUNT", default_value_t = 3)]
    pub(super) max_replans: usize,
    /// Never replan in flight: a lost drone's dependants hold for the rest of the
    /// flight, the other drones finish and land.
    #[arg(long)]
    pub(super) no_replan: bool,
    /// Print a plain status line every few seconds instead of a spinner.
    #[arg(long)]
    pub(super) plain: bool,
    /// MAVLink 2 signing key file (64 hex digits), overriding the mission's
    /// `link.signing`. The bundled SITL then enforces signatures too.
    #[arg(long, value_name = "FILE")]
    pub(super) signing_key_file: Option<PathBuf>,
    /// How the controller reaches the vehicles: `mavlink` (its own sockets, or
    /// the bundled SITL) or `zenoh` (through `swarmctl relay` processes). Default:
    /// zenoh when the mission has `link.relays`, else mavlink.
    #[arg(long, value_parser = ["mavlink", "zenoh"])]
    pub(super) via: Option<String>,
    /// With --via zenoh: where the controller accepts Zenoh sessions, repeatable
    /// (default: the mission's `link.zenoh.listen`, else tcp/127.0.0.1:7447,
    /// where relays connect by default).
    #[arg(long, value_name = "ENDPOINT")]
    pub(super) zenoh_listen: Vec<String>,
    /// With --via zenoh: routers or relays to connect to, repeatable (default:
    /// the mission's `link.zenoh.connect`).
    #[arg(long, value_name = "ENDPOINT")]
    pub(super) zenoh_connect: Vec<String>,
    /// With --via zenoh: seconds to wait for relays to announce every drone.
    #[arg(long, value_name = "SECONDS", default_value_t = 30.0)]
    pub(super) relay_wait: f64,
    /// Start the plan at this instant, so the flight keeps time with music, a
    /// camera or another system: `+SECONDS` from now, a UTC instant
    /// (`2026-12-05T20:30:00Z`) or a UTC time of day today (`20:30:00`). The swarm
    /// arms `--takeoff-lead` seconds before it and hovers above its pads until
    /// then; a swarm that cannot be ready by then is refused before takeoff.
    #[arg(long, value_name = "TIME")]
    pub(super) start_at: Option<String>,
    /// With --start-at: seconds before the start instant the swarm arms and
    /// takes off (pre-flight must have passed by then).
    #[arg(long, value_name = "SECONDS", default_value_t = fly::StartAt::DEFAULT_TAKEOFF_LEAD.as_secs_f64())]
    pub(super) takeoff_lead: f64,
    /// Connect to every vehicle and run the whole pre-flight (autopilot,
    /// readiness, frame and pad, the autopilot's own limits set and read back,
    /// streams turned down to the link budget), print what is ready and what is
    /// not, and disconnect without arming anyone. Exits 0 only if the swarm
    /// would be allowed to fly.
    #[arg(long)]
    pub(super) dry_run: bool,
    /// Where the Rerun recording goes (default: beside the flight log).
    #[command(flatten)]
    pub(super) viewer: swarmctl_cli::record::ViewerArgs,
}

fn parse_fault(s: &str) -> Result<FaultSpec, String> {
    swarmctl_sitl::parse_fault(s).map_err(|e| e.reason)
}

/// The flags' durations, read once.
pub(super) struct Durations {
    /// `--ready-timeout`, if given.
    pub(super) ready: Option<std::time::Duration>,
    /// `--replan-deadline`.
    pub(super) replan_deadline: std::time::Duration,
    /// `--start-at` with `--takeoff-lead`, if given.
    pub(super) start_at: Option<fly::StartAt>,
}

/// Refuses flags no flight can use, before anything is planned, started or
/// recorded; returns their durations.
pub(super) fn check_args(args: &Args) -> anyhow::Result<Durations> {
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
    let takeoff_lead = seconds(args.takeoff_lead).with_context(|| {
        format!(
            "--takeoff-lead must be a non-negative number of seconds, got {}",
            args.takeoff_lead
        )
    })?;
    let start_at = match &args.start_at {
        Some(text) => {
            let at = super::start_instant::parse(text, std::time::SystemTime::now())
                .map_err(|why| anyhow::anyhow!("--start-at {why}"))?;
            Some(fly::StartAt { at, takeoff_lead })
        }
        None => None,
    };
    Ok(Durations {
        ready,
        replan_deadline,
        start_at,
    })
}

/// Per-vehicle frames unless `--shared-frame`.
pub(super) fn frame_source(args: &Args) -> fly::FrameSource {
    if args.shared_frame {
        fly::FrameSource::Shared
    } else {
        fly::FrameSource::PerVehicle
    }
}
