//! The rest of a flight planned from where the drones are, without the ones that
//! are gone: what a replan after a loss flies.
//!
//! A drone that stops talking may be hovering, drifting or falling, so the voxel it
//! was last known in **and the column below it down to the pad layer** become
//! obstacles: nobody is planned through the space it may fall into. That is the
//! safety margin of a lost drone, stated once here; goals inside it are dropped.
//! A survivor that is already in such a column (below where the lost drone was)
//! keeps its voxel only to leave it: the plan must take it out and never back,
//! and nobody else in (checked after planning; otherwise there is no plan). A
//! survivor in a lost drone's voxel itself is refused.
//! The survivors of each group take the group's remaining goals (a group with
//! fewer drones than goals leaves some empty; one with none left drops out), and every later leg — stages and the
//! landing on their own pads — is planned as [`super::solve`] plans a whole flight,
//! each leg makespan-optimal from where the previous left the drones.
//!
//! ```
//! use swarmctl::{mission, plan};
//! use swarmctl::world::Voxel;
//! let m = mission::from_yaml("
//! name: two
//! world: { dimensions: [4, 2, 1], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 1.5] }
//! limits: { max_speed_mps: 1.0, max_accel_mps2: 1.0, safety_distance_m: 0.2 }
//! groups:
//!   - name: g
//!     drones: [{ id: a, start: [0, 0, 0] }, { id: b, start: [0, 1, 0] }]
//!     goals: [[3, 0, 0], [3, 1, 0]]
//! ", "two.yaml".as_ref()).unwrap();
//! // After takeoff (leg 0) `b` is lost at (1, 1, 0); `a` is at its start.
//! let re = plan::replan(
//!     &m, 1, &[("a", Voxel::new(0, 0, 0))], &[Voxel::new(1, 1, 0)],
//!     &plan::PlanOptions::default(),
//! ).unwrap();
//! let rest = &re.solution.plan;
//! assert_eq!(rest.drones.len(), 1);
//! assert_eq!((rest.legs[0].name.as_str(), rest.legs[0].makespan_steps), ("formation", 3));
//! // b's voxel and the column below it are obstacles now.
//! assert!(!re.mission.airspace.is_free(Voxel::new(1, 1, -1)));
//! ```

use super::discrete_plan::DiscretePlan;
use super::error::PlanError;
use super::flight::solve_from;
use super::options::PlanOptions;
use super::solve::Solution;
use super::stats::Progress;
use crate::mission::Mission;
use crate::world::Voxel;

/// A replanned rest of the flight and the mission it was planned in: the
/// survivors only, the lost drones' columns blocked in its airspace. Check and
/// schedule the plan against this mission, not the original.
#[derive(Debug, Clone)]
pub struct Replanned {
    /// The survivors' mission.
    pub mission: Mission,
    /// Where in `mission.legs()` the plan starts (the replanned leg, counted in
    /// the survivors' mission): what `plan::validate_rest` checks it from.
    pub from_leg: usize,
    /// Their plan from where they are, leg by leg, to their pads.
    pub solution: Solution,
}

/// Plans the rest of `mission` from leg `from_leg` (an index into
/// `Mission::legs`: the leg the swarm is in, re-flown from where it stopped) with
/// the drones in `survivors` (mission id, the voxel it is at) and without every
/// other one; each voxel in `lost` is a lost drone's last known one, blocked with
/// its column down to the pad layer. Fails naming the drone when a survivor is
/// unknown, named twice or inside a blocked column, and as [`super::solve`] fails
/// when no plan exists (a survivor walled off by a lost drone's column, say).
pub fn replan(
    mission: &Mission,
    from_leg: usize,
    survivors: &[(&str, Voxel)],
    lost: &[Voxel],
    options: &PlanOptions,
) -> Result<Replanned, PlanError> {
    replan_with_progress(mission, from_leg, survivors, lost, options, &mut |_| {})
}

/// [`replan`], calling `progress` a few times a second while a conflict tree grows.
pub fn replan_with_progress(
    mission: &Mission,
    from_leg: usize,
    survivors: &[(&str, Voxel)],
    lost: &[Voxel],
    options: &PlanOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Replanned, PlanError> {
    let legs = mission.legs().len();
    if from_leg >= legs {
        return Err(PlanError::LiveState {
            drone: survivors
                .first()
                .map_or_else(String::new, |s| s.0.to_string()),
            problem: format!("leg {from_leg} does not exist (the mission has {legs})"),
        });
    }
    let mut rest = mission.clone();
    // Column voxels a survivor is in stay free for it to leave (see the module docs).
    let mut evacuated: Vec<(Voxel, &str)> = Vec::new();
    for &v in lost {
        for z in -1..=v.z {
            let below = Voxel::new(v.x, v.y, z);
            match survivors.iter().find(|s| s.1 == below) {
                Some(&(id, _)) if below != v && !lost.contains(&below) => {
                    evacuated.push((below, id));
                }
                _ if rest.airspace.contains(below) => rest.airspace.block(below),
                _ => {}
            }
        }
    }
    check_survivors(mission, &rest, survivors)?;
    let at_of = |id: &str| survivors.iter().find(|s| s.0 == id).map(|s| s.1);
    let mut kept_groups = Vec::with_capacity(rest.groups.len());
    for group in &mut rest.groups {
        // A drone that is gone leaves its pad to the others (`group_pads` landing):
        // one of theirs may lie in a lost drone's column.
        let (kept, gone): (Vec<_>, Vec<_>) = std::mem::take(&mut group.drones)
            .into_iter()
            .partition(|d| at_of(&d.id).is_some());
        group.drones = kept;
        group.free_pads.extend(
            gone.iter()
                .map(|d| d.pad_voxel())
                .filter(|&v| rest.airspace.is_free(v)),
        );
        kept_groups.push(!group.drones.is_empty());
    }
    let mut keep = kept_groups.iter();
    rest.groups
        .retain(|_| keep.next().copied().unwrap_or(false));
    // Goals inside a blocked column are gone too (a group left with fewer goals
    // than drones is reported unreachable by the planner, naming it), and so are
    // those on a voxel a survivor must leave.
    let airspace = rest.airspace.clone();
    let usable = |g: Voxel| airspace.is_free(g) && !evacuated.iter().any(|e| e.0 == g);
    for group in &mut rest.groups {
        group.goals.retain(|&g| usable(g));
        group.free_pads.retain(|&g| usable(g));
    }
    for stage in &mut rest.stages {
        let mut keep = kept_groups.iter();
        stage
            .goals
            .retain(|_| keep.next().copied().unwrap_or(false));
        for goals in stage.goals.iter_mut().flatten() {
            goals.retain(|&g| usable(g));
        }
    }
    let at: Vec<Vec<Voxel>> = rest
        .groups
        .iter()
        .map(|g| g.drones.iter().filter_map(|d| at_of(&d.id)).collect())
        .collect();
    // The formation leg exists only while some group has starts: with every such
    // group gone it drops out, and the rest starts at the next leg that is left.
    let rest_legs = rest.legs();
    let from_rest_leg = mission.legs()[from_leg..]
        .iter()
        .find_map(|leg| rest_legs.iter().position(|l| l.name == leg.name))
        .ok_or(PlanError::Internal("a replan without a landing leg"))?;
    let solution = solve_from(&rest, from_rest_leg, at, options, progress)?;
    check_evacuation(&solution.plan, &evacuated)?;
    Ok(Replanned {
        mission: rest,
        from_leg: from_rest_leg,
        solution,
    })
}

/// Each `(voxel, drone)` in `evacuated` is in a lost drone's column: `drone` must
/// leave it and never come back, and no other drone may enter it.
fn check_evacuation(plan: &DiscretePlan, evacuated: &[(Voxel, &str)]) -> Result<(), PlanError> {
    for d in &plan.drones {
        for (step, &v) in d.path.iter().enumerate() {
            let Some(&(_, owner)) = evacuated.iter().find(|e| e.0 == v) else {
                continue;
            };
            let leaving = owner == d.id && d.path[..step].iter().all(|&p| p == v);
            if !leaving {
                return Err(PlanError::LiveState {
                    drone: d.id.clone(),
                    problem: format!(
                        "the only plan found has it at {v} at step {step}, in the column below a lost drone that {owner} must leave"
                    ),
                });
            }
        }
    }
    Ok(())
}

/// Every survivor is a drone of `mission`, named once, in free airspace of `rest`.
fn check_survivors(
    mission: &Mission,
    rest: &Mission,
    survivors: &[(&str, Voxel)],
) -> Result<(), PlanError> {
    let bad = |drone: &str, problem: String| PlanError::LiveState {
        drone: drone.to_string(),
        problem,
    };
    for (i, &(id, at)) in survivors.iter().enumerate() {
        if !mission.drones().any(|(_, d)| d.id == id) {
            return Err(bad(id, "not a drone of the mission".into()));
        }
        if survivors[..i].iter().any(|s| s.0 == id) {
            return Err(bad(id, "named twice".into()));
        }
        if !mission.airspace.is_free(at) {
            return Err(bad(
                id,
                format!("{at} is outside the airspace or in an obstacle"),
            ));
        }
        if !rest.airspace.is_free(at) {
            return Err(bad(
                id,
                format!("it is at {at}, where a lost drone was last known"),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{DiscretePlan, PlanViolation, solve};

    fn formation_change() -> Mission {
        crate::mission::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/missions/formation-change.yaml"
        )))
        .expect("mission")
    }

    /// The formation change with a spare per group.
    fn formation_change_spares() -> Mission {
        crate::mission::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/missions/formation-change-spares.yaml"
        )))
        .expect("mission")
    }

    /// Every drone's voxel at `step` of `plan`, by id.
    fn at_step(plan: &DiscretePlan, step: u32) -> Vec<(&str, Voxel)> {
        plan.drones
            .iter()
            .map(|d| (d.id.as_str(), d.path[step as usize]))
            .collect()
    }

    /// No voxel is held by two drones at one step, and no two drones swap voxels.
    fn assert_conflict_free(plan: &DiscretePlan) {
        for t in 0..=plan.makespan_steps as usize {
            for (i, a) in plan.drones.iter().enumerate() {
                for b in &plan.drones[i + 1..] {
                    assert_ne!(a.path[t], b.path[t], "{} and {} at step {t}", a.id, b.id);
                    if t > 0 {
                        let swapped = a.path[t] == b.path[t - 1] && b.path[t] == a.path[t - 1];
                        assert!(!swapped, "{} and {} swap at step {t}", a.id, b.id);
                    }
                }
            }
        }
    }

    /// With everyone on their pads and nobody lost, the rest of the flight is the
    /// flight: the same legs with the same makespans.
    #[test]
    fn from_the_pads_with_nobody_lost_it_is_the_whole_plan() {
        let mission = formation_change();
        let options = PlanOptions::default();
        let whole = solve(&mission, &options).expect("plan").plan;
        let everyone = at_step(&whole, 0);
        let re = replan(&mission, 0, &everyone, &[], &options).expect("replan");
        let steps =
            |p: &DiscretePlan| -> Vec<u32> { p.legs.iter().map(|l| l.makespan_steps).collect() };
        assert_eq!(steps(&re.solution.plan), steps(&whole));
        assert_eq!(re.solution.plan.makespan_steps, whole.makespan_steps);
    }

    /// b1 lost where takeoff left it: the survivors start where they are, nobody is
    /// planned into b1's voxel or the column below it, blue's three survivors take
    /// three of its four goals, and everyone lands on a pad of its group (the
    /// mission's landing), one per pad.
    #[test]
    fn survivors_fly_on_around_a_lost_drones_column_and_land_on_their_pads_apart() {
        let mission = formation_change();
        let options = PlanOptions::default();
        let whole = solve(&mission, &options).expect("plan").plan;
        let after_takeoff = whole.legs[0].end_step;
        let everyone = at_step(&whole, after_takeoff);
        let (lost_id, lost_at) = everyone[0];
        assert_eq!(lost_id, "b1");
        let survivors: Vec<(&str, Voxel)> = everyone[1..].to_vec();
        let re = replan(&mission, 1, &survivors, &[lost_at], &options).expect("replan");
        let rest = &re.solution.plan;
        assert_eq!(rest.drones.len(), survivors.len());
        assert_conflict_free(rest);
        for d in &rest.drones {
            let start = survivors.iter().find(|s| s.0 == d.id).map(|s| s.1);
            assert_eq!(Some(d.path[0]), start, "{} starts where it is", d.id);
            for v in &d.path {
                let in_column = v.x == lost_at.x && v.y == lost_at.y && v.z <= lost_at.z;
                assert!(!in_column, "{} enters b1's column at {v:?}", d.id);
            }
            // Group pads: any survivor's pad of its group, one drone each.
            let group = re.mission.groups.iter().find(|g| g.name == d.group);
            let pads: Vec<Voxel> = group
                .map(|g| g.drones.iter().map(|m| m.pad_voxel()).collect())
                .unwrap_or_default();
            assert!(
                pads.contains(&d.goal),
                "{} lands on a pad of its group",
                d.id
            );
        }
        let mut landed: Vec<Voxel> = rest.drones.iter().map(|d| d.goal).collect();
        landed.sort_by_key(|v| (v.x, v.y, v.z));
        landed.dedup();
        assert_eq!(landed.len(), rest.drones.len(), "one drone per pad");
        let formation_end = rest.legs[0].end_step as usize;
        let blue = &mission.groups[0];
        let mut taken: Vec<Voxel> = rest
            .drones
            .iter()
            .filter(|d| d.group == blue.name)
            .map(|d| d.path[formation_end])
            .collect();
        assert_eq!(taken.len(), blue.drones.len() - 1);
        assert!(taken.iter().all(|v| blue.goals.contains(v)), "{taken:?}");
        taken.dedup();
        assert_eq!(taken.len(), blue.drones.len() - 1, "distinct goals");

        // The independent checker takes it against the survivors' mission...
        let check = |plan: &DiscretePlan| {
            crate::plan::validate_rest(&re.mission, re.from_leg, &survivors, plan)
        };
        assert_eq!(check(rest), Ok(()));
        // ...and refuses a path that starts elsewhere or enters b1's column.
        let mut moved = rest.clone();
        moved.drones[0].path[0] = lost_at;
        let violations = check(&moved).expect_err("refused");
        assert!(
            violations
                .iter()
                .any(|v| matches!(v, PlanViolation::WrongLiveStart { .. }))
                && violations
                    .iter()
                    .any(|v| matches!(v, PlanViolation::NotFree { .. })),
            "{violations:?}"
        );
    }

    /// A live state that does not fit the mission is refused naming the drone.
    #[test]
    fn bad_live_states_name_the_drone() {
        let mission = formation_change();
        let options = PlanOptions::default();
        let whole = solve(&mission, &options).expect("plan").plan;
        let everyone = at_step(&whole, whole.legs[0].end_step);
        let (_, b2_at) = everyone[1];
        let problem = |survivors: &[(&str, Voxel)], lost: &[Voxel], leg: usize| match replan(
            &mission, leg, survivors, lost, &options,
        ) {
            Err(PlanError::LiveState { drone, problem }) => format!("{drone}: {problem}"),
            other => panic!("refused, got {other:?}"),
        };
        assert!(problem(&[("zz", b2_at)], &[], 1).starts_with("zz: not a drone"));
        assert!(problem(&[("b2", b2_at), ("b2", b2_at)], &[], 1).contains("named twice"));
        assert!(
            problem(&[("b2", b2_at)], &[b2_at], 1).contains("where a lost drone was last known")
        );
        assert!(problem(&[("b2", b2_at)], &[], 99).contains("leg 99 does not exist"));
    }

    /// A survivor below a lost drone, in its column, is planned out of it: b2
    /// waits at its start under b1's last known voxel, one above. The plan takes
    /// b2 out and never back and nobody else through b2's voxel; b2's own pad is in
    /// the column, so blue lands on b1's instead.
    #[test]
    fn a_survivor_under_a_lost_drone_is_planned_out_of_its_column() {
        let mission = formation_change();
        let options = PlanOptions::default();
        let whole = solve(&mission, &options).expect("plan").plan;
        let everyone = at_step(&whole, whole.legs[0].end_step);
        let survivors: Vec<(&str, Voxel)> = everyone[1..].to_vec();
        let (b2, b2_at) = survivors[0];
        assert_eq!(b2, "b2");
        let lost = Voxel::new(b2_at.x, b2_at.y, b2_at.z + 1);
        let re = replan(&mission, 1, &survivors, &[lost], &options).expect("replan");
        let rest = &re.solution.plan;
        for d in &rest.drones {
            for (step, &v) in d.path.iter().enumerate() {
                if v == b2_at {
                    assert!(
                        d.id == "b2" && d.path[..step].iter().all(|&p| p == b2_at),
                        "{} at b2's voxel at step {step}",
                        d.id
                    );
                }
                let under = v.x == lost.x && v.y == lost.y && v.z <= lost.z;
                assert!(!under || v == b2_at, "{} in the column at {v}", d.id);
            }
        }
        let b2_path = &rest.drones.iter().find(|d| d.id == "b2").expect("b2").path;
        assert!(b2_path.iter().any(|&v| v != b2_at), "b2 leaves");
        let b1_pad = mission.groups[0].drones[0].pad_voxel();
        assert!(
            rest.drones.iter().any(|d| d.goal == b1_pad),
            "someone lands on b1's pad"
        );
        assert_eq!(
            crate::plan::validate_rest(&re.mission, re.from_leg, &survivors, rest),
            Ok(())
        );
    }

    /// b1 is lost over b2's pad (it may be in the pad-layer cells (0, 2), (1, 2)
    /// and (2, 2), as a flight saw it): b2 cannot land on its own pad,
    /// so one of blue lands on b1's, which b1 no longer needs (`group_pads`).
    #[test]
    fn a_pad_under_a_lost_drone_is_replaced_by_the_lost_drones_own() {
        let m = formation_change_spares();
        let v = Voxel::new;
        let at = [
            ("b2", v(7, 2, 1)),
            ("b3", v(7, 3, -1)),
            ("b4", v(5, 3, 1)),
            ("b5", v(0, 5, -1)),
            ("r1", v(0, 1, 1)),
            ("r2", v(1, 2, 1)),
            ("r3", v(1, 3, 1)),
            ("r4", v(0, 3, 1)),
            ("r5", v(7, 0, -1)),
        ];
        let lost = [v(0, 2, -1), v(1, 2, -1), v(2, 2, -1)];
        let re = replan(&m, 1, &at, &lost, &PlanOptions::default()).expect("a plan");
        let ends: Vec<Voxel> = re
            .solution
            .plan
            .drones
            .iter()
            .filter_map(|d| d.path.last().copied())
            .collect();
        assert!(!ends.contains(&v(0, 2, -1)), "nobody lands in b1's column");
        assert!(
            ends.contains(&v(0, 1, -1)),
            "someone lands on b1's pad: {ends:?}"
        );
        let starts: Vec<(&str, Voxel)> = at.to_vec();
        assert_eq!(
            crate::plan::validate_rest(&re.mission, re.from_leg, &starts, &re.solution.plan),
            Ok(())
        );
    }

    /// A spare takes the lost drone's goal: on the formation change with a spare
    /// per group, b1 is lost where takeoff left it; blue's four survivors, its
    /// spare b5 among them, end the formation on all four of blue's goals.
    #[test]
    fn a_spare_takes_the_lost_drones_goal() {
        let m = formation_change_spares();
        let options = PlanOptions::default();
        let whole = solve(&m, &options).expect("plan").plan;
        // As planned, b5 holds at its start while the others form the square.
        let formation_end = whole.legs[1].end_step as usize;
        let b5 = whole.drones.iter().find(|d| d.id == "b5").expect("b5");
        assert_eq!(Some(b5.path[formation_end]), m.groups[0].drones[4].start);
        let everyone = at_step(&whole, whole.legs[0].end_step);
        let (lost_id, lost_at) = everyone[0];
        assert_eq!(lost_id, "b1");
        let survivors: Vec<(&str, Voxel)> = everyone[1..].to_vec();
        let re = replan(&m, 1, &survivors, &[lost_at], &options).expect("replan");
        let rest = &re.solution.plan;
        let end = rest.legs[0].end_step as usize;
        let mut taken: Vec<Voxel> = rest
            .drones
            .iter()
            .filter(|d| d.group == "blue")
            .map(|d| d.path[end])
            .collect();
        taken.sort_unstable();
        let mut goals = m.groups[0].goals.clone();
        goals.sort_unstable();
        assert_eq!(taken, goals, "every blue goal taken, b5 included");
        assert_eq!(
            crate::plan::validate_rest(&re.mission, re.from_leg, &survivors, rest),
            Ok(())
        );
    }
}
