//! One file per subcommand: argument struct and the code that reports its result;
//! `autopilot` is the one flag type two subcommands share.

pub mod autopilot;
pub mod bench;
pub mod bench_flight;
pub mod bench_peers;
pub mod bench_relays;
pub mod check;
pub mod fly;
pub mod fly_relays;
pub mod generate;
pub mod pads;
pub mod plan;
pub mod relay;
pub mod replay;
pub mod sitl;
pub mod template;

/// A `--fault` naming a drone the mission does not have is a usage error, like a
/// malformed one (exit code 2): says which, with the drones there are.
pub fn refuse_unknown_fault_drones(
    faults: &[swarmctl_sitl::FaultSpec],
    mission: &swarmctl::mission::Mission,
) -> Option<std::process::ExitCode> {
    let known: Vec<&str> = mission.drones().map(|(_, d)| d.id.as_str()).collect();
    let unknown = swarmctl_sitl::faults::unknown_drone(faults, &known)?;
    let shown = if known.len() > 12 {
        format!("{}, … ({} in all)", known[..12].join(", "), known.len())
    } else {
        known.join(", ")
    };
    eprintln!(
        "error: --fault names drone {unknown:?}, which is not in the mission (drones: {shown})"
    );
    Some(std::process::ExitCode::from(2))
}
