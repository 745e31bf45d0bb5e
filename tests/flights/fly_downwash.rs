//! Downwash-aware separation flown: `missions/downwash-crossing.yaml`, where a
//! sphere would let one drone pass right under the other and the ellipsoid makes
//! it climb over, on the bundled SITL. The scaled separation must stay at 1 or
//! more from telemetry and from the simulator's truth, pad to pad.

use std::time::Duration;
use swarmctl::plan;
use swarmctl_harness::fault_matrix::{run_scenario, scenarios};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn drones_cross_outside_each_others_downwash() {
    let mission = swarmctl::mission::load(&crate::support::repo_path(
        "missions/downwash-crossing.yaml",
    ))
    .expect("mission");
    let plan = plan::solve(&mission, &plan::PlanOptions::default())
        .expect("plan")
        .plan;
    let scenario = scenarios(false)
        .into_iter()
        .find(|s| s.name == "no faults")
        .expect("the no-fault scenario");
    let report = run_scenario(&mission, &plan, &scenario, Duration::from_secs(120))
        .await
        .expect("scenario runs");
    let log = report.log.as_ref().expect("a flight log");
    for line in log.summary.lines() {
        eprintln!("{line}");
    }
    assert!(report.passed, "{:?}", report.failures);
    let (telemetry, truth) = report.scaled_telemetry_truth.expect("scaled separations");
    assert!(telemetry >= 1.0 && truth >= 1.0, "{telemetry} / {truth}");
    assert_eq!(log.summary.min_scaled_separation, Some(telemetry));
    assert!(log.summary.completed && log.summary.safety_held);
    // Passing under would have put them 1 m apart vertically (scaled 1/1.2);
    // the climb keeps them at least 2 m apart in any shared column.
    assert!(truth > 1.2, "truth scaled separation {truth}");
}
