//! Which drones a replan flies on, which it leaves out, and when it must wait:
//! read from each drone's phase and whether it already left a plan.

use crate::fly::drone::DroneRun;
use crate::fly::phase::{Phase, Retirement};

/// Still in the plan and flying it.
pub(super) fn flies_on(d: &DroneRun) -> bool {
    !d.left_plan() && matches!(d.phase(), Phase::Flying | Phase::AtGoal)
}

/// In the plan, but lost, or retired and down: a replan leaves it out.
pub(super) fn leaves_plan(d: &DroneRun) -> bool {
    !d.left_plan()
        && (matches!(d.phase(), Phase::Lost { .. })
            || (d.released() && matches!(d.phase(), Phase::Landed)))
}

/// A retirement under way (it pauses the swarm itself and must finish first).
pub(super) fn retiring(d: &DroneRun) -> bool {
    d.retired().is_some() && !d.released() && !matches!(d.phase(), Phase::Lost { .. })
}

/// "b1 (lost)", "b2 (retired, low battery)".
pub(super) fn why_out(d: &DroneRun) -> String {
    match d.retired() {
        Some(Retirement::LowBattery) => format!("{} (retired, low battery)", d.id()),
        Some(Retirement::AutopilotFailsafe) => {
            format!("{} (retired, autopilot failsafe)", d.id())
        }
        Some(Retirement::LeftAirspace) => format!("{} (retired, left the airspace)", d.id()),
        None => format!("{} (lost)", d.id()),
    }
}
