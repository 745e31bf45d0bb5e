//! Reduced soak: three flights back to back in one process must leave no file
//! descriptors behind and keep memory flat. `swarmctl bench soak` runs ten.

use std::time::Duration;
use swarmctl::plan;
use swarmctl_harness::fault_matrix::{Expect, Scenario, run_scenario};
use swarmctl_harness::process_resources;
use swarmctl_sitl::Flavour;

/// Set in the child process that runs the soak alone.
const ALONE: &str = "SWARMCTL_SOAK_ALONE";

/// The flights binary runs its tests in parallel in one process, and every flight
/// opens sockets; descriptors are counted per process, so the soak re-runs itself
/// alone in a child process of this same binary and asserts there.
#[test]
fn three_flights_back_to_back_leak_no_descriptors() {
    if std::env::var_os(ALONE).is_some() {
        soak_alone();
        return;
    }
    let exe = std::env::current_exe().expect("test binary path");
    let status = std::process::Command::new(exe)
        .args([
            "soak::three_flights_back_to_back_leak_no_descriptors",
            "--exact",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(ALONE, "1")
        .status()
        .expect("run the soak alone");
    assert!(status.success(), "the soak failed when run alone: {status}");
}

fn soak_alone() {
    let mission =
        swarmctl::mission::load(&crate::support::repo_path("missions/swap-corridor.yaml"))
            .expect("mission");
    let plan = plan::solve(&mission, &plan::PlanOptions::default())
        .expect("plan")
        .plan;
    let runtime = tokio::runtime::Runtime::new().expect("runtime");
    let scenario = Scenario {
        name: "soak",
        faults: Vec::new(),
        flavour: Flavour::Px4,
        expect: Expect::Completes,
        replan: swarmctl::fly::ReplanOptions::default(),
    };
    let mut after = Vec::new();
    for _ in 0..3 {
        let report = runtime
            .block_on(run_scenario(
                &mission,
                &plan,
                &scenario,
                Duration::from_secs(120),
            ))
            .expect("flight runs");
        assert!(report.passed, "{:?}", report.failures);
        after.push(process_resources());
    }
    eprintln!("{after:?}");
    assert_eq!(
        after[0].open_fds, after[2].open_fds,
        "open file descriptors grew from flight 1 to flight 3"
    );
    let growth_mib = (after[2].rss_bytes as f64 - after[1].rss_bytes as f64) / 1048576.0;
    assert!(
        growth_mib < 8.0,
        "resident memory grew {growth_mib:.1} MiB from flight 2 to flight 3"
    );
}
