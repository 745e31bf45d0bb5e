//! What the simulated vehicles saw of the flight, read before they shut down.

use super::AT_GOAL_TOLERANCE_M;
use swarmctl::link::frames;
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;
use swarmctl_sitl::swarm::SetpointIntervals;
use swarmctl_sitl::{LinkStats, Swarm};

/// The vehicles' side of the flight: setpoint timing, link counters, and where
/// each ended up (simulator truth).
pub(super) struct VehiclesAfter {
    /// Every vehicle's setpoint intervals together.
    pub setpoints: SetpointIntervals,
    /// The worst single vehicle's p99 interval, seconds.
    pub worst_vehicle_p99_s: f64,
    /// Link counters summed over the vehicles.
    pub link: LinkStats,
    /// System ids still armed.
    pub still_armed: Vec<u8>,
    /// Vehicles landed, disarmed, within [`AT_GOAL_TOLERANCE_M`] of below their goal.
    pub at_goal: usize,
    /// Largest horizontal distance of a vehicle from below its goal, metres.
    pub max_goal_error_m: f64,
}

impl VehiclesAfter {
    /// Reads every vehicle of `swarm` (plan order: vehicle `i` flies drone `i`).
    pub fn read(swarm: &Swarm, mission: &Mission, plan: &DiscretePlan) -> Self {
        let mut after = Self {
            setpoints: SetpointIntervals::default(),
            worst_vehicle_p99_s: 0.0,
            link: LinkStats::default(),
            still_armed: Vec::new(),
            at_goal: 0,
            max_goal_error_m: 0.0,
        };
        for (i, drone) in plan.drones.iter().enumerate() {
            let intervals = swarm.setpoint_intervals(i);
            after.worst_vehicle_p99_s = after.worst_vehicle_p99_s.max(intervals.quantile_s(0.99));
            after.setpoints.merge(&intervals);
            let s = swarm.snapshot(i);
            add_link_stats(&mut after.link, &s.link);
            if s.armed {
                after.still_armed.push(s.system_id);
            }
            let goal = mission.airspace.center_m(drone.goal);
            let below_goal = frames::ned_f32_from_enu([goal.x, goal.y, 0.0]);
            let error_m = f64::from(
                ((s.position_ned_m[0] - below_goal[0]).powi(2)
                    + (s.position_ned_m[1] - below_goal[1]).powi(2))
                .sqrt(),
            );
            after.max_goal_error_m = after.max_goal_error_m.max(error_m);
            if !s.armed && s.landed && error_m <= AT_GOAL_TOLERANCE_M {
                after.at_goal += 1;
            }
        }
        after
    }
}

/// Adds one vehicle's link counters to `sum`.
fn add_link_stats(sum: &mut LinkStats, s: &LinkStats) {
    sum.rx_datagrams += s.rx_datagrams;
    sum.rx_dropped_by_fault += s.rx_dropped_by_fault;
    sum.rx_duplicated += s.rx_duplicated;
    sum.rx_reordered += s.rx_reordered;
    sum.rx_messages += s.rx_messages;
    sum.rx_bad_signature += s.rx_bad_signature;
    sum.rx_undecodable += s.rx_undecodable;
    sum.tx_datagrams += s.tx_datagrams;
    sum.tx_dropped_by_fault += s.tx_dropped_by_fault;
    sum.tx_duplicated += s.tx_duplicated;
    sum.tx_reordered += s.tx_reordered;
    sum.tx_errors += s.tx_errors;
}
