//! Judging a flown scenario: what happened (the flight's result, the simulator's
//! truth, who is still armed) held against what the scenario promises and the
//! mission's safety distance.

use super::cases::{Expect, Scenario};
use super::report::{ScenarioReport, describe_error, describe_log};
use std::time::Duration;
use swarmctl::fly::{FlightLog, FlyError};
use swarmctl::mission::Mission;

/// A scenario's flight and what the simulator saw of it.
pub(super) struct Flown {
    /// The flight's result, or `Err` if it hit the limit.
    pub(super) result: Result<Result<FlightLog, FlyError>, tokio::time::error::Elapsed>,
    /// Smallest true distance between two airborne vehicles, metres.
    pub(super) truth_m: f64,
    /// Under an ellipsoid, the smallest true scaled separation of two airborne
    /// vehicles.
    pub(super) truth_scaled: Option<f64>,
    /// Whether any vehicle left the ground.
    pub(super) ever_airborne: bool,
    /// System ids armed after the flight.
    pub(super) still_armed: Vec<u8>,
    /// Wall time of the flight, seconds.
    pub(super) duration_s: f64,
}

impl Flown {
    /// The report: what happened against what `scenario` promises.
    pub(super) fn judge(
        self,
        mission: &Mission,
        scenario: &Scenario,
        limit: Duration,
    ) -> ScenarioReport {
        let safety = mission.limits.safety_distance_m;
        let mut failures = Vec::new();
        let (observed, log) = match self.result {
            Err(_) => {
                failures.push(format!("did not finish within {limit:?}"));
                ("timed out".to_string(), None)
            }
            Ok(Err(e)) => (describe_error(&e), None),
            Ok(Ok(log)) => (describe_log(&log), Some(log)),
        };
        expectation_failures(
            &scenario.expect,
            log.as_ref(),
            self.ever_airborne,
            &mut failures,
        );
        let wrongly_armed = wrongly_armed(self.still_armed, log.as_ref());
        if !wrongly_armed.is_empty() {
            failures.push(format!("systems {wrongly_armed:?} still armed"));
        }
        let telemetry_m = log
            .as_ref()
            .map_or(f64::INFINITY, |l| l.summary.min_separation_m);
        let truth_m = self.truth_m;
        let scaled_telemetry_truth = self.truth_scaled.map(|truth| {
            let telemetry = log
                .as_ref()
                .and_then(|l| l.summary.min_scaled_separation)
                .unwrap_or(f64::INFINITY);
            (telemetry, truth)
        });
        match scaled_telemetry_truth {
            Some((telemetry, truth)) => {
                for (what, scaled) in [("telemetry", telemetry), ("true", truth)] {
                    if scaled < 1.0 {
                        failures.push(format!("{what} scaled separation {scaled:.3} < 1"));
                    }
                }
            }
            None => {
                if telemetry_m < safety {
                    failures.push(format!(
                        "telemetry separation {telemetry_m:.3} m < {safety} m"
                    ));
                }
                if truth_m < safety {
                    failures.push(format!("true separation {truth_m:.3} m < {safety} m"));
                }
            }
        }
        ScenarioReport {
            name: scenario.name.to_string(),
            faults: if scenario.faults.is_empty() {
                "—".into()
            } else {
                scenario.faults.join(" ")
            },
            expected: scenario.expect.describe(),
            observed,
            min_separation_telemetry_m: telemetry_m,
            min_separation_truth_m: truth_m,
            safety_distance_m: safety,
            scaled_telemetry_truth,
            duration_s: self.duration_s,
            passed: failures.is_empty(),
            failures,
            log,
        }
    }
}

/// Where the flight (its log, if it ran to its end) broke the promise `expect`.
fn expectation_failures(
    expect: &Expect,
    log: Option<&FlightLog>,
    ever_airborne: bool,
    failures: &mut Vec<String>,
) {
    match (expect, log) {
        (Expect::AbortsOnGround, None) if !ever_airborne => {}
        (Expect::AbortsOnGround, _) => failures.push("expected a refusal on the ground".into()),
        (_, None) => failures.push("expected a flight".into()),
        (Expect::Completes, Some(log)) => {
            if !log.summary.completed {
                failures.push("not every drone reached its goal".into());
            }
        }
        (Expect::Lost { drone }, Some(log)) => {
            if log.summary.lost != [drone.to_string()] {
                failures.push(format!("lost {:?}, expected [{drone}]", log.summary.lost));
            }
        }
        (Expect::Replanned { drone }, Some(log)) => {
            let s = &log.summary;
            if s.lost != [drone.to_string()] {
                failures.push(format!("lost {:?}, expected [{drone}]", s.lost));
            }
            let spliced: Vec<_> = s.replans.iter().filter(|r| r.fallback.is_none()).collect();
            if spliced.len() != 1 || spliced[0].left_out != [drone.to_string()] {
                failures.push(format!(
                    "expected one replan without {drone}: {:?}",
                    s.replans
                ));
            }
            if !s.completed {
                failures.push("the survivors did not complete the replanned flight".into());
            }
        }
        (Expect::FallsBack { drone }, Some(log)) => {
            let s = &log.summary;
            if s.lost != [drone.to_string()] {
                failures.push(format!("lost {:?}, expected [{drone}]", s.lost));
            }
            if !s.replans.iter().all(|r| r.fallback.is_some()) || s.replans.is_empty() {
                failures.push(format!(
                    "expected a replan that falls back: {:?}",
                    s.replans
                ));
            }
            if s.completed {
                failures.push("completed although the replan fell back".into());
            }
        }
        (Expect::Retires { drone }, Some(log)) => {
            if log.summary.retired != [drone.to_string()] {
                failures.push(format!(
                    "retired {:?}, expected [{drone}]",
                    log.summary.retired
                ));
            }
            if !log.summary.lost.is_empty() || !log.summary.handed_over.is_empty() {
                failures.push("someone else was lost or handed over".into());
            }
        }
    }
}

/// The armed systems that should not be: lost and handed-over drones hover on by
/// design; everybody else must be disarmed.
fn wrongly_armed(still_armed: Vec<u8>, log: Option<&FlightLog>) -> Vec<u8> {
    let lost_ids: Vec<u8> = log.map_or(Vec::new(), |l| {
        l.drones
            .iter()
            .filter(|d| l.summary.lost.contains(&d.id) || l.summary.handed_over.contains(&d.id))
            .map(|d| d.system_id)
            .collect()
    });
    still_armed
        .into_iter()
        .filter(|id| !lost_ids.contains(id))
        .collect()
}
