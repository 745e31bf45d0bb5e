//! `swarmctl fly --dry-run`: the whole pre-flight on every vehicle, a line per
//! drone saying what is ready and what is not, the link budget, and no arming.

use super::{Args, Durations, Flight, prepare};
use std::process::ExitCode;
use swarmctl::fly::{self, DryRun, FrameFix};

/// Runs the dry run and reports it; exit 0 only if the swarm would fly.
pub(super) async fn run(
    args: &Args,
    durations: &Durations,
    flight: Flight<'_>,
) -> anyhow::Result<ExitCode> {
    let Flight {
        mission,
        checked,
        plan,
    } = flight;
    let (options, backing) = prepare(args, durations, mission, plan).await?;
    eprintln!(
        "dry run: pre-flight on {} vehicles, nobody will be armed",
        options.vehicles.len()
    );
    let result = fly::dry_run(mission, checked, &options).await;
    backing.shutdown().await;
    let dry = result?;
    print_dry_run(&mission.name, &dry);
    Ok(if dry.ready() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn print_dry_run(mission: &str, dry: &DryRun) {
    println!("{mission}: dry run, nobody armed");
    for d in &dry.drones {
        match &d.readiness {
            Ok(v) => {
                let [e, n, u] = v.local_origin_enu_m.map(centimetres);
                let kept = if v.streams_still_on.is_empty() {
                    String::new()
                } else {
                    format!(
                        "; still streaming message ids {:?} (they spend link capacity)",
                        v.streams_still_on
                    )
                };
                let fence = match &v.fence {
                    Some(fence) => format!("fence {fence} (set, read back, left set)"),
                    None => "fence left as it was (fence.enabled: false)".to_string(),
                };
                println!(
                    "  {:<8} ready      {}, frame {}, local origin E {e} N {n} U {u} m, {} default streams turned off{kept}; {fence}",
                    d.id,
                    v.autopilot,
                    frame_text(v.frame),
                    v.streams_off.len()
                );
            }
            Err(why) => println!("  {:<8} NOT READY  {why}", d.id),
        }
    }
    let b = &dry.budget;
    println!(
        "  link     {:.1} kbit/s up + {:.1} kbit/s down per drone at {} Hz",
        b.per_drone.up_kbps(),
        b.per_drone.down_kbps(),
        b.setpoint_rate_hz
    );
    for r in &b.radios {
        println!(
            "  radio    {}: {} drones, {:.1} of {:.1} kbit/s usable{}",
            r.name,
            r.drones,
            r.load_kbps,
            r.usable_kbps,
            if r.fits() { "" } else { ": OVER" }
        );
    }
    for refusal in b.refusals() {
        println!("  {refusal}");
    }
    let not_ready: Vec<&str> = dry
        .drones
        .iter()
        .filter(|d| d.readiness.is_err())
        .map(|d| d.id.as_str())
        .collect();
    if dry.ready() {
        println!(
            "dry run: the swarm would fly ({0} of {0} ready)",
            dry.drones.len()
        );
    } else if not_ready.is_empty() {
        println!("dry run: the swarm would NOT fly: its radios cannot carry it");
    } else {
        println!(
            "dry run: the swarm would NOT fly: {} of {} not ready ({})",
            not_ready.len(),
            dry.drones.len(),
            not_ready.join(", ")
        );
    }
}

/// Metres to the centimetre, a value that rounds to zero printed as 0.00 (not -0.00).
fn centimetres(m: f64) -> String {
    // Adding +0.0 turns the -0.0 that rounding leaves into 0.0.
    format!("{:.2}", (m * 100.0).round() / 100.0 + 0.0)
}

fn frame_text(fix: FrameFix) -> &'static str {
    match fix {
        FrameFix::Shared => "shared with the mission",
        FrameFix::GpsOrigin => "from its GPS origin",
        FrameFix::HomePosition => "from its home position",
        FrameFix::Placement => "from standing on its pad",
    }
}
