//! Shared helpers for the `fly_*` end-to-end tests: plan a mission, start the
//! bundled SITL with faults, fly it, and check the log.
#![allow(dead_code)] // each test uses a different subset

use std::time::Duration;
use swarmctl::fly::{self, FlightLog, FlyError};
use swarmctl::mission::{self, Mission};
use swarmctl::plan::{self, DiscretePlan};
use swarmctl_sitl::Flavour;
use swarmctl_sitl::faults::{FaultSpec, parse_fault};

pub fn load(path: &str) -> (Mission, DiscretePlan) {
    let mission = mission::load(&crate::support::repo_path(path)).expect("mission loads");
    let plan = plan::solve(&mission, &plan::PlanOptions::default())
        .expect("mission plans")
        .plan;
    (mission, plan)
}

/// Flies `mission` on the bundled SITL with the given flavour and faults, with an
/// overall time limit so a hung flight fails the test instead of hanging it.
pub async fn fly_bundled(
    mission: &Mission,
    plan: &DiscretePlan,
    flavour: Flavour,
    faults: &[&str],
    limit: Duration,
) -> Result<FlightLog, FlyError> {
    let faults: Vec<FaultSpec> = faults
        .iter()
        .map(|f| parse_fault(f).expect("fault flag"))
        .collect();
    let configs =
        swarmctl_bundled::vehicle_configs(mission, plan, flavour, &faults).expect("configs");
    let (swarm, links) = swarmctl_bundled::start(configs, mission.link.setpoint_rate_hz)
        .await
        .expect("sitl");
    let options = swarmctl_bundled::fly_options(links);
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let result = tokio::time::timeout(limit, fly::fly(mission, plan, &options, abort_rx))
        .await
        .expect("flight finished within its time limit");
    // Nobody may be left armed, whatever happened.
    for i in 0..plan.drones.len() {
        let s = swarm.snapshot(i);
        assert!(
            !s.armed,
            "vehicle {} still armed after the flight",
            s.system_id
        );
    }
    swarm.shutdown().await;
    result
}

/// Every drone reached its goal, separation from telemetry held, limits held.
pub fn assert_success(log: &FlightLog) {
    let s = &log.summary;
    for line in s.lines() {
        eprintln!("{line}");
    }
    assert!(s.completed, "flight did not complete: {:?}", log.events);
    assert!(s.safety_held, "safety not held");
    assert!(s.speed_held, "speed limit not held");
    assert!(
        s.min_separation_m >= s.safety_distance_m,
        "separation {} m below safety distance {} m",
        s.min_separation_m,
        s.safety_distance_m
    );
    assert!(
        s.max_final_distance_to_goal_m <= 0.1,
        "a drone ended {} m from its goal",
        s.max_final_distance_to_goal_m
    );
    // Telemetry speed includes the vehicle's own tracking; allow sensor noise.
    assert!(
        s.max_speed_mps <= s.speed_limit_mps * 1.05,
        "telemetry speed {} m/s over the limit {}",
        s.max_speed_mps,
        s.speed_limit_mps
    );
    for d in &log.drones {
        assert!(!d.samples.is_empty(), "{} has telemetry samples", d.id);
        // The bundled vehicles track their setpoints closely; a real one is measured
        // the same way and reported.
        let t = d
            .tracking_error
            .unwrap_or_else(|| panic!("{} has no tracking error", d.id));
        assert!(
            t.median_m <= t.p95_m && t.p95_m <= t.max_m,
            "{}: {t:?}",
            d.id
        );
    }
    assert!(
        s.worst_tracking.is_some(),
        "the summary names the worst tracker"
    );
    // The checker ran before arming, on what was flown, and its figures are logged.
    let check = s.check.as_ref().expect("the pre-flight check's figures");
    assert!(check.passed(), "{}", check.line());
    assert_eq!(check.drones, log.drones.len());
    assert!(check.samples > 1);
    assert!(
        check.min_separation_bound_m >= check.required_separation_m,
        "{}",
        check.line()
    );
    assert!(check.required_separation_m >= s.safety_distance_m);
    assert!(
        check.max_speed_mps <= s.speed_limit_mps + 1e-9,
        "{}",
        check.line()
    );
    assert!(
        s.lines().iter().any(|l| l.contains("pre-flight check")),
        "the summary prints it"
    );
}

/// Each drone's measured link, each way, is within 10 % of the link budget:
/// the budget counts what the flight sends, and pre-flight turned off the
/// streams it does not count.
pub fn assert_traffic_within_budget(log: &FlightLog) {
    for d in &log.drones {
        let t = d.link_traffic.expect("measured link traffic");
        for (way, measured, budget) in [
            ("up", t.up_kbps, t.budget_up_kbps),
            ("down", t.down_kbps, t.budget_down_kbps),
        ] {
            assert!(
                (measured / budget - 1.0).abs() <= 0.10,
                "{}: {way} {measured:.2} kbit/s measured against {budget:.2} kbit/s budgeted",
                d.id
            );
        }
    }
}
