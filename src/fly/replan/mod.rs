//! Replanning in flight: when a drone is lost or has retired, plan the rest of the
//! flight for the survivors and fly that instead of holding its dependants for good.
//!
//! ```text
//! loss or retirement ─► freeze (everyone brakes to rest, then goes to a centre
//!   it holds) ─► plan on a blocking thread under a deadline (replan, plan
//!   validator, schedule, trajectory check of the spliced trajectories)
//!   ─► splice: new routes, plan clock from zero
//!     └► no plan in time, or a checker refused it: fall back (dependants hold,
//!        the rest finish and land), say why
//! ```
//!
//! Everything before the splice keeps the old plan's guarantees: the freeze is a
//! delay, which the plan graph absorbs, and the moves to voxel centres stay inside
//! voxels each drone holds (see [`super::freeze`]). Everything after it has the new
//! plan's, whose starts are those centres (see [`super::splice`]). A lost drone's
//! last known voxels and the columns below them are obstacles of the new plan.
//! Replans are counted and capped per flight; each is recorded in the flight log.
//!
//! The freeze and the start of the planner are in `freezing`, the planner's answer
//! (splice or fall back, and the record of either) in `outcome`, and which drones
//! a replan flies on or leaves out in `membership`.

mod freezing;
mod membership;
mod outcome;

pub use outcome::Spliced;

use super::drone::DroneRun;
use super::log::{LogEvent, ReplanRecord};
use super::splice::{Splice, SpliceError};
use crate::mission::Mission;
use crate::plan::DiscretePlan;
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Beyond its deadline the planner gets this long to return before the flight
/// stops waiting for it.
const DEADLINE_GRACE: Duration = Duration::from_secs(2);

/// Whether and how the flight replans when drones leave it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplanOptions {
    /// Replan at all (off: a loss holds the drones that depend on it, as before).
    pub enabled: bool,
    /// How long the planner may take; every drone holds meanwhile.
    pub deadline: Duration,
    /// At most this many replans per flight; later losses fall back.
    pub max_replans: usize,
}

impl Default for ReplanOptions {
    /// On, 3 s to plan, at most 3 replans per flight.
    fn default() -> Self {
        Self {
            enabled: true,
            deadline: Duration::from_secs(3),
            max_replans: 3,
        }
    }
}

/// What set a replan off.
struct Trigger {
    /// Seconds since the first arm command.
    at_s: f64,
    since: Instant,
    /// For the log: "b1 lost", "b2 retired (low battery)".
    why: String,
}

/// What the planner was asked: why, and which drones fly on and which leave.
struct Asked {
    trigger: Trigger,
    /// Loop indices of the drones the new plan flies.
    survivors: Vec<usize>,
    /// Loop indices of the drones it flies without.
    left_out: Vec<usize>,
}

/// Where the replanner is.
enum State {
    /// Flying the current plan.
    Idle,
    /// Everyone brakes to rest before the freeze targets are taken.
    Freezing(Trigger),
    /// The planner runs; everyone holds.
    Planning {
        trigger: Trigger,
        started: Instant,
        result: mpsc::Receiver<Result<Splice, SpliceError>>,
        survivors: Vec<usize>,
        left_out: Vec<usize>,
    },
}

/// The replanning state of one flight.
pub struct Replanner {
    options: ReplanOptions,
    /// The mission the current plan was planned in.
    mission: Mission,
    /// The plan the drones fly now.
    plan: DiscretePlan,
    /// Its makespan, seconds.
    makespan_s: f64,
    /// Per drone: its loss or retirement has been handled (replanned or not).
    considered: Vec<bool>,
    state: State,
    /// Every replan tried, in order.
    pub records: Vec<ReplanRecord>,
}

impl Replanner {
    /// For a flight of `plan` (makespan `makespan_s`) in `mission` with `drones` drones.
    pub fn new(
        options: ReplanOptions,
        mission: Mission,
        plan: DiscretePlan,
        makespan_s: f64,
        drones: usize,
    ) -> Self {
        Self {
            options,
            mission,
            plan,
            makespan_s,
            considered: vec![false; drones],
            state: State::Idle,
            records: Vec::new(),
        }
    }

    /// A replan is under way: every drone holds still.
    pub fn busy(&self) -> bool {
        !matches!(self.state, State::Idle)
    }

    /// Gives up a replan under way (an abort, a timeout: everyone holds, then
    /// lands).
    pub fn abandon(&mut self, since_arm_s: f64, events: &mut Vec<LogEvent>) {
        if let State::Freezing(trigger) | State::Planning { trigger, .. } =
            std::mem::replace(&mut self.state, State::Idle)
        {
            self.fall_back(trigger, since_arm_s, "the flight is aborting", events);
        }
    }

    /// One tick of the plan clock (`t_s`): notice losses, freeze, plan, splice.
    /// Returns the new plan when one was spliced in this tick (its clock starts now).
    pub fn tick(
        &mut self,
        drones: &mut [DroneRun],
        t_s: f64,
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) -> Option<Spliced> {
        match std::mem::replace(&mut self.state, State::Idle) {
            State::Idle => {
                self.notice(drones, since_arm_s, events);
                None
            }
            State::Freezing(trigger) => {
                self.freeze(drones, trigger, t_s, since_arm_s, events);
                None
            }
            State::Planning {
                trigger,
                started,
                result,
                survivors,
                left_out,
            } => match result.try_recv() {
                Err(mpsc::TryRecvError::Empty)
                    if started.elapsed() <= self.options.deadline + DEADLINE_GRACE =>
                {
                    self.state = State::Planning {
                        trigger,
                        started,
                        result,
                        survivors,
                        left_out,
                    };
                    None
                }
                Err(_) => {
                    let why = format!(
                        "the planner did not answer within {:.1} s",
                        (self.options.deadline + DEADLINE_GRACE).as_secs_f64()
                    );
                    self.fall_back(trigger, since_arm_s, &why, events);
                    None
                }
                Ok(answer) => {
                    let asked = Asked {
                        trigger,
                        survivors,
                        left_out,
                    };
                    self.answer(drones, answer, asked, since_arm_s, events)
                }
            },
        }
    }
}
