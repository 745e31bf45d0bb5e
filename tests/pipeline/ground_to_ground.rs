//! Whole flights, pad to pad: takeoff and landing as planned legs where starts and
//! goals are stacked, the three landing modes, spare goals, stages with holds, and
//! the plan file carrying pads and legs back to the flight.

use std::path::Path;
use swarmctl::compiled::{self, CompiledPlan};
use swarmctl::mission::{self, LegKind, Mission};
use swarmctl::plan::{self, DiscretePlan, PlanOptions};
use swarmctl::schedule;
use swarmctl::world::Voxel;

fn example(name: &str) -> Mission {
    mission::load(&crate::support::repo_path(&format!("missions/{name}"))).expect("mission")
}

fn load(yaml: &str) -> Mission {
    mission::from_yaml(yaml, Path::new("case.yaml")).unwrap_or_else(|e| panic!("{e}"))
}

/// Plans, validates and compiles (the checker measures the flight from the ground
/// up and back down, and compiling fails if any limit breaks).
fn fly_on_paper(m: &Mission) -> (DiscretePlan, CompiledPlan) {
    let solution = plan::solve(m, &PlanOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    if let Err(v) = plan::validate_plan(m, &solution.plan) {
        panic!("{}: {v:#?}", m.name);
    }
    let compiled = compiled::compile(m, &solution).unwrap_or_else(|e| panic!("{}: {e}", m.name));
    assert!(
        compiled.check.min_separation_bound_m >= m.limits.setpoint_separation_m(),
        "{}: {:?}",
        m.name,
        compiled.check
    );
    (solution.plan, compiled)
}

/// Where every drone is at the end of leg `k`.
fn at_leg_end(plan: &DiscretePlan, k: usize) -> Vec<Voxel> {
    let end = plan.legs[k].end_step as usize;
    plan.drones.iter().map(|d| d.path[end]).collect()
}

#[test]
fn stacked_starts_and_goals_take_off_and_land_apart() {
    // paper-scale stacks starts and goals in shared columns; pad to pad, the checker
    // measures the whole flight at or above the safety distance.
    let m = example("paper-scale.yaml");
    let stacked = m
        .groups
        .iter()
        .flat_map(|g| g.drones.iter())
        .filter_map(|d| d.start)
        .map(|s| (s.x, s.y))
        .collect::<Vec<_>>();
    let mut columns = stacked.clone();
    columns.sort_unstable();
    columns.dedup();
    assert!(columns.len() < stacked.len(), "the example stacks starts");
    let (plan, compiled) = fly_on_paper(&m);
    let kinds: Vec<LegKind> = plan.legs.iter().map(|l| l.kind).collect();
    assert_eq!(
        kinds,
        [LegKind::Takeoff, LegKind::Formation, LegKind::Landing]
    );
    for d in &plan.drones {
        assert_eq!(d.path[0].z, -1, "{} starts on the pad layer", d.id);
        assert_eq!(d.goal.z, -1, "{} ends on the pad layer", d.id);
    }
    for (k, leg) in plan.legs.iter().enumerate() {
        assert!(leg.makespan_steps >= leg.lower_bound_steps, "{}", leg.name);
        assert!(!at_leg_end(&plan, k).is_empty());
    }
    // The checked flight starts and ends on the ground.
    assert!(compiled.check.max_speed_mps <= m.limits.max_speed_mps + 1e-9);
}

const THREE_COLUMNS: &str = "
name: modes
world: { dimensions: [4, 3, 3], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 1.5] }
limits: { max_speed_mps: 1.0, max_accel_mps2: 2.0, safety_distance_m: 0.4 }
groups:
  - name: g
    drones: [{ id: a, pad: [0, 0] }, { id: b, pad: [0, 1] }, { id: c, pad: [0, 2] }]
    goals: [[3, 0, 2], [3, 1, 1], [3, 2, 0]]
";

#[test]
fn group_pads_own_pad_and_below_goal_landing() {
    let pads_of = |m: &Mission| -> Vec<Voxel> { m.drones().map(|(_, d)| d.pad_voxel()).collect() };
    // group_pads: the drones land on their group's pads, in any order.
    let m = load(THREE_COLUMNS);
    let (plan, _) = fly_on_paper(&m);
    let mut ends: Vec<Voxel> = plan.drones.iter().map(|d| d.goal).collect();
    let mut pads = pads_of(&m);
    ends.sort();
    pads.sort();
    assert_eq!(ends, pads);
    // own_pad: each back on its own.
    let m = load(&format!("{THREE_COLUMNS}landing: own_pad\n"));
    let (plan, _) = fly_on_paper(&m);
    let ends: Vec<Voxel> = plan.drones.iter().map(|d| d.goal).collect();
    assert_eq!(ends, pads_of(&m));
    // below_goal: straight down from the goal each took.
    let m = load(&format!("{THREE_COLUMNS}landing: below_goal\n"));
    let (plan, _) = fly_on_paper(&m);
    let formed = at_leg_end(&plan, 0);
    for (d, goal) in plan.drones.iter().zip(&formed) {
        assert_eq!(d.goal, goal.pad_below(), "{}", d.id);
        let landing = &d.path[plan.legs[0].end_step as usize..];
        assert!(
            landing.iter().all(|v| v.x == goal.x && v.y == goal.y),
            "{}",
            d.id
        );
    }
}

#[test]
fn spare_goals_leave_slots_empty() {
    let m = load(&THREE_COLUMNS.replace(
        "goals: [[3, 0, 2], [3, 1, 1], [3, 2, 0]]",
        "goals: [[3, 0, 2], [3, 1, 1], [3, 2, 0], [2, 1, 2], [1, 1, 1]]",
    ));
    let (plan, _) = fly_on_paper(&m);
    let formed = at_leg_end(&plan, 0);
    assert!(formed.iter().all(|v| m.groups[0].goals.contains(v)));
    // The far corner [3, 0, 2] costs six moves from the nearest pad; with the spare
    // slots nearer the pads the formation is reached sooner, leaving it empty.
    let (without, _) = fly_on_paper(&load(THREE_COLUMNS));
    assert!(
        plan.legs[0].makespan_steps < without.legs[0].makespan_steps,
        "{} vs {}",
        plan.legs[0].makespan_steps,
        without.legs[0].makespan_steps
    );
    assert!(!formed.contains(&Voxel::new(3, 0, 2)), "{formed:?}");
}

#[test]
fn stages_are_flown_in_order_with_their_holds() {
    let m = example("small-show.yaml");
    let (plan, compiled) = fly_on_paper(&m);
    let names: Vec<&str> = plan.legs.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["takeoff", "square", "tower", "ring", "landing"]);
    // Every stage's formation is formed when its leg ends.
    for (k, stage) in m.stages.iter().enumerate() {
        let formed = at_leg_end(&plan, k + 1);
        for (gi, g) in m.groups.iter().enumerate() {
            let goals = stage.goals[gi]
                .as_ref()
                .expect("the stage names every group");
            for (i, _) in g.drones.iter().enumerate() {
                let offset: usize = m.groups[..gi].iter().map(|g| g.drones.len()).sum();
                assert!(
                    goals.contains(&formed[offset + i]),
                    "{} in {}",
                    g.name,
                    stage.name
                );
            }
        }
    }
    // The schedule holds: nobody leaves the square before everyone has been in it
    // for its 3 s, nor the tower before 2 s.
    let tpg = schedule::build(&m, &plan).expect("tpg");
    let sched = schedule::solve(&tpg).expect("schedule");
    for (k, hold_s) in [(1, 3.0), (2, 2.0)] {
        let end = plan.legs[k].end_step;
        let formed_s = tpg
            .drones
            .iter()
            .zip(&sched.drones)
            .map(|(d, s)| {
                let i = d.events.iter().rposition(|e| e.step <= end).expect("event");
                s.events[i].reach_s
            })
            .fold(0.0, f64::max);
        for (d, s) in tpg.drones.iter().zip(&sched.drones) {
            let i = d.events.iter().rposition(|e| e.step <= end).expect("event");
            assert!(
                s.events[i].leave_s >= formed_s + hold_s - 1e-9,
                "{} leaves {} at {:.2} s, formed at {formed_s:.2} s",
                d.id,
                plan.legs[k].name,
                s.events[i].leave_s
            );
        }
    }
    assert!(compiled.makespan_s > 5.0);
}

#[test]
fn plan_files_round_trip_with_pads_and_legs() {
    let m = example("small-show.yaml");
    let (plan, compiled) = fly_on_paper(&m);
    let json = serde_json::to_vec(&compiled).expect("serialises");
    let back = compiled::file::from_bytes(&json, Path::new("show.json"), &m).expect("reads back");
    assert_eq!(back.discrete(), plan);
    // What is flown is what the file holds: the same samples, checked.
    assert_eq!(back.compiled().drones.len(), compiled.drones.len());
    assert!(back.figures().passed());
    assert_eq!(compiled.legs, plan.legs);
    let pads: Vec<[i32; 2]> = compiled.drones.iter().map(|d| d.pad).collect();
    let want: Vec<[i32; 2]> = m.drones().map(|(_, d)| d.pad).collect();
    assert_eq!(pads, want);
    // A plan for other stages is refused with the legs named.
    let other = example("formation-change.yaml");
    let e = compiled::file::from_bytes(&json, Path::new("show.json"), &other).unwrap_err();
    assert!(e.to_string().contains("show.json"), "{e}");
}
