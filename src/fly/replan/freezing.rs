//! The freeze: noticing that a drone left the plan, waiting for every survivor to
//! brake to rest, taking the voxel centres they hold (and the voxels the drones
//! that left may be in), and starting the planner on a blocking thread.

use super::membership::{flies_on, leaves_plan, retiring, why_out};
use super::{Replanner, State, Trigger};
use crate::fly::contingency::Clearance;
use crate::fly::drone::DroneRun;
use crate::fly::freeze::{FreezeTarget, freeze_target, lost_voxels, replan_from_leg, voxels_near};
use crate::fly::log::LogEvent;
use crate::fly::phase::Phase;
use crate::fly::splice::{SpliceInput, Survivor, plan_splice};
use crate::plan::PlanOptions;
use crate::world::Voxel;
use std::sync::mpsc;
use std::time::Instant;

impl Replanner {
    /// Starts a freeze when a drone still in the plan is newly lost or newly down
    /// after retiring — once no retirement is under way (it needs the swarm too).
    pub(super) fn notice(
        &mut self,
        drones: &[DroneRun],
        since_arm_s: f64,
        events: &mut Vec<LogEvent>,
    ) {
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
    pub(super) fn freeze(
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
                reserve_per_drone_step: crate::compiled::COMPILE_TIME_PER_DRONE_STEP,
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
}
