//! Where one drone is in the flight, and why it left the plan if it did.
//!
//! These types sit below both the executor (which moves drones through their
//! phases) and `contingency` (which takes drones out of the plan), so neither
//! needs the other to name a phase.

use super::autopilot::Takeoff;
use super::command::{CommandError, Request};

/// Why a drone was given up (it holds or lands by itself). Display is the log text.
#[derive(Debug, thiserror::Error)]
pub enum FailReason {
    /// The autopilot refused (or never confirmed) a step of its takeoff: PX4 the
    /// switch to OFFBOARD, ArduPilot the takeoff command.
    #[error("{step} refused: {error}")]
    Takeoff {
        /// The step, as the autopilot's ground station names it.
        step: &'static str,
        /// What the vehicle answered.
        error: CommandError,
    },
    /// Landing was refused or touchdown and disarm never showed in telemetry.
    #[error("landing: {0}")]
    Land(CommandError),
}

/// Why a drone left its plan early.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Retirement {
    /// Battery at or below `contingency::LOW_BATTERY_PCT`: we land it ourselves.
    LowBattery,
    /// The autopilot switched itself to land or return: we let it.
    AutopilotFailsafe,
    /// Outside the mission's airspace by telemetry, beyond the tracking bound (its
    /// own geofence stopped it, or a rogue ground station or a flyaway took it
    /// there): landed where it is, in nobody's airspace.
    LeftAirspace,
}

/// Where a retiring drone is on its way down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RetireStage {
    /// Waiting for itself and the swarm to come to rest.
    Halting,
    /// Its column was blocked: the swarm moves on until `retry_at_s`.
    WaitColumn {
        /// When to try the descent again, seconds since the first arm command.
        retry_at_s: f64,
    },
    /// The autopilot is landing it on its own.
    AutopilotLanding,
}

/// Where a drone is in the flight.
#[derive(Debug)]
pub enum Phase {
    /// Armed on the pad, on its way up to the start voxel the way its autopilot
    /// takes off (see `autopilot::Flavour::takeoff`).
    TakingOff(Box<dyn Takeoff>),
    /// Hovering above its pad until everyone is.
    AtStart,
    /// Following the plan.
    Flying,
    /// Holding at the goal until everyone is.
    AtGoal,
    /// Nothing heard for the mission's `link.lost_after_s`: left to its own failsafe.
    Lost {
        /// It had reached its goal before it went silent (it rejoins as at goal).
        was_at_goal: bool,
    },
    /// Leaving the plan early (low battery, autopilot failsafe): see `contingency`.
    Retiring {
        /// How far down it is.
        stage: RetireStage,
    },
    /// Done (at its goal or held for good): lands once nothing is below it.
    AwaitLanding,
    /// Could never land safely: put in the autopilot's hold mode for manual control.
    HandedOver {
        /// The switch to the hold mode.
        request: Request,
    },
    /// Land commanded; waiting for touchdown and disarm.
    Landing {
        /// The land command.
        request: Request,
    },
    /// On the ground and disarmed.
    Landed,
    /// Gave up on this drone (a refused command); it holds or lands by itself.
    Failed(FailReason),
}

impl Phase {
    /// The phase's name in the status view.
    pub fn name(&self) -> &'static str {
        match self {
            Phase::TakingOff(takeoff) => takeoff.name(),
            Phase::AtStart => "at start",
            Phase::Flying => "flying",
            Phase::AtGoal => "at goal",
            Phase::Lost { .. } => "LOST",
            Phase::Retiring { .. } => "retiring",
            Phase::AwaitLanding => "to land",
            Phase::HandedOver { .. } => "HANDED OVER",
            Phase::Landing { .. } => "landing",
            Phase::Landed => "landed",
            Phase::Failed(_) => "FAILED",
        }
    }

    /// Retiring and still in the air under our setpoints (halting or waiting for
    /// its column), as opposed to being landed by its autopilot.
    pub fn retiring_on_our_setpoints(&self) -> bool {
        matches!(
            self,
            Phase::Retiring {
                stage: RetireStage::Halting | RetireStage::WaitColumn { .. }
            }
        )
    }
}
