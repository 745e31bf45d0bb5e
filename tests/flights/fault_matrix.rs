//! The reduced fault matrix CI runs: the scenarios no other end-to-end test
//! covers, each flown on the bundled SITL with the formation change. Every one
//! must show its promised behaviour and keep the safety distance, measured both
//! from telemetry and from the simulator's true positions. The full matrix is
//! `swarmctl bench faults`.

use std::time::Duration;
use swarmctl::plan;
use swarmctl_harness::fault_matrix::{ScenarioReport, run_scenario, scenarios};

const LIMIT: Duration = Duration::from_secs(150);

async fn fly(name: &str) -> ScenarioReport {
    let mission =
        swarmctl::mission::load(&crate::support::repo_path("missions/formation-change.yaml"))
            .expect("mission");
    let plan = plan::solve(&mission, &plan::PlanOptions::default())
        .expect("plan")
        .plan;
    let scenario = scenarios(true)
        .into_iter()
        .find(|s| s.name == name)
        .expect("scenario in the reduced matrix");
    let report = run_scenario(&mission, &plan, &scenario, LIMIT)
        .await
        .expect("scenario runs");
    if let Some(log) = &report.log {
        for e in &log.events {
            eprintln!("{:6.1} s {:?} {}", e.t_s, e.drone, e.message);
        }
    }
    eprintln!(
        "{}: {} (telemetry {:.3} m, truth {:.3} m)",
        report.name,
        report.observed,
        report.min_separation_telemetry_m,
        report.min_separation_truth_m
    );
    assert!(report.passed, "{}: {:?}", report.name, report.failures);
    report
}

fn reported(report: &ScenarioReport, drone: &str, text: &str) -> bool {
    report.log.as_ref().is_some_and(|log| {
        log.events
            .iter()
            .any(|e| e.drone.as_deref() == Some(drone) && e.message.contains(text))
    })
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn thirty_percent_loss_completes() {
    fly("loss 30%").await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_hundred_ms_latency_completes() {
    fly("latency 200 ms each way").await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn duplicated_and_reordered_packets_complete() {
    fly("duplicated 20% + reordered 20%").await;
}

/// b1's link goes for good 5 s after takeoff: it is reported lost, the swarm
/// freezes at voxel centres, the survivors are replanned without it (its last
/// voxels and their columns blocked) and complete the flight: every survivor on a
/// goal, then landed.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_drone_lost_for_good_is_replanned_around_and_the_rest_complete() {
    let report = fly("b1 lost for good").await;
    assert!(reported(&report, "b1", "LOST"), "b1's loss is in the log");
    let log = report.log.expect("flight log");
    assert!(log.summary.completed, "{:?}", log.summary.replans);
    let replan = &log.summary.replans[0];
    assert_eq!(replan.left_out, ["b1"]);
    assert!(replan.new_makespan_s.is_some_and(|s| s > 0.0));
    // The spliced trajectories were checked before they flew, inside the deadline.
    let check = replan.check.as_ref().expect("the replan's check figures");
    assert!(check.passed(), "{}", check.line());
    assert_eq!(check.drones, 7, "the survivors");
    assert!(check.min_separation_bound_m >= check.required_separation_m);
    assert!(check.check_s <= replan.planning_s);
    assert!(log.summary.check.is_some(), "and the plan before arming");
    assert!(
        log.events
            .iter()
            .any(|e| e.message.starts_with("replanned without b1")),
        "the splice is in the log"
    );
    // The survivors landed on their pads; b1's last report (hovering where it was
    // lost) is not a landing and is left out.
    assert!(
        log.summary.max_final_distance_to_goal_m < 0.2,
        "final pad distance {} m",
        log.summary.max_final_distance_to_goal_m
    );
}

/// A crash is a loss that is not hovering: b1's motors stop 5 s after takeoff, it
/// falls and never speaks again. It is reported lost, the survivors are replanned
/// around the column it fell through, and they complete and land apart (truth:
/// airborne pairs, the fall included).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_crashed_drone_is_replanned_around_and_the_rest_land_apart() {
    let report = fly("b1 crashes (falls, silent)").await;
    assert!(reported(&report, "b1", "LOST"), "b1's loss is in the log");
    let log = report.log.expect("flight log");
    assert!(log.summary.completed, "{:?}", log.summary.replans);
    assert_eq!(log.summary.lost, ["b1"]);
}

/// With no time to replan the flight falls back to what it did before replanning
/// existed, and says why: b1's dependants hold, the rest finish and land.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_replan_out_of_time_falls_back_to_holding() {
    let report = fly("b1 lost, no time to replan (`--replan-deadline 0`)").await;
    let log = report.log.expect("flight log");
    assert!(!log.summary.completed);
    assert!(log.summary.gating_waits > 0, "somebody waited for b1");
    assert!(
        log.events
            .iter()
            .any(|e| e.message.starts_with("no replan without b1")),
        "the fallback is in the log"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn low_battery_drone_leaves_the_plan_and_the_rest_finish() {
    let report = fly("r1 low battery").await;
    assert!(reported(&report, "r1", "battery low"));
    assert!(reported(&report, "r1", "released"));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn autopilot_battery_failsafe_is_not_fought() {
    let report = fly("r1 critical battery (autopilot lands it)").await;
    assert!(reported(&report, "r1", "autopilot failsafe took over"));
    assert!(
        !reported(&report, "r1", "re-entering"),
        "the executor never fights the failsafe for OFFBOARD"
    );
}

/// A group with a spare completes its formation after a loss: on the formation
/// change with one spare per group (`missions/formation-change-spares.yaml`), b1
/// is lost 12 s after takeoff, the replan sends blue's spare to its goal, and after
/// the replan every goal of both groups is reached by a different drone. (Lost at
/// 5 s, b1 is between its own pad and b2's: both columns are blocked, four blue
/// drones are left three pads, and the flight rightly falls back.)
///
/// Ignored in CI: where the freeze leaves the drones depends on timing, and under
/// CI's load one run found no plan ("group red cannot be matched to distinct
/// reachable goals", 2026-12-03) and fell back safely; `plan::replan`'s
/// `a_spare_takes_the_lost_drones_goal` checks the same from a fixed state.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
#[ignore = "timing-dependent freeze state; run with --ignored"]
async fn a_spare_takes_the_lost_drones_goal() {
    use swarmctl_harness::fault_matrix::{Expect, Scenario};
    let mission = swarmctl::mission::load(&crate::support::repo_path(
        "missions/formation-change-spares.yaml",
    ))
    .expect("mission");
    let plan = plan::solve(&mission, &plan::PlanOptions::default())
        .expect("plan")
        .plan;
    let scenario = Scenario {
        name: "b1 lost, a spare per group",
        faults: vec!["lose=b1@12s"],
        flavour: swarmctl_sitl::Flavour::Px4,
        expect: Expect::Replanned { drone: "b1" },
        replan: swarmctl::fly::ReplanOptions::default(),
    };
    let report = run_scenario(&mission, &plan, &scenario, LIMIT)
        .await
        .expect("scenario runs");
    let log = report.log.as_ref().expect("flight log");
    for e in &log.events {
        eprintln!("{:6.1} s {:?} {}", e.t_s, e.drone, e.message);
    }
    assert!(report.passed, "{:?}", report.failures);
    let replanned_at_s = log.summary.replans[0].at_s;
    // Which drones (never b1) came within 0.3 m of each goal after the replan; a
    // drone passing a goal on its way counts for it too, so ask for a matching:
    // every goal taken by a drone of its own.
    let reached: Vec<Vec<usize>> = mission
        .groups
        .iter()
        .flat_map(|g| &g.goals)
        .map(|goal| {
            let c = mission.airspace.center_m(*goal);
            (0..log.drones.len())
                .filter(|&i| log.drones[i].id != "b1")
                .filter(|&i| {
                    log.drones[i].samples.iter().any(|s| {
                        s[0] > replanned_at_s
                            && ((s[1] - c.x).powi(2) + (s[2] - c.y).powi(2) + (s[3] - c.z).powi(2))
                                .sqrt()
                                < 0.3
                    })
                })
                .collect()
        })
        .collect();
    assert!(
        reached.iter().all(|r| !r.is_empty()),
        "a goal nobody reached: {reached:?}"
    );
    assert_eq!(
        plan::maximum_matching(&reached, log.drones.len()),
        8,
        "every goal by its own drone: {reached:?}"
    );
}
