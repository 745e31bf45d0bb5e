use std::path::PathBuf;
use std::process::ExitCode;
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
            Ok(m) => print_summary(path, &m),
            Err(e) => {
                all_valid = false;
                eprintln!("{e}");
            }
        }
    }
    Ok(if all_valid {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn print_summary(path: &std::path::Path, m: &mission::Mission) {
    let [x, y, z] = m.world.dimensions();
    let lower_bound = plan::makespan_lower_bound(m).map_or_else(
        || "none (no starts, or an unmatched group)".to_string(),
        |lb| format!("{lb} steps"),
    );
    println!("{}: valid mission {:?}", path.display(), m.name);
    println!(
        "  world      {x}×{y}×{z} voxels of {} m, {} free, {} obstacles",
        m.world.voxel_size_m(),
        m.world.free_count(),
        m.world.len() - m.world.free_count()
    );
    let sizes: Vec<String> = m
        .groups
        .iter()
        .map(|g| format!("{} ({})", g.name, g.drones.len()))
        .collect();
    println!("  groups     {}: {}", m.groups.len(), sizes.join(", "));
    println!("  drones     {}", m.drone_count());
    println!("  formation  ≥ {lower_bound} from the starts (lower bound, collisions ignored)");
    super::pads::print_pads_and_legs(m);
}
