//! The autopilots' own geofence on the bundled simulator: pre-flight sets it on
//! every vehicle from the mission; a rogue ground station that takes a drone out
//! of swarmctl's reach is stopped by the vehicle's own fence (by the simulator's
//! truth), and one that takes a drone swarmctl still hears out of the airspace
//! has it landed there by swarmctl, reported, while the rest fly on.

use crate::fly_common::load;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;
use swarmctl::fly::{self, FencePlan};
use swarmctl_sitl::Flavour;
use swarmctl_sitl::faults::parse_fault;

const LIMIT: Duration = Duration::from_secs(150);

/// How far past its fence a vehicle may go before its autopilot's action has
/// stopped it, metres: the braking distance from the mission's speed limit at its
/// acceleration limit (1 m/s at 2 m/s²: 0.25 m), with room for one control step.
fn stopping_distance_m(mission: &swarmctl::mission::Mission) -> f64 {
    let l = &mission.limits;
    l.max_speed_mps.powi(2) / (2.0 * l.max_accel_mps2) + 0.1
}

/// What a flight with a rogue b1 came to: the log, and from the simulator's
/// truth how far b1 went from where it armed and the closest two airborne
/// vehicles came.
struct Rogue {
    log: fly::FlightLog,
    farthest_m: f64,
    min_separation_m: f64,
    /// b1's fence radius, metres.
    radius_m: f64,
}

/// Flies the formation change with `faults`, watching b1's truth at 50 Hz.
async fn fly_rogue(flavour: Flavour, faults: &[&str]) -> Rogue {
    let (mission, plan) = load("missions/formation-change.yaml");
    let fence = FencePlan::of(&mission).expect("the fence is on by default");
    let rogue = plan
        .drones
        .iter()
        .position(|d| d.id == "b1")
        .expect("b1 in the plan");
    let faults: Vec<_> = faults
        .iter()
        .map(|f| parse_fault(f).expect("fault flag"))
        .collect();
    let configs =
        swarmctl_bundled::vehicle_configs(&mission, &plan, flavour, &faults).expect("configs");
    let (swarm, links) = swarmctl_bundled::start(configs, mission.link.setpoint_rate_hz)
        .await
        .expect("sitl");
    let options = swarmctl_bundled::fly_options(links);
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let done = AtomicBool::new(false);
    let flight = async {
        let result =
            tokio::time::timeout(LIMIT, fly::fly(&mission, &plan, &options, abort_rx)).await;
        done.store(true, Ordering::Relaxed);
        result
    };
    let watch = async {
        let home = swarm.snapshot(rogue).position_ned_m;
        let mut farthest_m = 0.0f64;
        let mut min_separation_m = f64::INFINITY;
        let mut airborne = Vec::new();
        while !done.load(Ordering::Relaxed) {
            let p = swarm.snapshot(rogue).position_ned_m;
            farthest_m = farthest_m.max(f64::from(p[0] - home[0]).hypot(f64::from(p[1] - home[1])));
            swarmctl_sitl::truth::airborne_positions(&swarm, &mut airborne);
            min_separation_m =
                min_separation_m.min(swarmctl_sitl::truth::min_separation_m(&airborne));
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        (farthest_m, min_separation_m)
    };
    let (result, (farthest_m, min_separation_m)) = tokio::join!(flight, watch);
    // The fenced vehicle lands and disarms by itself: give it the time.
    let deadline = std::time::Instant::now() + Duration::from_secs(30);
    while swarm.snapshot(rogue).armed && std::time::Instant::now() < deadline {
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    let still_armed = swarm.armed_system_ids();
    swarm.shutdown().await;
    let log = result
        .expect("flight finished within its time limit")
        .expect("flight");
    for e in &log.events {
        eprintln!("{:6.1} s {:?} {}", e.t_s, e.drone, e.message);
    }
    for line in log.summary.lines() {
        eprintln!("{line}");
    }
    assert!(still_armed.is_empty(), "still armed: {still_armed:?}");
    assert!(
        log.events.iter().any(|e| e
            .message
            .starts_with("fence set and read back on 8 vehicles")),
        "fence event: {:?}",
        log.events
    );
    assert!(
        min_separation_m >= mission.limits.safety_distance_m,
        "truth separation {min_separation_m:.3} m"
    );
    let b1 = mission
        .groups
        .iter()
        .flat_map(|g| &g.drones)
        .find(|d| d.id == "b1")
        .expect("b1");
    let pad = mission
        .world
        .center_m(swarmctl::world::Voxel::new(b1.pad[0], b1.pad[1], 0));
    let radius_m = fence.for_pad([pad.x, pad.y, 0.0]).radius_m;
    eprintln!(
        "{flavour:?}: b1 farthest {farthest_m:.2} m from home by truth (fence {radius_m:.2} m); truth separation {min_separation_m:.3} m"
    );
    assert!(
        farthest_m <= radius_m + stopping_distance_m(&mission),
        "within its fence: {farthest_m:.2} m > {radius_m:.2} m + {:.2} m",
        stopping_distance_m(&mission)
    );
    Rogue {
        log,
        farthest_m,
        min_separation_m,
        radius_m,
    }
}

/// The case the fence is for: b1's link to swarmctl is gone and a rogue ground
/// station sends it away. swarmctl cannot see it (LOST, the rest replanned
/// around where it was last heard); its own fence lands it at the fence.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_rogue_px4_out_of_reach_is_landed_by_its_own_fence() {
    let flight = fly_rogue(Flavour::Px4, &["lose=b1@8s", "rogue=b1@8s"]).await;
    assert!(
        flight.farthest_m > flight.radius_m - 0.5,
        "it flew to its fence: {:.2} m of {:.2} m",
        flight.farthest_m,
        flight.radius_m
    );
    let s = &flight.log.summary;
    assert_eq!(s.lost, ["b1"], "swarmctl lost it: {:?}", s.lost);
    assert!(flight.min_separation_m.is_finite());
}

/// A rogue ground station takes b1 while swarmctl still hears it: once it is
/// outside the airspace beyond the tracking bound, swarmctl says so, puts it in
/// its land mode where it is — below it nobody's airspace — and flies the rest
/// to the end; it never reaches its fence.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_rogue_arducopter_in_reach_is_landed_outside_the_airspace() {
    let flight = fly_rogue(Flavour::ArduPilot, &["rogue=b1@8s"]).await;
    let log = &flight.log;
    assert!(
        log.events.iter().any(|e| e.drone.as_deref() == Some("b1")
            && e.message.starts_with("left the airspace")),
        "reported: {:?}",
        log.events
    );
    assert!(
        flight.farthest_m < flight.radius_m,
        "landed before its fence: {:.2} m",
        flight.farthest_m
    );
    assert_eq!(log.summary.retired, ["b1"]);
    assert!(log.summary.lost.is_empty() && log.summary.handed_over.is_empty());
}
