//! The pad table and the legs of a mission, as `swarmctl check` and `plan` print them:
//! where an operator places each drone, and what the flight will fly.

use swarmctl::mission::{Landing, Mission, PadSource};

/// Prints the legs, then one line per drone: its pad cell, the pad's ENU position
/// on the ground, and how the pad was chosen.
pub fn print_pads_and_legs(m: &Mission) {
    let legs: Vec<String> = m
        .legs()
        .iter()
        .map(|l| {
            if l.hold_s > 0.0 {
                format!("{} (hold {} s)", l.name, l.hold_s)
            } else {
                l.name.clone()
            }
        })
        .collect();
    let landing = match m.landing {
        Landing::GroupPads => "each on a pad of its group",
        Landing::OwnPad => "each on its own pad",
        Landing::BelowGoal => "straight down from the last goal",
    };
    println!("  legs       {} (landing {landing})", legs.join(" → "));
    let count = |source: PadSource| m.drones().filter(|(_, d)| d.pad_source == source).count();
    println!(
        "  pads       {} on the ground, pad layer at {:.2} m ({} given, {} below their start, {} assigned)",
        m.drone_count(),
        m.pad_height_m(),
        count(PadSource::Given),
        count(PadSource::BelowStart),
        count(PadSource::Assigned)
    );
    let width = m.drones().map(|(_, d)| d.id.len()).max().unwrap_or(0);
    for (_, d) in m.drones() {
        let [east_m, north_m, _] = m.pad_ground_m(d);
        println!(
            "    {:<width$}  pad [{}, {}]  at E {east_m:.2} m, N {north_m:.2} m  ({})",
            d.id, d.pad[0], d.pad[1], d.pad_source
        );
    }
}
