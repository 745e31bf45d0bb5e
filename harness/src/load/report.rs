//! What a load run measured, and what of it counts as a failure.

use swarmctl::fly::FlightLog;
use swarmctl_sitl::swarm::SetpointIntervals;
use swarmctl_sitl::{LinkStats, TickStats};

/// CPU time over the flight, seconds, split by thread.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CpuUse {
    /// Wall time of the flight, seconds: what the CPU seconds are shares of.
    pub wall_s: f64,
    /// The whole process.
    pub total_s: f64,
    /// The SITL runtime's threads.
    pub sitl_s: f64,
    /// The truth watcher (this benchmark's own measuring).
    pub watch_s: f64,
    /// Busiest [`PEAK_WINDOW_S`](super::PEAK_WINDOW_S) s of the whole process, CPU s per wall s.
    pub peak_total_share: f64,
    /// Busiest [`PEAK_WINDOW_S`](super::PEAK_WINDOW_S) s of the controller, CPU s per wall s.
    pub peak_controller_share: f64,
}

impl CpuUse {
    /// Everything but the SITL and the watcher, seconds.
    pub fn controller_s(&self) -> f64 {
        (self.total_s - self.sitl_s - self.watch_s).max(0.0)
    }

    /// Percent of one core.
    pub fn percent(&self, cpu_s: f64) -> f64 {
        if self.wall_s > 0.0 {
            100.0 * cpu_s / self.wall_s
        } else {
            0.0
        }
    }
}

/// What one load run measured.
#[derive(Debug, Clone)]
pub struct LoadReport {
    /// Drones flown, one SITL vehicle each.
    pub vehicles: usize,
    /// The seed of the mission and the planner.
    pub seed: u64,
    /// The generated mission's name.
    pub mission: String,
    /// Wall time of each planning run, seconds.
    pub plan_times_s: Vec<f64>,
    /// Length of the flown plan, in plan steps.
    pub makespan_steps: u32,
    /// The flight log, if the flight ran to its end.
    pub log: Option<FlightLog>,
    /// How the flight ended, in words.
    pub observed: String,
    /// Vehicles resting disarmed within [`AT_GOAL_TOLERANCE_M`](super::AT_GOAL_TOLERANCE_M) of the point below
    /// their goal (simulator truth).
    pub at_goal: usize,
    /// Largest horizontal distance of a vehicle from below its goal (truth), metres.
    pub max_goal_error_m: f64,
    /// System ids still armed after the flight.
    pub still_armed: Vec<u8>,
    /// Wall time of the flight, seconds (takeoff to landing, or to the limit).
    pub flight_wall_s: f64,
    /// CPU time over the flight, by thread.
    pub cpu: CpuUse,
    /// Every vehicle's setpoint intervals together.
    pub setpoints: SetpointIntervals,
    /// The worst single vehicle's p99 interval, seconds.
    pub worst_vehicle_p99_s: f64,
    /// Link counters summed over the vehicles.
    pub link: LinkStats,
    /// Link losses the controller noticed, summed over the drones.
    pub controller_link_losses: usize,
    /// The SITL physics ticker over the flight.
    pub ticks: TickStats,
    /// Telemetry, whole flight pad to pad (∞ if fewer than two flew).
    pub min_separation_telemetry_m: f64,
    /// Simulator truth, whole flight, airborne pairs.
    pub min_separation_truth_m: f64,
    /// The mission's safety distance, metres: what the separations must keep
    /// (under an ellipsoid its horizontal radius; the scaled separations decide).
    pub safety_distance_m: f64,
    /// Under an ellipsoid, the scaled separation from telemetry and from truth,
    /// whole flight (separated at 1 or more); `None` for a sphere.
    pub scaled_telemetry_truth: Option<(f64, f64)>,
    /// Process peak resident memory (`VmHWM`), bytes: planning included; 0 where
    /// unknown (not Linux).
    pub peak_rss_bytes: u64,
    /// Highest resident memory sampled during the flight (once a second), bytes.
    pub flight_max_rss_bytes: u64,
    /// Open file descriptors before the runtimes and vehicles start.
    pub fds_before: usize,
    /// Most open file descriptors sampled during the flight.
    pub fds_max: usize,
    /// Open file descriptors once the vehicles and runtimes are gone.
    pub fds_after: usize,
    /// What went wrong; empty if the run is correct (speed is not judged).
    pub failures: Vec<String>,
}

impl LoadReport {
    /// Whether the run was correct: nothing in [`LoadReport::failures`].
    pub fn passed(&self) -> bool {
        self.failures.is_empty()
    }

    /// Whether the flight ran to its end with every drone at its goal.
    pub fn completed(&self) -> bool {
        self.log.as_ref().is_some_and(|l| l.summary.completed)
    }
}

/// How a completed flight went, in words.
pub(super) fn describe(log: &FlightLog) -> String {
    let s = &log.summary;
    if s.completed {
        format!(
            "completed, plan {:.1} s (planned {:.1} s), {} gating waits",
            s.executed_makespan_s.unwrap_or(f64::NAN),
            s.planned_makespan_s,
            s.gating_waits
        )
    } else {
        "not completed".into()
    }
}

/// What the flight log shows wrong: drones short of their goal, lost, retired or
/// handed over.
pub(super) fn log_failures(log: &FlightLog, failures: &mut Vec<String>) {
    if !log.summary.completed {
        failures.push("not every drone reached its goal".into());
    }
    for (what, names) in [
        ("lost", &log.summary.lost),
        ("retired", &log.summary.retired),
        ("handed over", &log.summary.handed_over),
    ] {
        if !names.is_empty() {
            failures.push(format!("{what}: {}", names.join(", ")));
        }
    }
}

/// What the vehicles show wrong after the flight, then every separation below
/// the safety distance. Adds to `failures` (which may already name the flight's
/// own failures).
pub(super) fn vehicle_and_separation_failures(report: &LoadReport, failures: &mut Vec<String>) {
    if report.at_goal != report.vehicles {
        failures.push(format!(
            "{}/{} vehicles landed disarmed below their goal (worst {:.2} m off)",
            report.at_goal, report.vehicles, report.max_goal_error_m
        ));
    }
    if !report.still_armed.is_empty() {
        failures.push(format!("systems {:?} still armed", report.still_armed));
    }
    if report.link.tx_errors > 0 {
        failures.push(format!("{} vehicle send errors", report.link.tx_errors));
    }
    if let Some((telemetry, truth)) = report.scaled_telemetry_truth {
        for (what, scaled) in [("telemetry", telemetry), ("true", truth)] {
            if scaled < 1.0 {
                failures.push(format!("{what} scaled separation {scaled:.3} < 1"));
            }
        }
        return;
    }
    let safety = report.safety_distance_m;
    for (what, m) in [
        ("telemetry", report.min_separation_telemetry_m),
        ("true", report.min_separation_truth_m),
    ] {
        if m < safety {
            failures.push(format!("{what} separation {m:.3} m < {safety} m"));
        }
    }
}
