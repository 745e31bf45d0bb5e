//! From the flags to one vehicle: which of the parsed faults reach the vehicle
//! named `drone`, as the [`Faults`] its simulation runs with.

use super::FaultSpec;
use crate::config::{Faults, LinkDrop};
use std::time::Duration;

/// A low battery turns critical (and the autopilot lands) this long after the
/// warning, unless the flag says otherwise.
pub const CRITICAL_AFTER_LOW: Duration = Duration::from_secs(45);

/// The faults of vehicle `drone`: a fault naming no drone applies to everyone,
/// one naming a drone only to that drone; where two set the same thing, the
/// later flag wins.
pub fn faults_for(drone: &str, faults: &[FaultSpec]) -> Faults {
    let mut out = Faults::default();
    for f in faults
        .iter()
        .filter(|f| f.drone().is_none_or(|d| d == drone))
    {
        match f {
            FaultSpec::Loss { percent, .. } => out.loss_percent = *percent,
            FaultSpec::Latency { latency, .. } => out.latency = *latency,
            FaultSpec::Duplicate { percent, .. } => out.duplicate_percent = *percent,
            FaultSpec::Reorder { percent, .. } => out.reorder_percent = *percent,
            FaultSpec::Slow { factor, .. } => out.speed_factor = *factor,
            FaultSpec::Drop {
                after, duration, ..
            } => {
                out.link_drop = Some(LinkDrop {
                    after_takeoff: *after,
                    duration: *duration,
                });
            }
            FaultSpec::Lose { after, .. } => out.link_drop = Some(LinkDrop::permanent(*after)),
            FaultSpec::RefuseArm { .. } => out.refuse_arm = true,
            FaultSpec::Crash { after, .. } => out.crash_after_takeoff = Some(*after),
            FaultSpec::Rogue { after, .. } => out.rogue_after_takeoff = Some(*after),
            FaultSpec::LowBattery {
                after,
                critical_after,
                ..
            } => {
                out.low_battery_after = Some(*after);
                // An endless (or overflowing) wait leaves the battery low for good.
                if let Some(critical) = after.checked_add(*critical_after) {
                    out.critical_battery_after = Some(critical);
                }
            }
            FaultSpec::CriticalBattery { after, .. } => {
                out.critical_battery_after = Some(*after);
            }
        }
    }
    out
}

/// The first drone a fault names that is not among `drones`, if any: a fault
/// for a vehicle that does not exist is a mistake to refuse, not to ignore.
pub fn unknown_drone<'a>(faults: &'a [FaultSpec], drones: &[&str]) -> Option<&'a str> {
    faults
        .iter()
        .filter_map(FaultSpec::drone)
        .find(|d| !drones.contains(d))
}

#[cfg(test)]
mod tests {
    use super::super::parse_fault;
    use super::*;

    fn specs(flags: &[&str]) -> Vec<FaultSpec> {
        flags.iter().map(|f| parse_fault(f).unwrap()).collect()
    }

    #[test]
    fn faults_reach_only_the_drones_they_name() {
        let faults = specs(&[
            "loss=10%",
            "loss=b2:30%",
            "latency=50ms",
            "slow=b1:0.5",
            "lose=b2@8s",
            "low-battery=b1@10s",
        ]);
        let b1 = faults_for("b1", &faults);
        let b2 = faults_for("b2", &faults);
        assert_eq!((b1.loss_percent, b2.loss_percent), (10.0, 30.0));
        assert_eq!(b1.latency, Duration::from_millis(50));
        assert_eq!(b2.latency, Duration::from_millis(50));
        assert_eq!((b1.speed_factor, b2.speed_factor), (0.5, 1.0));
        assert_eq!(b1.link_drop, None);
        assert_eq!(
            b2.link_drop,
            Some(LinkDrop::permanent(Duration::from_secs(8)))
        );
        assert_eq!(b1.low_battery_after, Some(Duration::from_secs(10)));
        assert_eq!(b1.critical_battery_after, Some(Duration::from_secs(55)));
        assert_eq!(b2.critical_battery_after, None);
        assert_eq!(unknown_drone(&faults, &["b1", "b2"]), None);
        assert_eq!(unknown_drone(&faults, &["b1"]), Some("b2"));
    }

    #[test]
    fn a_low_battery_for_good_leaves_the_critical_one_alone() {
        let faults = specs(&["critical-battery=1@90s", "low-battery=1@60s+inf"]);
        let f = faults_for("1", &faults);
        assert_eq!(f.low_battery_after, Some(Duration::from_secs(60)));
        assert_eq!(f.critical_battery_after, Some(Duration::from_secs(90)));
    }
}
