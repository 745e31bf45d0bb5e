//! Starting the bundled simulator: one mock vehicle per drone, with the
//! `--fault`s and autopilot asked for, when the mission names no endpoints.

use super::Args;
use swarmctl::fly::VehicleLink;
use swarmctl::link::SigningKey;
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;

/// Starts one bundled SITL vehicle per drone with the `--fault`s, the autopilot
/// `--autopilot` or the mission names, and the signing key if there is one.
pub(super) async fn start_bundled_sitl(
    args: &Args,
    mission: &Mission,
    plan: &DiscretePlan,
    signing_key: Option<&SigningKey>,
) -> anyhow::Result<(Vec<VehicleLink>, swarmctl_sitl::Swarm)> {
    let autopilot = crate::commands::autopilot::chosen(args.autopilot, mission);
    let flavour = swarmctl_bundled::flavour(autopilot);
    let mut configs = swarmctl_bundled::vehicle_configs_in(
        mission,
        plan,
        flavour,
        &args.faults,
        super::args::frame_source(args),
    )?;
    for c in &mut configs {
        c.signing_key = signing_key.map(SigningKey::bytes);
    }
    let (swarm, links) = swarmctl_bundled::start(configs, mission.link.setpoint_rate_hz).await?;
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
