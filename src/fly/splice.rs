//! The rest of a flight, replanned from where the freeze left the survivors, as
//! routes the running flight loop can swap in.
//!
//! Planning, the independent checks, scheduling and the routes are all computed
//! here, off the loop (the caller runs [`plan_splice`] on a blocking thread while
//! every drone holds). The new plan starts each survivor at the centre of the
//! voxel it froze in ([`super::freeze`]), so each new route begins with one short
//! *re-centring* run from where its follower stopped to that centre, inside the
//! voxel's stretch the drone holds; every run of the new plan is delayed until
//! the longest re-centring has ended, so the new schedule begins with everyone
//! at rest at their starts — the state its safety argument starts from.
//!
//! The new plan is composed as every plan is ([`compiled::compose`]), and the
//! spliced trajectories — re-centring runs, the new plan and each touchdown — go
//! through the same trajectory checker as the plan flown before arming
//! ([`compiled::check_flight`]) before any of them flies: a splice that breaks a
//! limit is refused with the checker's figures, and the flight falls back.

use super::path::Route;
use crate::compiled::{self, Begin, CheckFigures, Composition};
use crate::mission::Mission;
use crate::plan::{self, DiscretePlan, PlanError, PlanOptions};
use crate::schedule::ScheduleError;
use crate::trajectory::{Profile, Run};
use crate::verify::CheckError;
use crate::world::Voxel;
use std::time::Instant;

/// A re-centring shorter than this is no run at all, metres.
const RECENTRE_MIN_M: f64 = 1e-6;

/// One surviving drone as the freeze left it.
#[derive(Debug, Clone)]
pub struct Survivor {
    /// Its mission id.
    pub id: String,
    /// Its index in the flight loop (what an event's drone number must name).
    pub run_index: usize,
    /// The voxel it froze in (see `freeze::freeze_target`).
    pub voxel: Voxel,
    /// Where its commanded motion came to rest, ENU metres.
    pub rest_m: [f64; 3],
}

/// Everything a replan needs, owned, so it can run on another thread.
#[derive(Debug, Clone)]
pub struct SpliceInput {
    /// The mission the flight is flying now (the original, or the last replan's).
    pub mission: Mission,
    /// The leg of `mission.legs()` the least advanced survivor is in.
    pub from_leg: usize,
    /// The drones that fly on.
    pub survivors: Vec<Survivor>,
    /// Voxels lost drones may be in (each is blocked with its column).
    pub lost: Vec<Voxel>,
    /// The planner's knobs; its deadline is the replan's.
    pub options: PlanOptions,
}

/// A new plan, checked and scheduled, and the survivors' new routes.
#[derive(Debug, Clone)]
pub struct Splice {
    /// The survivors' mission the plan was planned in (lost drones' columns blocked).
    pub mission: Mission,
    /// The new discrete plan, from the frozen voxels to the pads.
    pub plan: DiscretePlan,
    /// `(loop index, new route)` for every survivor.
    pub routes: Vec<(usize, Route)>,
    /// The new schedule's makespan including the re-centring, seconds.
    pub makespan_s: f64,
    /// Seconds spent planning, checking and scheduling.
    pub planning_s: f64,
    /// What the trajectory checker measured on the spliced trajectories.
    pub check: CheckFigures,
}

/// Why no new plan could be spliced in.
#[derive(Debug, thiserror::Error)]
pub enum SpliceError {
    /// The planner found no plan (none exists, or not within the deadline).
    #[error("no plan for the survivors: {0}")]
    Plan(#[from] PlanError),
    /// The independent checker refused the plan the planner returned.
    #[error("the plan checker refused the new plan: {0}")]
    Refused(String),
    /// The plan could not be scheduled.
    #[error("the new plan could not be scheduled: {0}")]
    Schedule(#[from] ScheduleError),
    /// The trajectory checker could not run on the spliced trajectories.
    #[error("the trajectory checker could not run on the new plan: {0}")]
    Check(#[from] CheckError),
    /// The trajectory checker measured a limit broken on the spliced
    /// trajectories; its figures go into the flight log.
    #[error(
        "the trajectory checker refused the spliced trajectories: {}",
        .0.violations.join("; ")
    )]
    Unsafe(Box<CheckFigures>),
}

/// Replans, checks the plan with the independent plan validator, composes it,
/// splices the re-centring runs in, checks the spliced trajectories with the
/// trajectory checker and builds the routes.
pub fn plan_splice(input: &SpliceInput) -> Result<Splice, SpliceError> {
    let started = Instant::now();
    let starts: Vec<(&str, Voxel)> = input
        .survivors
        .iter()
        .map(|s| (s.id.as_str(), s.voxel))
        .collect();
    let re = plan::replan(
        &input.mission,
        input.from_leg,
        &starts,
        &input.lost,
        &input.options,
    )?;
    let rest = re.solution.plan;
    plan::validate_rest(&re.mission, re.from_leg, &starts, &rest).map_err(|violations| {
        let all: Vec<String> = violations.iter().map(ToString::to_string).collect();
        SpliceError::Refused(all.join("; "))
    })?;
    let Composition {
        mut execution,
        mut trajectories,
    } = compiled::compose(&re.mission, &rest)?;
    let kinematics = re.mission.commanded_limits().kinematics();
    let survivor = |id: &str| input.survivors.iter().find(|s| s.id == id);
    let recentring: Vec<Option<Run>> = trajectories
        .drones
        .iter()
        .map(|t| {
            let from_m = survivor(&t.id)?.rest_m;
            let length_m = super::path::distance_m(from_m, t.start_m);
            (length_m > RECENTRE_MIN_M).then(|| Run {
                start_s: 0.0,
                from_m,
                to_m: t.start_m,
                profile: Profile::new(length_m, kinematics),
            })
        })
        .collect();
    let shift_s = recentring
        .iter()
        .flatten()
        .map(|r| r.profile.duration_s())
        .fold(0.0, f64::max);
    // New-plan drone k is loop drone `loop_index[k]`.
    let loop_index: Vec<u32> = trajectories
        .drones
        .iter()
        .map(|t| survivor(&t.id).map_or(u32::MAX, |s| s.run_index as u32))
        .collect();
    for ((t, e), first) in trajectories
        .drones
        .iter_mut()
        .zip(&mut execution.drones)
        .zip(recentring)
    {
        for run in &mut t.runs {
            run.start_s += shift_s;
        }
        if let Some(run) = first {
            t.start_m = run.from_m;
            t.runs.insert(0, run);
        }
        for event in &mut e.events {
            event.reach_s += shift_s;
            event.leave_s += shift_s;
            for id in &mut event.after {
                id.drone = loop_index
                    .get(id.drone as usize)
                    .copied()
                    .unwrap_or(u32::MAX);
            }
        }
    }
    trajectories.makespan_s += shift_s;
    // What flies from here is checked first: the re-centring runs, the new plan
    // and each touchdown, the drones at rest in the air where they froze.
    let (report, check) = compiled::check_flight(&re.mission, &trajectories, Begin::Airborne)?;
    if !report.ok() {
        return Err(SpliceError::Unsafe(Box::new(check)));
    }
    let routes = super::path::joined(&trajectories, &execution)
        .into_iter()
        .filter_map(|r| survivor(&r.id).map(|s| (s.run_index, r)))
        .collect();
    Ok(Splice {
        mission: re.mission,
        plan: rest,
        routes,
        makespan_s: execution.makespan_s + shift_s,
        planning_s: started.elapsed().as_secs_f64(),
        check,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Three drones in one group; `b` (loop index 1) is lost after takeoff at
    /// (0, 1, 0). `a` froze at `a_rest_m` in voxel (0, 0, 0), `c` at the centre of
    /// (1, 2, 0).
    pub(crate) fn three_without_b(a_rest_m: [f64; 3]) -> SpliceInput {
        let mission = crate::mission::from_yaml(
            "
name: three
world: { dimensions: [4, 3, 1], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 1.5] }
limits: { max_speed_mps: 1.0, max_accel_mps2: 1.0, safety_distance_m: 0.2 }
groups:
  - name: g
    drones: [{ id: a, start: [0, 0, 0] }, { id: b, start: [0, 1, 0] }, { id: c, start: [0, 2, 0] }]
    goals: [[3, 0, 0], [3, 1, 0], [3, 2, 0]]
",
            "three.yaml".as_ref(),
        )
        .expect("mission");
        SpliceInput {
            mission,
            from_leg: 1,
            survivors: vec![
                Survivor {
                    id: "a".into(),
                    run_index: 0,
                    voxel: Voxel::new(0, 0, 0),
                    rest_m: a_rest_m,
                },
                Survivor {
                    id: "c".into(),
                    run_index: 2,
                    voxel: Voxel::new(1, 2, 0),
                    rest_m: [1.0, 2.0, 1.5],
                },
            ],
            lost: vec![Voxel::new(0, 1, 0)],
            options: PlanOptions::default(),
        }
    }

    /// `a` froze 0.2 m east of its voxel's centre, `c` at a centre.
    #[test]
    fn the_new_routes_start_where_the_freeze_left_the_drones() {
        let a_rest_m = [0.2, 0.0, 1.5];
        let input = three_without_b(a_rest_m);
        let splice = plan_splice(&input).expect("a plan without b");
        assert_eq!(splice.plan.drones.len(), 2);
        let indices: Vec<usize> = splice.routes.iter().map(|(i, _)| *i).collect();
        assert_eq!(indices, [0, 2]);
        let (_, a) = &splice.routes[0];
        // a re-centres first: from where it stopped to its voxel's centre ...
        assert_eq!(a.start_m, a_rest_m);
        assert_eq!(a.runs[0].from_m, a_rest_m);
        assert_eq!(a.runs[0].to_m, [0.0, 0.0, 1.5]);
        let recentre_s = a.runs[0].profile.duration_s();
        assert!(recentre_s > 0.0);
        // ... and nobody's new-plan runs start before it is done.
        for (_, route) in &splice.routes {
            let first_new = usize::from(route.id == "a");
            assert!(
                route.runs[first_new..]
                    .iter()
                    .all(|r| r.scheduled_start_s >= recentre_s - 1e-9),
                "{}",
                route.id
            );
            // Its first event is the new plan's start, at the centre it froze in.
            let start = &route.events[0];
            assert_eq!(start.kind, crate::schedule::EventKind::Start);
            let (x, y) = if route.id == "a" { (0, 0) } else { (1, 2) };
            assert_eq!((start.voxel.x, start.voxel.y), (x, y));
            // Gates name loop drones: 0 or 2, never the new plan's 1.
            for e in &route.events {
                assert!(e.after.iter().all(|id| id.drone == 0 || id.drone == 2));
            }
        }
        // The schedule includes the re-centring.
        assert!(splice.makespan_s > recentre_s);
        // b's column is an obstacle of the plan flown from here on.
        assert!(!splice.mission.airspace.is_free(Voxel::new(0, 1, -1)));
        // The spliced trajectories were checked: every survivor, within the limits.
        assert!(splice.check.passed(), "{}", splice.check.line());
        assert_eq!(splice.check.drones, 2);
        assert!(splice.check.min_separation_bound_m >= splice.check.required_separation_m);
        assert!(splice.check.max_speed_mps <= 1.0 + 1e-9);
    }

    /// A rest point no freeze would leave — `a` stopped where `c` hovers — makes
    /// `a`'s re-centring run start inside `c`: the valid new plan is refused by the
    /// trajectory checker, with figures that say why.
    #[test]
    fn spliced_trajectories_that_break_separation_are_refused() {
        let input = three_without_b([1.0, 2.0, 1.5]);
        match plan_splice(&input) {
            Err(SpliceError::Unsafe(figures)) => {
                assert!(!figures.passed());
                assert!(figures.min_separation_bound_m < 0.2, "{}", figures.line());
                assert_eq!(
                    figures
                        .closest
                        .as_ref()
                        .map(|(a, b, _)| (a.as_str(), b.as_str())),
                    Some(("a", "c"))
                );
                assert!(
                    figures.violations.iter().any(|v| v.contains("\"a\"")),
                    "drones named by id: {:?}",
                    figures.violations
                );
            }
            other => panic!("expected a refusal by the checker, got {other:?}"),
        }
    }
}
