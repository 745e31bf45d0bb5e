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

use super::contingency::Clearance;
use super::drone::DroneRun;
use super::freeze::{FreezeTarget, freeze_target, lost_voxels, replan_from_leg, voxels_near};
use super::log::{LogEvent, ReplanRecord};
use super::phase::Phase;
use super::splice::{Splice, SpliceError, SpliceInput, Survivor, plan_splice};
use crate::mission::Mission;
use crate::plan::{DiscretePlan, PlanOptions};
use crate::world::Voxel;
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

/// A replan that just took effect.
#[derive(Debug, Clone, Copy)]
pub struct Spliced {
    /// The new plan's makespan from the splice, seconds.
    pub makespan_s: f64,
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

    /// Splices the planner's answer in, or falls back: on no plan, a plan or
    /// spliced trajectories a checker refused (the trajectory checker's figures
    /// are recorded either way), a plan over the deadline, or drones that left or
    /// came back meanwhile.
    fn answer(
        &mut self,
        drones: &mut [DroneRun],
        answer: Result<Splice, SpliceError>,
        asked: Asked,
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) -> Option<Spliced> {
        let Asked {
            trigger,
            survivors,
            left_out,
        } = asked;
        let splice = match answer {
            Err(e) => {
                let check = match &e {
                    SpliceError::Unsafe(figures) => Some(figures.as_ref().clone()),
                    _ => None,
                };
                self.fall_back(trigger, since_arm_s, &e.to_string(), events)
                    .check = check;
                return None;
            }
            Ok(splice) => splice,
        };
        let why = if splice.planning_s > self.options.deadline.as_secs_f64() {
            Some(format!(
                "planning took {:.2} s, over the {:.1} s deadline",
                splice.planning_s,
                self.options.deadline.as_secs_f64()
            ))
        } else if let Some(&i) = survivors.iter().find(|&&i| !flies_on(&drones[i])) {
            // Someone left while we planned: that plan counts on them.
            Some(format!(
                "{} left the plan while it was replanned",
                drones[i].id()
            ))
        } else {
            // Back in the old plan: the new one would fly without it.
            left_out
                .iter()
                .find(|&&i| !leaves_plan(&drones[i]))
                .map(|&i| format!("{} was heard again while it was replanned", drones[i].id()))
        };
        if let Some(why) = why {
            self.fall_back(trigger, since_arm_s, &why, events).check = Some(splice.check);
            return None;
        }
        Some(self.splice(drones, splice, trigger, &left_out, since_arm_s, events))
    }

    /// Starts a freeze when a drone still in the plan is newly lost or newly down
    /// after retiring — once no retirement is under way (it needs the swarm too).
    fn notice(&mut self, drones: &[DroneRun], since_arm_s: f64, events: &mut Vec<LogEvent>) {
        if !self.options.enabled || drones.iter().any(retiring) {
            return;
        }
        let newly: Vec<usize> = (0..drones.len())
            .filter(|&i| !self.considered[i] && leaves_plan(&drones[i]))
            .collect();
        if newly.is_empty() {
            return;
        }
        for &i in &newly {
            self.considered[i] = true;
        }
        let names: Vec<String> = newly.iter().map(|&i| why_out(&drones[i])).collect();
        let trigger = Trigger {
            at_s: since_arm_s,
            since: Instant::now(),
            why: names.join(", "),
        };
        if self.records.len() >= self.options.max_replans {
            let why = format!(
                "the flight's cap of {} replans is reached",
                self.options.max_replans
            );
            self.fall_back(trigger, since_arm_s, &why, events);
            return;
        }
        events.push(LogEvent::new(
            since_arm_s,
            None,
            &format!(
                "replanning without {}: every drone brakes to rest at a voxel centre it holds",
                trigger.why
            ),
        ));
        self.state = State::Freezing(trigger);
    }

    /// Where the drones leaving the plan (`left_out`, indices into `drones`) may
    /// be, as voxels the replan keeps free with their columns.
    fn left_out_voxels(&self, drones: &[DroneRun], left_out: &[usize], t_s: f64) -> Vec<Voxel> {
        let mut voxels = Vec::new();
        for &i in left_out {
            let d = &drones[i];
            if matches!(d.phase(), Phase::Lost { .. }) {
                let commanded_m = d.follower().arc_m(d.route(), t_s);
                let observed_m = d.progress().observed_arc_m;
                voxels.extend(lost_voxels(
                    &self.mission,
                    d.route(),
                    observed_m,
                    commanded_m,
                    d.position_m(),
                ));
            } else if let Some(p) = d.position_m() {
                // Retired and down where it descended, perhaps between cells:
                // nobody is planned to come down within the landing clearance.
                let l = &self.mission.limits;
                let clearance = Clearance::new(l.safety_distance_m, l.tracking_error_m);
                let clearance_m = clearance.airborne_m.max(clearance.grounded_m);
                voxels.extend(voxels_near(&self.mission, p, clearance_m));
            }
        }
        voxels
    }

    /// Once every survivor's commanded motion is at rest, takes the freeze targets
    /// and starts the planner on a blocking thread.
    fn freeze(
        &mut self,
        drones: &[DroneRun],
        trigger: Trigger,
        t_s: f64,
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) {
        let survivors: Vec<usize> = (0..drones.len())
            .filter(|&i| flies_on(&drones[i]))
            .collect();
        let braking = |i: usize| {
            matches!(drones[i].phase(), Phase::Flying) && !drones[i].follower().at_rest()
        };
        if survivors.iter().any(|&i| braking(i)) {
            self.state = State::Freezing(trigger);
            return;
        }
        if let Some(d) = drones.iter().find(|d| retiring(d)) {
            let why = format!("{} started retiring during the freeze", d.id());
            self.fall_back(trigger, since_arm_s, &why, events);
            return;
        }
        if survivors.is_empty() {
            self.fall_back(trigger, since_arm_s, "no drone is left to fly", events);
            return;
        }
        let left_out: Vec<usize> = (0..drones.len())
            .filter(|&i| !drones[i].left_plan() && leaves_plan(&drones[i]))
            .collect();
        let mut targets: Vec<(usize, FreezeTarget, [f64; 3])> = Vec::with_capacity(survivors.len());
        for &i in &survivors {
            let d = &drones[i];
            let arc_m = d.follower().arc_m(d.route(), t_s);
            let rest_m = d.follower().setpoint(d.route(), t_s).position_m;
            match freeze_target(d.route(), arc_m) {
                Some(target) => targets.push((i, target, rest_m)),
                None => {
                    let why = format!("{} has no voxel to freeze in", d.id());
                    self.fall_back(trigger, since_arm_s, &why, events);
                    return;
                }
            }
        }
        let from_leg = replan_from_leg(
            &self.mission,
            &self.plan,
            targets.iter().map(|(_, t, _)| t.step),
        );
        let lost = self.left_out_voxels(drones, &left_out, t_s);
        if !lost.is_empty() {
            let voxels: Vec<String> = lost.iter().map(ToString::to_string).collect();
            events.push(LogEvent::new(
                since_arm_s,
                None,
                &format!(
                    "frozen; planning around {} with the columns below them (where the drones that left may be)",
                    voxels.join(" ")
                ),
            ));
        }
        let input = SpliceInput {
            mission: self.mission.clone(),
            from_leg,
            survivors: targets
                .iter()
                .map(|(i, t, rest_m)| Survivor {
                    id: drones[*i].id().to_string(),
                    run_index: *i,
                    voxel: t.voxel,
                    rest_m: *rest_m,
                })
                .collect(),
            lost,
            options: PlanOptions {
                deadline: self.options.deadline,
                ..PlanOptions::default()
            },
        };
        let (send, result) = mpsc::channel();
        // The planner is CPU-bound: off the loop's threads, so setpoints keep streaming.
        tokio::task::spawn_blocking(move || {
            // The receiver is gone only if the flight gave up waiting.
            let _ = send.send(plan_splice(&input));
        });
        self.state = State::Planning {
            trigger,
            started: Instant::now(),
            result,
            survivors,
            left_out,
        };
    }

    /// Swaps the new routes in and records the replan.
    fn splice(
        &mut self,
        drones: &mut [DroneRun],
        splice: Splice,
        trigger: Trigger,
        left_out: &[usize],
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) -> Spliced {
        for (i, route) in splice.routes {
            if let Some(d) = drones.get_mut(i) {
                d.splice(route);
            }
        }
        let mut left: Vec<String> = Vec::with_capacity(left_out.len());
        for &i in left_out {
            if let Some(d) = drones.get_mut(i) {
                d.leave_plan();
                left.push(d.id().to_string());
            }
        }
        let latency_s = trigger.since.elapsed().as_secs_f64();
        events.push(LogEvent::new(
            since_arm_s,
            None,
            &format!(
                "replanned without {} in {:.1} ms ({:.2} s after the loss was noticed): {} drones fly a new plan of {:.1} s (the old one had {:.1} s); checked: {}",
                left.join(", "),
                1e3 * splice.planning_s,
                latency_s,
                drones.len() - left.len(),
                splice.makespan_s,
                self.makespan_s,
                splice.check.line()
            ),
        ));
        self.records.push(ReplanRecord {
            at_s: trigger.at_s,
            why: trigger.why,
            left_out: left,
            planning_s: splice.planning_s,
            latency_s,
            old_makespan_s: self.makespan_s,
            new_makespan_s: Some(splice.makespan_s),
            fallback: None,
            check: Some(splice.check),
        });
        self.mission = splice.mission;
        self.plan = splice.plan;
        self.makespan_s = splice.makespan_s;
        Spliced {
            makespan_s: splice.makespan_s,
        }
    }

    /// No new plan: the flight goes on with the old one, and says why. Returns the
    /// record kept, for the trajectory checker's figures when it got that far.
    fn fall_back(
        &mut self,
        trigger: Trigger,
        since_arm_s: f64,
        why: &str,
        events: &mut Vec<LogEvent>,
    ) -> &mut ReplanRecord {
        events.push(LogEvent::new(
            since_arm_s,
            None,
            &format!(
                "no replan without {} ({why}): the drones that depend on it hold, the rest finish and land",
                trigger.why
            ),
        ));
        self.records.push(ReplanRecord {
            at_s: trigger.at_s,
            why: trigger.why,
            left_out: Vec::new(),
            planning_s: 0.0,
            latency_s: trigger.since.elapsed().as_secs_f64(),
            old_makespan_s: self.makespan_s,
            new_makespan_s: None,
            fallback: Some(why.to_string()),
            check: None,
        });
        let last = self.records.len() - 1;
        &mut self.records[last]
    }
}

/// Still in the plan and flying it.
fn flies_on(d: &DroneRun) -> bool {
    !d.left_plan() && matches!(d.phase(), Phase::Flying | Phase::AtGoal)
}

/// In the plan, but lost, or retired and down: a replan leaves it out.
fn leaves_plan(d: &DroneRun) -> bool {
    !d.left_plan()
        && (matches!(d.phase(), Phase::Lost { .. })
            || (d.released() && matches!(d.phase(), Phase::Landed)))
}

/// A retirement under way (it pauses the swarm itself and must finish first).
fn retiring(d: &DroneRun) -> bool {
    d.retired().is_some() && !d.released() && !matches!(d.phase(), Phase::Lost { .. })
}

/// "b1 (lost)", "b2 (retired, low battery)".
fn why_out(d: &DroneRun) -> String {
    match d.retired() {
        Some(super::phase::Retirement::LowBattery) => format!("{} (retired, low battery)", d.id()),
        Some(super::phase::Retirement::AutopilotFailsafe) => {
            format!("{} (retired, autopilot failsafe)", d.id())
        }
        None => format!("{} (lost)", d.id()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::splice::tests::three_without_b;

    /// A replanner flying the three-drone mission, and what it was asked after
    /// losing `b`.
    fn asked_without_b(input: &SpliceInput) -> (Replanner, Asked) {
        let plan = crate::plan::solve(&input.mission, &PlanOptions::default())
            .expect("plan")
            .plan;
        let replanner = Replanner::new(
            ReplanOptions::default(),
            input.mission.clone(),
            plan,
            12.0,
            3,
        );
        let asked = Asked {
            trigger: Trigger {
                at_s: 8.0,
                since: Instant::now(),
                why: "b (lost)".into(),
            },
            survivors: Vec::new(),
            left_out: Vec::new(),
        };
        (replanner, asked)
    }

    /// The planner finds a valid plan, but `a` rests where `c` hovers (see
    /// `splice::tests`): the trajectory checker refuses the spliced trajectories,
    /// nothing is spliced, and the flight falls back with the figures recorded.
    #[test]
    fn a_splice_the_trajectory_checker_refuses_falls_back_with_its_figures() {
        let input = three_without_b([1.0, 2.0, 1.5]);
        let (mut replanner, asked) = asked_without_b(&input);
        let answer = plan_splice(&input);
        assert!(matches!(answer, Err(SpliceError::Unsafe(_))), "{answer:?}");
        let mut events = Vec::new();
        let spliced = replanner.answer(&mut [], answer, asked, 9.0, &mut events);
        assert!(spliced.is_none());
        assert_eq!(replanner.records.len(), 1);
        let record = &replanner.records[0];
        assert_eq!(record.new_makespan_s, None);
        let why = record.fallback.as_deref().unwrap_or_default();
        assert!(why.contains("trajectory checker refused"), "{why}");
        let check = record.check.as_ref().expect("the check's figures");
        assert!(!check.passed());
        assert!(check.min_separation_bound_m < check.required_separation_m);
        assert!(
            events
                .last()
                .is_some_and(|e| e.message.starts_with("no replan without b (lost)")),
            "{events:?}"
        );
        assert!(record.line().contains("NOT replanned"), "{}", record.line());
        // The replanner flies on with the old plan.
        assert!(!replanner.busy());
        assert!((replanner.makespan_s - 12.0).abs() < 1e-12);
    }

    /// A splice that passes is flown, and its figures are in the record and the
    /// event.
    #[test]
    fn a_checked_splice_is_recorded_with_its_figures() {
        let input = three_without_b([0.2, 0.0, 1.5]);
        let (mut replanner, asked) = asked_without_b(&input);
        let mut events = Vec::new();
        let spliced = replanner.answer(&mut [], plan_splice(&input), asked, 9.0, &mut events);
        assert!(spliced.is_some());
        let record = &replanner.records[0];
        assert_eq!(record.fallback, None);
        let check = record.check.as_ref().expect("the check's figures");
        assert!(check.passed(), "{}", check.line());
        assert_eq!(check.drones, 2);
        assert!(check.check_s <= record.planning_s);
        assert!(
            events
                .iter()
                .any(|e| e.message.contains("checked: min separation")),
            "{events:?}"
        );
    }
}
