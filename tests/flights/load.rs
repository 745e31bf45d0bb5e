//! The load benchmark in the reduced form CI runs: a 60-drone generated mission
//! planned and flown on 60 bundled SITL vehicles in this process, through the same
//! library function as `swarmctl bench load` (which flies 200). The flight must
//! complete with every vehicle landed, disarmed, below its goal, the safety
//! distance kept in telemetry and in the simulator's truth, and no send errors.
//! Speed is not judged here; the benchmark reports it.

use std::time::Duration;
use swarmctl_harness::load::{LoadOptions, markdown_table, run_load};

const VEHICLES: usize = 60;

#[test]
fn sixty_vehicles_fly_the_load_mission_correctly() {
    let mut options = LoadOptions::new(VEHICLES, 1);
    options.limit = Duration::from_secs(300);
    let report = run_load(&options).expect("the load benchmark runs");
    eprintln!("{}", markdown_table(std::slice::from_ref(&report)));
    if let Some(log) = &report.log {
        for e in &log.events {
            eprintln!("{:6.1} s {:?} {}", e.t_s, e.drone, e.message);
        }
    }

    let log = report.log.as_ref().expect("the flight ran to its end");
    assert!(log.summary.completed, "{}", report.observed);
    assert!(
        log.summary.lost.is_empty()
            && log.summary.retired.is_empty()
            && log.summary.handed_over.is_empty(),
        "{}",
        log.summary.lines().join("\n")
    );
    assert_eq!(report.vehicles, VEHICLES);
    assert_eq!(
        report.at_goal, VEHICLES,
        "landed below their goal (worst {:.2} m off)",
        report.max_goal_error_m
    );
    assert!(report.still_armed.is_empty(), "{:?}", report.still_armed);
    let safety = report.safety_distance_m;
    assert!(
        report.min_separation_telemetry_m >= safety,
        "telemetry {:.3} m",
        report.min_separation_telemetry_m
    );
    assert!(
        report.min_separation_truth_m.is_finite() && report.min_separation_truth_m >= safety,
        "truth {:.3} m",
        report.min_separation_truth_m
    );
    assert_eq!(report.link.tx_errors, 0, "vehicle send errors");
    assert_eq!(report.link.rx_undecodable, 0);
    assert_eq!(report.link.rx_bad_signature, 0);
    // Every vehicle heard a setpoint stream (counts, not timing).
    assert!(
        report.setpoints.count() >= VEHICLES as u64 * 20,
        "{} setpoint intervals",
        report.setpoints.count()
    );
    assert!(report.failures.is_empty(), "{:?}", report.failures);
    // Nothing the flight opened outlives it (tokio keeps one process-wide signal
    // socket pair from the first runtime on).
    assert!(
        report.fds_after <= report.fds_before + 4,
        "fds {} before, {} after",
        report.fds_before,
        report.fds_after
    );
}
