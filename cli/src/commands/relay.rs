//! `swarmctl relay`: serve some of a mission's drones to a controller over
//! Zenoh — their own vehicles (the mission's endpoints), or bundled simulated
//! ones standing on their pads (`--sitl`) — until Ctrl-C or SIGTERM.

use anyhow::Context;
use std::path::PathBuf;
use std::process::ExitCode;
use swarmctl::link::SigningKey;
use swarmctl::mission::Autopilot;
use swarmctl::mission::Mission;
use swarmctl_relay::truth::{self, TruthRecord};
use swarmctl_relay::{Relay, RelaySpec, RelayedDrone, ZenohEndpoints};
use swarmctl_sitl::FaultSpec;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mission file (YAML).
    mission: PathBuf,
    /// This relay's name; it serves the drones the mission's `link.relays` gives
    /// it, unless --drones says otherwise.
    #[arg(long)]
    name: String,
    /// The drones to serve, comma-separated (default: the mission's
    /// `link.relays` entry named --name).
    #[arg(long, value_delimiter = ',', value_name = "ID,ID,…")]
    drones: Vec<String>,
    /// Run one bundled simulated vehicle per drone, standing on its pad, instead
    /// of reaching the mission's endpoints (a whole topology on one machine).
    #[arg(long)]
    sitl: bool,
    /// Autopilot the bundled SITL imitates (default: the mission's `link.autopilot`).
    #[arg(long, value_name = "AUTOPILOT", value_parser = super::autopilot::parser(), requires = "sitl")]
    autopilot: Option<Autopilot>,
    /// Bundled SITL fault, repeatable, as `swarmctl fly --fault` (for this
    /// relay's drones).
    #[arg(long = "fault", value_name = "FAULT", value_parser = parse_fault, requires = "sitl")]
    faults: Vec<FaultSpec>,
    /// Zenoh endpoint to connect to, repeatable: the controller, a zenohd router,
    /// or another relay (default: tcp/127.0.0.1:7447, where `fly --via zenoh`
    /// listens by default). Retried in the background until it answers.
    #[arg(long, value_name = "ENDPOINT")]
    connect: Vec<String>,
    /// Zenoh endpoint to accept sessions on, repeatable (default: none).
    #[arg(long, value_name = "ENDPOINT")]
    listen: Vec<String>,
    /// With --sitl: publish the simulated vehicles' true states this many times
    /// a second, so tests and benchmarks measure separation from the truth
    /// (0: never).
    #[arg(long, value_name = "HZ", default_value_t = 20.0, requires = "sitl")]
    truth_hz: f64,
    /// Write what the relay carried (and, with --sitl, the setpoint intervals the
    /// vehicles received) to this JSON file when it stops.
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
}

fn parse_fault(s: &str) -> Result<FaultSpec, String> {
    swarmctl_sitl::parse_fault(s).map_err(|e| e.reason)
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mission = swarmctl::mission::load(&args.mission)?;
    if let Some(usage) = super::refuse_unknown_fault_drones(&args.faults, &mission) {
        return Ok(usage);
    }
    let drones = served_drones(&args, &mission)?;
    let runtime = tokio::runtime::Runtime::new().context("starting the async runtime")?;
    runtime.block_on(serve(&args, &mission, drones))?;
    Ok(ExitCode::SUCCESS)
}

/// The drones this relay serves: --drones, or the mission's entry for --name.
fn served_drones(args: &Args, mission: &Mission) -> anyhow::Result<Vec<String>> {
    if !args.drones.is_empty() {
        return Ok(args.drones.clone());
    }
    let entry = mission
        .link
        .relays
        .iter()
        .find(|r| r.name == args.name)
        .with_context(|| {
            let names: Vec<&str> = mission.link.relays.iter().map(|r| r.name.as_str()).collect();
            if names.is_empty() {
                format!(
                    "{}: no link.relays section, so relay {} does not know its drones: give --drones ID,ID,…",
                    args.mission.display(),
                    args.name
                )
            } else {
                format!(
                    "{}: link.relays has no relay named {} (it has {}); give --name one of them, or --drones",
                    args.mission.display(),
                    args.name,
                    names.join(", ")
                )
            }
        })?;
    Ok(entry.drones.clone())
}

/// Runs the relay until Ctrl-C or SIGTERM.
async fn serve(args: &Args, mission: &Mission, ids: Vec<String>) -> anyhow::Result<()> {
    let signing = mission
        .link
        .signing
        .as_ref()
        .map(SigningKey::load)
        .transpose()?;
    let (drones, swarm) = if args.sitl {
        let (drones, swarm) = start_sitl(args, mission, &ids, signing.as_ref()).await?;
        (drones, Some(swarm))
    } else {
        (mission_endpoints(args, mission, &ids)?, None)
    };
    let zenoh = ZenohEndpoints {
        role: swarmctl_relay::Role::Client,
        listen: args.listen.clone(),
        connect: if args.connect.is_empty() && args.listen.is_empty() {
            ZenohEndpoints::relay_default().connect
        } else {
            args.connect.clone()
        },
    };
    let described = zenoh.describe();
    println!(
        "relay {}: waiting for the controller (Zenoh: {described})",
        args.name
    );
    let relay = Relay::start(RelaySpec {
        name: args.name.clone(),
        mission: mission.name.clone(),
        drones,
        signing,
        zenoh,
    })
    .await?;
    let truth_task = match (&swarm, args.truth_hz > 0.0) {
        (Some(swarm), true) => {
            Some(publish_truth(&relay, swarm.clone(), &ids, args.truth_hz).await?)
        }
        _ => None,
    };
    println!(
        "relay {}: serving {} drones ({}){} for mission {:?}; Zenoh: {described}",
        args.name,
        ids.len(),
        ids.join(", "),
        if args.sitl {
            " on the bundled SITL"
        } else {
            ""
        },
        mission.name,
    );
    wait_for_stop().await;
    if let Some(t) = truth_task {
        t.abort();
    }
    let report = RelayReport::read(&relay, swarm.as_deref());
    relay.close().await;
    if let Some(swarm) = swarm
        && let Ok(swarm) = std::sync::Arc::try_unwrap(swarm)
    {
        swarm.shutdown().await;
    }
    println!("relay {}: stopped; {}", args.name, report.line());
    if let Some(path) = &args.report {
        std::fs::write(path, serde_json::to_string_pretty(&report)?)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}

/// Each drone's endpoint and system id from the mission (required without --sitl).
fn mission_endpoints(
    args: &Args,
    mission: &Mission,
    ids: &[String],
) -> anyhow::Result<Vec<RelayedDrone>> {
    ids.iter()
        .enumerate()
        .map(|(i, id)| {
            let (_, d) = mission
                .drones()
                .find(|(_, d)| d.id == *id)
                .with_context(|| format!("{}: no drone {id} in the mission", args.mission.display()))?;
            let endpoint = d.endpoint.clone().with_context(|| {
                format!(
                    "{}: drone {id} has no endpoint for relay {} to reach it (or run bundled vehicles with --sitl)",
                    args.mission.display(),
                    args.name
                )
            })?;
            Ok(RelayedDrone {
                id: id.clone(),
                endpoint,
                system_id: d.system_id.unwrap_or(i as u8 + 1),
            })
        })
        .collect()
}

/// Starts one bundled vehicle per drone on its pad (loopback, ephemeral ports).
async fn start_sitl(
    args: &Args,
    mission: &Mission,
    ids: &[String],
    signing: Option<&SigningKey>,
) -> anyhow::Result<(Vec<RelayedDrone>, std::sync::Arc<swarmctl_sitl::Swarm>)> {
    let flavour = swarmctl_bundled::flavour(super::autopilot::chosen(args.autopilot, mission));
    let mut configs = swarmctl_bundled::relay_vehicle_configs(mission, ids, flavour, &args.faults)?;
    for c in &mut configs {
        c.signing_key = signing.map(SigningKey::bytes);
    }
    let (swarm, links) = swarmctl_bundled::start(configs, mission.link.setpoint_rate_hz).await?;
    let drones = ids
        .iter()
        .zip(links)
        .map(|(id, link)| RelayedDrone {
            id: id.clone(),
            endpoint: link.endpoint,
            system_id: link.system_id,
        })
        .collect();
    Ok((drones, std::sync::Arc::new(swarm)))
}

/// Publishes the bundled vehicles' true states on the relay's truth key.
async fn publish_truth(
    relay: &Relay,
    swarm: std::sync::Arc<swarmctl_sitl::Swarm>,
    ids: &[String],
    rate_hz: f64,
) -> anyhow::Result<tokio::task::JoinHandle<()>> {
    let ids = ids.to_vec();
    let sample = move || {
        ids.iter()
            .enumerate()
            .map(|(i, id)| {
                let s = swarm.snapshot(i);
                TruthRecord {
                    drone: id.clone(),
                    position_ned_m: s.position_ned_m,
                    velocity_ned_mps: s.velocity_ned_mps,
                }
            })
            .collect()
    };
    Ok(truth::publish(relay.session(), relay.keys(), relay.name(), rate_hz, sample).await?)
}

/// Ctrl-C, or SIGTERM (how a test or a service manager stops a relay).
async fn wait_for_stop() {
    let mut term = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()).ok();
    let terminated = async {
        match term.as_mut() {
            Some(t) => {
                t.recv().await;
            }
            None => std::future::pending::<()>().await,
        }
    };
    tokio::select! {
        _ = tokio::signal::ctrl_c() => {}
        () = terminated => {}
    }
}

/// What a relay carried, for `--report`.
#[derive(Debug, serde::Serialize)]
struct RelayReport {
    relay: String,
    drones: usize,
    frames_to_vehicles: u64,
    frames_from_vehicles: u64,
    /// Setpoint intervals as the bundled vehicles received them, milliseconds.
    /// (What the process costs, CPU and memory, whoever started it measures as
    /// the kernel counts it: the relay load benchmark does, when it exits.)
    setpoint_interval_ms: Option<Intervals>,
}

#[derive(Debug, serde::Serialize)]
struct Intervals {
    count: u64,
    p50_ms: f64,
    p99_ms: f64,
    max_ms: f64,
}

impl RelayReport {
    fn read(relay: &Relay, swarm: Option<&swarmctl_sitl::Swarm>) -> Self {
        let carried = relay.carried();
        let setpoint_interval_ms = swarm.map(|swarm| {
            let mut all = swarmctl_sitl::swarm::SetpointIntervals::default();
            for i in 0..swarm.len() {
                all.merge(&swarm.setpoint_intervals(i));
            }
            Intervals {
                count: all.count(),
                p50_ms: all.quantile_s(0.5) * 1e3,
                p99_ms: all.quantile_s(0.99) * 1e3,
                max_ms: all.max_s() * 1e3,
            }
        });
        Self {
            relay: relay.name().to_string(),
            drones: carried.len(),
            frames_to_vehicles: carried.iter().map(|c| c.to_vehicle).sum(),
            frames_from_vehicles: carried.iter().map(|c| c.from_vehicle).sum(),
            setpoint_interval_ms,
        }
    }

    fn line(&self) -> String {
        let intervals = self
            .setpoint_interval_ms
            .as_ref()
            .map_or(String::new(), |i| {
                format!(
                    "; setpoint intervals p50/p99/max {:.1}/{:.1}/{:.1} ms over {}",
                    i.p50_ms, i.p99_ms, i.max_ms, i.count
                )
            });
        format!(
            "carried {} frames to and {} from {} vehicles{intervals}",
            self.frames_to_vehicles, self.frames_from_vehicles, self.drones
        )
    }
}
