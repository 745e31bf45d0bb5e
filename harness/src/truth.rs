//! The simulator's truth: what really happened, independent of the telemetry the
//! flight executor saw (including drones it could no longer hear).

use swarmctl::world::Separation;
use swarmctl_sitl::Swarm;

/// Below this height (metres above the ground) a vehicle is on the ground, and
/// close pairs on the ground are parked, not a separation loss.
const AIRBORNE_M: f32 = 0.1;

/// Smallest distance between two airborne vehicles of a bundled-SITL swarm right
/// now, metres, from the simulator's true positions (∞ with fewer than two in the
/// air). `airborne` is a reused buffer, so sampling at 50 Hz allocates nothing;
/// afterwards it holds the airborne positions (NED).
pub fn true_min_separation_m(swarm: &Swarm, airborne: &mut Vec<[f32; 3]>) -> f64 {
    airborne.clear();
    airborne.extend(
        (0..swarm.len())
            .map(|i| swarm.snapshot(i).position_ned_m)
            .filter(|p| -p[2] > AIRBORNE_M),
    );
    let mut min_d2 = f32::INFINITY;
    for (k, a) in airborne.iter().enumerate() {
        for b in &airborne[k + 1..] {
            let d2 = (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2);
            min_d2 = min_d2.min(d2);
        }
    }
    f64::from(min_d2.sqrt())
}

/// Smallest scaled separation under `ellipsoid` among `airborne` positions (NED
/// metres, as [`true_min_separation_m`] leaves them), separated at 1 or more (∞
/// with fewer than two).
pub fn true_min_scaled_separation(airborne: &[[f32; 3]], ellipsoid: &Separation) -> f64 {
    let mut min = f64::INFINITY;
    for (k, a) in airborne.iter().enumerate() {
        for b in &airborne[k + 1..] {
            let delta_m: [f64; 3] = std::array::from_fn(|c| f64::from(a[c] - b[c]));
            min = min.min(ellipsoid.scaled(delta_m));
        }
    }
    min
}
