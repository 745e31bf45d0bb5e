//! The planner's answer: splicing the new routes in, or falling back to the old
//! plan and saying why, and the flight-log record of either.

use super::membership::{flies_on, leaves_plan};
use super::{Asked, Replanner, Trigger};
use crate::fly::drone::DroneRun;
use crate::fly::log::{LogEvent, ReplanRecord};
use crate::fly::splice::{Splice, SpliceError};

/// A replan that just took effect.
#[derive(Debug, Clone, Copy)]
pub struct Spliced {
    /// The new plan's makespan from the splice, seconds.
    pub makespan_s: f64,
}

impl Replanner {
    /// Splices the planner's answer in, or falls back: on no plan, a plan or
    /// spliced trajectories a checker refused (the trajectory checker's figures
    /// are recorded either way), a plan over the deadline, or drones that left or
    /// came back meanwhile.
    pub(super) fn answer(
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
    pub(super) fn fall_back(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::replan::ReplanOptions;
    use crate::fly::splice::tests::three_without_b;
    use crate::fly::splice::{SpliceInput, plan_splice};
    use crate::plan::PlanOptions;
    use std::time::Instant;

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
