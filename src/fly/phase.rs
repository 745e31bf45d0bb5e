//! Where one drone is in the flight, and why it left the plan if it did.
//!
//! These types sit below both the executor (which moves drones through their
//! phases) and `contingency` (which takes drones out of the plan), so neither
//! needs the other to name a phase.

use super::command::CommandError;
use std::time::Instant;

/// A command a phase waits for: not sent yet, in flight, or answered.
#[derive(Debug, Default)]
pub enum Request {
    /// Not sent yet (some phases wait before sending).
    #[default]
    NotSent,
    /// Sent; its result has not arrived.
    Sent,
    /// Answered; the phase acts on the result on its next step.
    Done(Result<(), CommandError>),
}

impl Request {
    /// Takes an answered result out, leaving `NotSent`; `None` while unsent or in flight.
    pub fn take_done(&mut self) -> Option<Result<(), CommandError>> {
        match std::mem::take(self) {
            Request::Done(result) => Some(result),
            other => {
                *self = other;
                None
            }
        }
    }
}

/// Why a drone was given up (it holds or lands by itself). Display is the log text.
#[derive(Debug, thiserror::Error)]
pub enum FailReason {
    /// PX4 refused (or never confirmed) the switch to OFFBOARD before takeoff.
    #[error("OFFBOARD refused: {0}")]
    Offboard(CommandError),
    /// ArduPilot refused its takeoff command while still on the ground.
    #[error("takeoff refused: {0}")]
    Takeoff(CommandError),
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
    /// PX4: streaming a ground hold so OFFBOARD is accepted, then switching.
    EnterOffboard {
        /// When the ground hold started (OFFBOARD is asked for 0.5 s later).
        since: Instant,
        /// The OFFBOARD switch.
        request: Request,
    },
    /// PX4: climbing on our setpoints along a vertical profile started at `t0`.
    Climb {
        /// When the climb profile started.
        t0: Instant,
        /// Height the climb started from, ENU metres.
        from_z_m: f64,
    },
    /// ArduPilot: the vehicle's own takeoff to the start altitude.
    Takeoff {
        /// The takeoff command.
        request: Request,
    },
    /// ArduPilot: takeoff accepted, climbing to the start altitude.
    AwaitAltitude,
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
            Phase::EnterOffboard { .. } => "offboard",
            Phase::Climb { .. } | Phase::Takeoff { .. } | Phase::AwaitAltitude => "takeoff",
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
