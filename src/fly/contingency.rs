//! What the swarm does when one drone can no longer fly its plan: its link is gone
//! for good, or its battery runs low, or its autopilot's failsafe takes over.
//!
//! The plan graph already makes the drones that depend on a missing drone wait at
//! their gates (its events are never observed), so the rest of the swarm keeps
//! flying everything that does not need it. What this module adds is leaving the
//! plan safely:
//!
//! - **Lost** (no message for the mission's `link.lost_after_s`): reported, left to its own
//!   failsafe, which must be position hold (see the README). If every other drone
//!   is at its goal or held at a gate, the flight ends: each lands when its
//!   column is clear, and one that cannot (the lost drone was last seen below or
//!   above it: silent, it may have crashed into the column) is put in the
//!   autopilot's hold mode and reported for manual control.
//! - **Low battery** ([`LOW_BATTERY_PCT`] or less): the drone stops at once, the
//!   whole swarm pauses (everyone brakes to rest along its path, where the plan
//!   graph keeps them safe), and the drone descends once nothing is below it.
//!   On the ground — below the voxel world — it can block nobody, so its events
//!   are released and the swarm resumes without it.
//! - **Autopilot failsafe** (the vehicle switched itself to land or return): we
//!   do not fight it. The swarm pauses until it has landed, then resumes as above.
//! - **Left the airspace** (by telemetry, beyond the tracking bound: its own
//!   geofence stopped it out there, or a rogue ground station or a flyaway took
//!   it): it can no longer fly its plan. Beside the airspace, below it is
//!   nobody's airspace: it is put in its autopilot's land mode where it is
//!   (unless its fence already landed it) and retired like an autopilot
//!   failsafe. Above it, its column crosses the swarm's: it comes down like a
//!   low-battery drone, once the swarm is at rest and its column is clear. The
//!   swarm pauses while it comes down.

use super::drone::DroneRun;
use super::follower::Hold;
use super::log::LogEvent;
use super::phase::Phase;
pub use super::phase::{RetireStage, Retirement};
use super::settings::LoopSettings;

/// Battery at or below this share (SYS_STATUS battery_remaining) ends its plan.
pub const LOW_BATTERY_PCT: i8 = 25;
/// Horizontal clearance margin over the safety distance for a vertical descent.
const COLUMN_MARGIN_M: f64 = 0.1;
/// Below this height, by telemetry, a drone is on the ground (the simulator
/// judges its truth with its own threshold, `swarmctl_sitl::truth`).
const ON_GROUND_BELOW_M: f64 = 0.1;
/// A drone at rest moves slower than this in telemetry.
const AT_REST_MPS: f64 = 0.1;
/// How long to let the swarm move before trying again to clear a blocked descent.
const COLUMN_RETRY_S: f64 = 5.0;

/// Horizontal distance between two ENU points, metres.
fn horizontal_m(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Whether the swarm must be at rest this tick: a retiring drone is about to
/// descend, or its autopilot is bringing it down.
pub fn swarm_paused(drones: &[DroneRun]) -> bool {
    drones.iter().any(descending_out_of_plan)
}

/// A retiring drone that is about to come down, or is being brought down.
fn descending_out_of_plan(d: &DroneRun) -> bool {
    matches!(
        d.phase(),
        Phase::Retiring {
            stage: RetireStage::Halting | RetireStage::AutopilotLanding,
        }
    ) || matches!(d.phase(), Phase::Landing { .. } if d.retired().is_some())
}

/// Whether drone `i` must be at rest this tick: the swarm is paused
/// ([`swarm_paused`]) and `i` is not under a drone coming down. One that is under
/// it keeps flying its plan (its gates still hold it), out of the column: an
/// autopilot's failsafe lands where the vehicle is, whatever is below, and pausing
/// there would wait for it to come down on top.
pub fn paused_for(drones: &[DroneRun], i: usize, safety_distance_m: f64) -> bool {
    let Some(p) = drones.get(i).and_then(DroneRun::position_m) else {
        return swarm_paused(drones);
    };
    let mut paused = false;
    for (j, other) in drones.iter().enumerate() {
        if j == i || !descending_out_of_plan(other) {
            continue;
        }
        let Some(q) = other.position_m() else {
            paused = true;
            continue;
        };
        let horizontal = horizontal_m(p, q);
        if q[2] > p[2] && horizontal < safety_distance_m + COLUMN_MARGIN_M {
            return false;
        }
        paused = true;
    }
    paused
}

/// How far apart horizontally a drone coming down keeps from the drones below it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clearance {
    /// From one in the air (it may still move) or a lost one: the safety distance
    /// plus a 0.1 m margin (`COLUMN_MARGIN_M`).
    pub airborne_m: f64,
    /// From one on the ground, which stays put: the safety distance plus the
    /// tracking error, as far as the lander may drift from where it starts down
    /// (a drone halted off its voxel's column once touched down 0.240 m from a
    /// landed one with the bare 0.25 m safety distance). Pads are a voxel apart,
    /// at least the safety distance plus twice the tracking error (validation), so
    /// neighbouring pads never block each other.
    pub grounded_m: f64,
}

impl Clearance {
    /// For a mission's safety distance and tracking error, metres.
    pub fn new(safety_distance_m: f64, tracking_error_m: f64) -> Self {
        Self {
            airborne_m: safety_distance_m + COLUMN_MARGIN_M,
            grounded_m: safety_distance_m + tracking_error_m.max(0.0),
        }
    }

    /// A drone at `lander` must not come down with another at `other` below it.
    pub fn blocks(&self, lander: [f64; 3], other: [f64; 3]) -> bool {
        let clearance_m = if other[2] > ON_GROUND_BELOW_M {
            self.airborne_m
        } else {
            self.grounded_m
        };
        other[2] < lander[2] && horizontal_m(lander, other) < clearance_m
    }
}

/// True if `i` can descend vertically: no other drone is below it within the safety
/// distance horizontally — where it is, or where it would stop braking from its
/// measured velocity (a drone still sliding after an abort comes underneath), one
/// already down on the ground included (nobody lands on top of another) — and no
/// lost drone last seen in the air is within that distance horizontally at any
/// height: silent, it may have crashed and be falling or lying on the ground below
/// where it was seen. Returns the blocking drone otherwise.
pub fn column_blocker(drones: &[DroneRun], i: usize, clearance: Clearance) -> Option<usize> {
    let p = drones.get(i)?.position_m()?;
    drones.iter().enumerate().find_map(|(j, other)| {
        if j == i {
            return None;
        }
        let now = other.position_m()?;
        // A lost drone may be falling (or already down) anywhere below its last
        // known position: its whole column is blocked, above the lander or not.
        if matches!(other.phase(), Phase::Lost { .. }) && now[2] > ON_GROUND_BELOW_M {
            return (horizontal_m(p, now) < clearance.airborne_m).then_some(j);
        }
        let stop = other
            .stopping_point_m(other.follower().limits())
            .unwrap_or(now);
        (clearance.blocks(p, now) || clearance.blocks(p, stop)).then_some(j)
    })
}

/// Declares drones lost after `lost_after_s` (the mission's `link.lost_after_s`)
/// without a message, and brings them back if they are heard again.
pub fn track_lost(
    drones: &mut [DroneRun],
    lost_after_s: f64,
    since_arm_s: f64,
    events: &mut Vec<LogEvent>,
) {
    for d in drones.iter_mut() {
        match d.phase() {
            Phase::Flying | Phase::AtGoal if d.silent_s() > lost_after_s => {
                events.push(LogEvent::new(
                    since_arm_s,
                    Some(d.id()),
                    &format!(
                        "LOST: nothing heard for {lost_after_s:.0} s (link.lost_after_s); left to its failsafe (hold), the drones that depend on it hold at their gates"
                    ),
                ));
                d.mark_lost();
            }
            Phase::Lost { .. } if !d.link_lost() && !d.telemetry_stale() && d.left_plan() => {
                events.push(LogEvent::new(
                    since_arm_s,
                    Some(d.id()),
                    "heard again after the swarm was replanned without it: it holds and lands where it is once its column is clear",
                ));
                d.land_out_of_plan();
            }
            Phase::Lost { .. } if !d.link_lost() && !d.telemetry_stale() => {
                events.push(LogEvent::new(
                    since_arm_s,
                    Some(d.id()),
                    "heard again after being lost: back in the plan",
                ));
                d.rejoin_plan();
            }
            _ => {}
        }
    }
}

/// Starts retiring drones that left the airspace, whose battery is low or whose
/// autopilot took over.
pub fn detect_retirement(
    drones: &mut [DroneRun],
    settings: &LoopSettings,
    since_arm_s: f64,
    events: &mut Vec<LogEvent>,
) {
    for d in drones.iter_mut() {
        if !matches!(d.phase(), Phase::Flying | Phase::AtGoal) || d.link_lost() {
            continue;
        }
        if let Some(outside_m) = d.outside_airspace_m(settings) {
            retire_outside(d, outside_m, settings, since_arm_s, events);
            continue;
        }
        let (battery, mode, fence_text) = {
            let s = d.session().state();
            (s.battery_remaining_pct, s.custom_mode, s.fence_text.clone())
        };
        let (why, message, stage) = if d.flavour().is_failsafe_mode(mode) {
            // Its own fence is the one failsafe that says why in so many words.
            let cause = fence_text
                .map(|text| format!(", its geofence: \"{text}\""))
                .unwrap_or_default();
            (
                Retirement::AutopilotFailsafe,
                format!(
                    "autopilot failsafe took over (mode {mode:#x}{cause}): the swarm pauses while it lands"
                ),
                RetireStage::AutopilotLanding,
            )
        } else if let Some(pct) = battery.filter(|pct| *pct <= LOW_BATTERY_PCT) {
            (
                Retirement::LowBattery,
                format!("battery low ({pct}%): leaving the plan; the swarm pauses while it lands"),
                RetireStage::Halting,
            )
        } else {
            continue;
        };
        events.push(LogEvent::new(since_arm_s, Some(d.id()), &message));
        d.retire(why, stage);
    }
}

/// Retires a drone `outside_m` outside the airspace, saying who took it there when
/// its autopilot told (its geofence). Beside the airspace, below it is nobody's
/// airspace: it is landed where it is (unless its autopilot is bringing it down
/// already). Above the airspace, its column crosses the swarm's: it comes down
/// like a low-battery drone, once the swarm is at rest and its column is clear.
fn retire_outside(
    d: &mut DroneRun,
    outside_m: f64,
    settings: &LoopSettings,
    since_arm_s: f64,
    events: &mut Vec<LogEvent>,
) {
    let (mode, fence_text) = {
        let s = d.session().state();
        (s.custom_mode, s.fence_text.clone())
    };
    let fence = fence_text
        .map(|text| format!(" (its geofence: \"{text}\")"))
        .unwrap_or_default();
    let beside = d.position_m().is_some_and(|p| {
        let a = &settings.airspace;
        let mid_z = (a.min_enu_m[2] + a.max_enu_m[2]) / 2.0;
        a.outside_by_m([p[0], p[1], mid_z]) > settings.tracking_error_m
    });
    let (landing, stage) = if d.flavour().is_failsafe_mode(mode) {
        (
            format!("its autopilot is bringing it down (mode {mode:#x})"),
            RetireStage::AutopilotLanding,
        )
    } else if beside {
        d.land_outside_airspace();
        (
            "landing it where it is, below it nobody's airspace".to_string(),
            RetireStage::AutopilotLanding,
        )
    } else {
        (
            "above the airspace: it comes down once its column is clear".to_string(),
            RetireStage::Halting,
        )
    };
    events.push(LogEvent::new(
        since_arm_s,
        Some(d.id()),
        &format!(
            "left the airspace: {outside_m:.1} m outside it{fence}; out of the plan, {landing}; the swarm pauses while it comes down"
        ),
    ));
    d.retire(Retirement::LeftAirspace, stage);
}

/// Moves retiring drones on: descend once the swarm is at rest and the column is
/// clear, or let the swarm move on for a while when it is not.
pub fn advance_retirements(
    drones: &mut [DroneRun],
    clearance: Clearance,
    since_arm_s: f64,
    events: &mut Vec<LogEvent>,
) {
    let swarm_at_rest = drones.iter().all(|d| {
        !matches!(d.phase(), Phase::Flying | Phase::Retiring { .. })
            || (d.follower().at_rest() && d.speed_mps() < AT_REST_MPS)
    });
    for i in 0..drones.len() {
        let &Phase::Retiring { stage } = drones[i].phase() else {
            continue;
        };
        let d = &mut drones[i];
        let mode = d.session().state().custom_mode;
        if stage != RetireStage::AutopilotLanding && d.flavour().is_failsafe_mode(mode) {
            events.push(LogEvent::new(
                since_arm_s,
                Some(d.id()),
                &format!("autopilot failsafe took over (mode {mode:#x}): the swarm stays paused while it lands"),
            ));
            d.retire(Retirement::AutopilotFailsafe, RetireStage::AutopilotLanding);
            continue;
        }
        match stage {
            RetireStage::Halting if swarm_at_rest => {
                try_descent(drones, i, clearance, since_arm_s, events);
            }
            RetireStage::WaitColumn { retry_at_s } if since_arm_s >= retry_at_s => {
                drones[i].set_retire_stage(RetireStage::Halting);
            }
            RetireStage::AutopilotLanding => {
                let d = &mut drones[i];
                let disarmed = !d.session().state().armed;
                if disarmed {
                    d.mark_landed();
                }
            }
            _ => {}
        }
    }
}

/// A halted retiring drone with the swarm at rest: descends if nothing is below
/// it, or lets the swarm move on for [`COLUMN_RETRY_S`] first.
fn try_descent(
    drones: &mut [DroneRun],
    i: usize,
    clearance: Clearance,
    since_arm_s: f64,
    events: &mut Vec<LogEvent>,
) {
    match column_blocker(drones, i, clearance) {
        None => {
            let d = &mut drones[i];
            events.push(LogEvent::new(
                since_arm_s,
                Some(d.id()),
                "swarm at rest and nothing below: descending",
            ));
            d.begin_landing();
        }
        Some(j) => {
            let blocker = drones[j].id().to_string();
            let d = &mut drones[i];
            events.push(LogEvent::new(
                since_arm_s,
                Some(d.id()),
                &format!("cannot descend: {blocker} is below; the swarm moves on, retrying in {COLUMN_RETRY_S:.0} s"),
            ));
            d.set_retire_stage(RetireStage::WaitColumn {
                retry_at_s: since_arm_s + COLUMN_RETRY_S,
            });
        }
    }
}

/// A retired drone that is down: its remaining events no longer hold anyone up,
/// as long as the ground is out of the voxel world by the safety distance.
pub fn release_landed(
    drones: &mut [DroneRun],
    ground_clear: bool,
    since_arm_s: f64,
    events: &mut Vec<LogEvent>,
) {
    for d in drones.iter_mut() {
        if d.retired().is_none() || !matches!(d.phase(), Phase::Landed) || d.released() {
            continue;
        }
        d.release_events(ground_clear);
        let message = if ground_clear {
            "landed: its remaining plan events are released, the swarm resumes"
        } else {
            "landed inside the voxel world: the drones that depend on it keep holding"
        };
        events.push(LogEvent::new(since_arm_s, Some(d.id()), message));
    }
}

/// True when no further progress is possible: a drone is lost (or failed in
/// flight) and every other one is done, retired, or at rest at a closed gate.
pub fn plan_stuck(drones: &[DroneRun]) -> bool {
    // One a replan left out holds nobody up any more.
    let someone_missing = drones
        .iter()
        .any(|d| !d.left_plan() && matches!(d.phase(), Phase::Lost { .. } | Phase::Failed(_)));
    someone_missing
        && drones.iter().all(|d| match d.phase() {
            Phase::Flying => d.follower().at_rest() && d.follower().hold == Hold::Gate,
            Phase::AtGoal | Phase::Landed | Phase::Failed(_) | Phase::Lost { .. } => true,
            _ => false,
        })
}

/// Drones still waiting to land whose column stays blocked by a drone that will
/// not move (lost): handing them to the autopilot's hold is all that is left.
pub fn stranded(drones: &[DroneRun], clearance: Clearance) -> Vec<usize> {
    let settled = drones.iter().all(|d| {
        matches!(
            d.phase(),
            Phase::AwaitLanding
                | Phase::Landed
                | Phase::Failed(_)
                | Phase::Lost { .. }
                | Phase::HandedOver { .. }
        )
    });
    if !settled {
        return Vec::new();
    }
    (0..drones.len())
        .filter(|&i| matches!(drones[i].phase(), Phase::AwaitLanding))
        .filter(|&i| column_blocker(drones, i, clearance).is_some())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::Clearance;

    /// Safety 0.25 m, tracking error 0.115 m, 1 m voxels (the paper setting).
    #[test]
    fn a_lander_keeps_the_safety_distance_plus_its_drift_from_a_landed_drone() {
        let c = Clearance::new(0.25, 0.115);
        let landed = [9.0, 8.0, 0.0];
        // Halted 0.25 m off its voxel's column, right beside a landed drone: it
        // would touch down at the bare safety distance, and drift closer.
        assert!(c.blocks([9.0, 8.25, 1.0], landed));
        assert!(c.blocks([9.0, 8.36, 1.0], landed));
        assert!(!c.blocks([9.0, 8.37, 1.0], landed));
        // Above the neighbouring pad, a voxel away: clear.
        assert!(!c.blocks([10.0, 8.0, 0.5], landed));
        // One in the air below keeps the 0.1 m margin, whatever the tracking error.
        assert!(c.blocks([9.0, 8.34, 2.0], [9.0, 8.0, 1.0]));
        assert!(!c.blocks([9.0, 8.36, 2.0], [9.0, 8.0, 1.0]));
        // Nobody is blocked by a drone above it.
        assert!(!c.blocks([9.0, 8.0, 1.0], [9.0, 8.0, 2.0]));
    }
}
