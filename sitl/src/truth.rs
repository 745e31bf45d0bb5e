//! The simulator's truth: how close the vehicles really came, from their true
//! positions, independent of any telemetry a controller saw (including from
//! vehicles it could no longer hear). One copy, used wherever simulated
//! vehicles are measured: in process (the harness) and carried out of relay
//! processes (the relay's truth watch).

use crate::swarm::Swarm;

/// Below this height (metres above the ground) a vehicle is on the ground, and
/// close pairs on the ground are parked, not a separation loss.
pub const AIRBORNE_M: f32 = 0.1;

/// Whether a vehicle at `position_ned_m` (its true NED position, metres) is in
/// the air.
pub fn is_airborne(position_ned_m: &[f32; 3]) -> bool {
    -position_ned_m[2] > AIRBORNE_M
}

/// The true positions (NED metres) of the airborne vehicles of `swarm`, into
/// `airborne`: a reused buffer, so sampling at 50 Hz allocates nothing.
pub fn airborne_positions(swarm: &Swarm, airborne: &mut Vec<[f32; 3]>) {
    airborne.clear();
    airborne.extend(
        (0..swarm.len())
            .map(|i| swarm.snapshot(i).position_ned_m)
            .filter(is_airborne),
    );
}

/// Smallest distance between two of the `airborne` positions (NED metres), metres;
/// ∞ with fewer than two.
pub fn min_separation_m(airborne: &[[f32; 3]]) -> f64 {
    let mut min_d2 = f32::INFINITY;
    for (k, a) in airborne.iter().enumerate() {
        for b in &airborne[k + 1..] {
            let d: [f32; 3] = std::array::from_fn(|c| a[c] - b[c]);
            min_d2 = min_d2.min(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
    }
    f64::from(min_d2.sqrt())
}

/// Smallest scaled separation among the `airborne` positions (NED metres), where
/// `scaled` gives the scaled distance of one offset between two vehicles (NED
/// metres; the controller's separation ellipsoid, which the simulator does not
/// know); ∞ with fewer than two.
pub fn min_scaled_separation(airborne: &[[f32; 3]], scaled: impl Fn([f64; 3]) -> f64) -> f64 {
    let mut min = f64::INFINITY;
    for (k, a) in airborne.iter().enumerate() {
        for b in &airborne[k + 1..] {
            let delta_m: [f64; 3] = std::array::from_fn(|c| f64::from(a[c] - b[c]));
            min = min.min(scaled(delta_m));
        }
    }
    min
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closest_pair_is_measured_and_one_vehicle_has_none() {
        let up = |x: f32| [x, 0.0, -2.0];
        let d = min_separation_m(&[up(0.0), up(0.7), up(3.0)]);
        assert!((d - 0.7).abs() < 1e-6);
        assert_eq!(min_separation_m(&[up(0.0)]), f64::INFINITY);
        let scaled = min_scaled_separation(&[up(0.0), up(1.0)], |d| d[0].abs() / 2.0);
        assert!((scaled - 0.5).abs() < 1e-9);
        assert!(is_airborne(&up(0.0)) && !is_airborne(&[0.0, 0.0, -0.05]));
    }
}
