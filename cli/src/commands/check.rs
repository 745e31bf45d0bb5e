use std::path::PathBuf;
use std::process::ExitCode;
use swarmctl::link::SigningKey;
use swarmctl::link::budget::{self, Budget};
use swarmctl::{mission, plan};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mission files (YAML) to validate.
    #[arg(required = true)]
    missions: Vec<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mut all_valid = true;
    for path in &args.missions {
        match mission::load(path) {
            // The key `fly` would load: a missing or malformed one is the
            // mission's problem too, and `check` says so first.
            Ok(m) => match m.link.signing.as_ref().map(SigningKey::load) {
                Some(Err(e)) => {
                    all_valid = false;
                    eprintln!("{}: link.signing: {e}", path.display());
                }
                _ => {
                    let budget = Budget::of(&m);
                    let refusals = budget.refusals();
                    if refusals.is_empty() {
                        print_summary(path, &m, &budget);
                    } else {
                        all_valid = false;
                        for r in refusals {
                            eprintln!("{}: link.radios: {r}", path.display());
                        }
                    }
                }
            },
            Err(e) => {
                all_valid = false;
                eprintln!(
                    "{}",
                    swarmctl_cli::error_text::chain(&anyhow::Error::new(e))
                );
            }
        }
    }
    Ok(if all_valid {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn print_summary(path: &std::path::Path, m: &mission::Mission, budget: &Budget) {
    let [x, y, z] = m.world.dimensions();
    let lower_bound = plan::makespan_lower_bound(m).map_or_else(
        || "none (no starts, or an unmatched group)".to_string(),
        |lb| format!("{lb} steps"),
    );
    println!("{}: valid mission {:?}", path.display(), m.name);
    let pad_layer_blocked = m.airspace.obstacles().filter(|v| v.z < 0).count();
    println!(
        "  world      {x}×{y}×{z} voxels of {} m, {} free, {} obstacles; {pad_layer_blocked} pad-layer cells blocked under obstacles{}",
        m.world.voxel_size_m(),
        m.world.free_count(),
        m.world.len() - m.world.free_count(),
        if m.formations_use_pad_layer {
            ""
        } else {
            "; formations keep out of the pad layer"
        }
    );
    let sizes: Vec<String> = m
        .groups
        .iter()
        .map(|g| format!("{} ({})", g.name, g.drones.len()))
        .collect();
    println!("  groups     {}: {}", m.groups.len(), sizes.join(", "));
    println!("  drones     {}", m.drone_count());
    if !m.link.relays.is_empty() {
        let relays: Vec<String> = m
            .link
            .relays
            .iter()
            .map(|r| format!("{} ({} drones)", r.name, r.drones.len()))
            .collect();
        println!(
            "  relays     {} over Zenoh: {}",
            relays.len(),
            relays.join(", ")
        );
    }
    println!("  separation {}", separation_text(m));
    print_budget(budget);
    print_fence(m);
    println!("  formation  ≥ {lower_bound} from the starts (lower bound, collisions ignored)");
    super::pads::print_pads_and_legs(m);
}

/// The geofence each autopilot will be given at pre-flight: the circle around
/// each pad and the ceiling above it, over the whole swarm.
fn print_fence(m: &mission::Mission) {
    let Some(plan) = swarmctl::fly::FencePlan::of(m) else {
        println!("  fence      off (fence.enabled: false): each autopilot keeps its own");
        return;
    };
    let fences: Vec<_> = m
        .groups
        .iter()
        .flat_map(|g| &g.drones)
        .map(|d| {
            let pad = m
                .world
                .center_m(swarmctl::world::Voxel::new(d.pad[0], d.pad[1], 0));
            plan.for_pad([pad.x, pad.y, 0.0])
        })
        .collect();
    if let Some(span) = swarmctl::fly::FenceSpan::of(&fences) {
        println!(
            "  fence      airspace + {:.1} m: {span}; on a breach the autopilot does: {}",
            plan.margin_m, plan.action
        );
    }
}

/// The link budget: each drone's steady traffic each way, message by message,
/// and each radio's load against what it can carry.
fn print_budget(budget: &Budget) {
    let d = &budget.per_drone;
    println!(
        "  link       per drone {:.1} kbit/s up + {:.1} kbit/s down = {:.1} kbit/s at {} Hz setpoints and telemetry",
        d.up_kbps(),
        d.down_kbps(),
        d.total_kbps(),
        budget.setpoint_rate_hz
    );
    for (way, flows) in [("up  ", &d.up), ("down", &d.down)] {
        let parts: Vec<String> = flows
            .iter()
            .map(|f| format!("{} {} B × {} Hz", f.message, f.frame_bytes, f.rate_hz))
            .collect();
        println!("             {way} {}", parts.join(", "));
    }
    for r in &budget.radios {
        println!(
            "  radio      {}: {} drones, {:.1} of {:.1} kbit/s usable ({:.0} % of its {} kbit/s)",
            r.name,
            r.drones,
            r.load_kbps,
            r.usable_kbps,
            budget::RADIO_USABLE_FRACTION * 100.0,
            r.capacity_kbps
        );
    }
    if budget.own_links > 0 {
        println!(
            "  own links  {} drones on no radio (Wi-Fi, loopback): not limited by the budget",
            budget.own_links
        );
    }
}

/// The separation the mission keeps, with the setpoints' and, under an ellipsoid,
/// how far its vertical reach goes.
fn separation_text(m: &mission::Mission) -> String {
    let l = &m.limits;
    let sep = l.separation();
    let grown = l.setpoint_separation();
    if !l.is_ellipsoid() {
        return format!(
            "sphere of {:.3} m (setpoints {:.3} m apart with a tracking error of {:.3} m)",
            sep.horizontal_m, grown.horizontal_m, l.tracking_error_m
        );
    }
    let reach = l.vertical_reach(&m.airspace);
    let stacking = if reach.is_trivial(&m.airspace) {
        "no two cells of a column within reach".to_string()
    } else {
        format!(
            "cells of a column closer than {:.3} m are never held at once",
            reach.reach_m
        )
    };
    format!(
        "ellipsoid {:.3} m beside × {:.3} m above and below (setpoints {:.3} × {:.3} m with a tracking error of {:.3} m; {stacking})",
        sep.horizontal_m, sep.vertical_m, grown.horizontal_m, grown.vertical_m, l.tracking_error_m
    )
}
