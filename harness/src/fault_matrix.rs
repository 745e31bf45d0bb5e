//! The fault matrix: one mission flown on the bundled SITL under each fault a
//! real swarm meets (lossy, slow and reordering links, a link cut or lost, a
//! drone refusing to arm, slow, or low on battery), each with the behaviour swarmctl promises, checked
//! against what happened.
//!
//! Separation is measured twice: from telemetry during plan execution (what the
//! executor saw) and from the simulator's true positions over the whole flight,
//! takeoff and landing included, for every airborne pair (what really happened,
//! including drones the executor could no longer hear).

use crate::HarnessError;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;
use swarmctl::fly::replan::ReplanOptions;
use swarmctl::fly::{self, FaultSpec, FlightLog, FlyError};
use swarmctl::mission::Mission;
use swarmctl::plan::DiscretePlan;
use swarmctl::world::Separation;
use swarmctl_sitl::{Flavour, Swarm};

/// What a scenario must do.
#[derive(Debug, Clone, PartialEq)]
pub enum Expect {
    /// Every drone reaches its goal and lands.
    Completes,
    /// The flight is refused before anybody leaves the ground.
    AbortsOnGround,
    /// `drone` is reported lost; everybody else lands or is handed over.
    Lost {
        /// Id of the drone whose link is lost.
        drone: &'static str,
    },
    /// `drone` is reported lost, the survivors are replanned without it, reach the
    /// goals left to them and land (`completed`).
    Replanned {
        /// Id of the drone whose link is lost.
        drone: &'static str,
    },
    /// `drone` is reported lost and the replan falls back (says why): its
    /// dependants hold, the rest finish and land.
    FallsBack {
        /// Id of the drone whose link is lost.
        drone: &'static str,
    },
    /// `drone` leaves the plan early and lands; everybody else finishes and lands.
    Retires {
        /// Id of the drone that retires.
        drone: &'static str,
    },
}

impl Expect {
    fn describe(&self) -> String {
        match self {
            Expect::Completes => "all at goals, landed".into(),
            Expect::AbortsOnGround => "refused before takeoff, nobody airborne".into(),
            Expect::Lost { drone } => {
                format!("{drone} reported lost, dependents hold, the rest finish")
            }
            Expect::Replanned { drone } => {
                format!("{drone} reported lost, the rest replanned without it, completed")
            }
            Expect::FallsBack { drone } => {
                format!(
                    "{drone} reported lost, replan falls back: dependents hold, the rest finish"
                )
            }
            Expect::Retires { drone } => {
                format!("{drone} leaves the plan and lands, the rest replanned and finish")
            }
        }
    }
}

/// One row of the matrix.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// What the row is called in the table (and how `--only` finds it).
    pub name: &'static str,
    /// The faults as `swarmctl fly --fault` flags, e.g. `loss=10%`.
    pub faults: Vec<&'static str>,
    /// Which autopilot the SITL vehicles imitate.
    pub flavour: Flavour,
    /// The behaviour swarmctl promises under these faults.
    pub expect: Expect,
    /// How the flight replans when drones leave it (`fly --replan-deadline`).
    pub replan: ReplanOptions,
}

impl Scenario {
    fn new(name: &'static str, faults: &[&'static str], expect: Expect) -> Self {
        Self {
            name,
            faults: faults.to_vec(),
            flavour: Flavour::Px4,
            expect,
            replan: ReplanOptions::default(),
        }
    }
}

/// The scenarios, for `missions/formation-change.yaml` (drone ids b1–b4, r1–r4).
/// `reduced` keeps the ones no other end-to-end test covers, for CI.
pub fn scenarios(reduced: bool) -> Vec<Scenario> {
    let mut all = vec![
        Scenario::new("no faults", &[], Expect::Completes),
        Scenario::new("loss 10%", &["loss=10%"], Expect::Completes),
        Scenario::new("loss 30%", &["loss=30%"], Expect::Completes),
        Scenario::new(
            "latency 200 ms each way",
            &["latency=200ms"],
            Expect::Completes,
        ),
        Scenario::new(
            "duplicated 20% + reordered 20%",
            &["dup=20%", "reorder=20%"],
            Expect::Completes,
        ),
        Scenario::new(
            "b1 link cut 5 s in flight",
            &["drop=b1@5s+5s"],
            Expect::Completes,
        ),
        Scenario::new(
            "b1 lost for good",
            &["lose=b1@5s"],
            Expect::Replanned { drone: "b1" },
        ),
        Scenario::new(
            "b1 crashes (falls, silent)",
            &["crash=b1@5s"],
            Expect::Replanned { drone: "b1" },
        ),
        Scenario {
            replan: ReplanOptions {
                deadline: Duration::ZERO,
                ..ReplanOptions::default()
            },
            ..Scenario::new(
                "b1 lost, no time to replan (`--replan-deadline 0`)",
                &["lose=b1@5s"],
                Expect::FallsBack { drone: "b1" },
            )
        },
        Scenario::new(
            "r2 refuses to arm",
            &["refuse-arm=r2"],
            Expect::AbortsOnGround,
        ),
        Scenario::new("b1 at half speed", &["slow=b1:0.5"], Expect::Completes),
        Scenario::new(
            "r1 low battery",
            &["low-battery=r1@12s"],
            Expect::Retires { drone: "r1" },
        ),
        Scenario::new(
            "r1 critical battery (autopilot lands it)",
            &["critical-battery=r1@12s"],
            Expect::Retires { drone: "r1" },
        ),
        Scenario {
            flavour: Flavour::ArduPilot,
            ..Scenario::new("ArduPilot, loss 20%", &["loss=20%"], Expect::Completes)
        },
    ];
    if reduced {
        let ci = [
            "loss 30%",
            "latency 200 ms each way",
            "duplicated 20% + reordered 20%",
            "b1 lost for good",
            "b1 crashes (falls, silent)",
            "b1 lost, no time to replan (`--replan-deadline 0`)",
            "r1 low battery",
            "r1 critical battery (autopilot lands it)",
        ];
        all.retain(|s| ci.contains(&s.name));
    }
    all
}

/// What one scenario did.
#[derive(Debug, Clone)]
pub struct ScenarioReport {
    /// The scenario's name (its row in the table).
    pub name: String,
    /// The `--fault` flags flown, space-separated, or a dash for none.
    pub faults: String,
    /// The promised behaviour, in words.
    pub expected: String,
    /// What happened, in words.
    pub observed: String,
    /// Telemetry, during plan execution (∞ if nobody flew).
    pub min_separation_telemetry_m: f64,
    /// Simulator truth, whole flight, airborne pairs (∞ if nobody flew).
    pub min_separation_truth_m: f64,
    /// The mission's safety distance, metres: what both separations must keep
    /// (under an ellipsoid, its horizontal radius; the scaled separations decide).
    pub safety_distance_m: f64,
    /// Under an ellipsoidal separation, the scaled separation from telemetry and
    /// from truth (separated at 1 or more); `None` for a sphere.
    pub scaled_telemetry_truth: Option<(f64, f64)>,
    /// Wall time of the run, seconds.
    pub duration_s: f64,
    /// Whether the scenario showed its promised behaviour and kept the distance.
    pub passed: bool,
    /// Why it failed, if it did.
    pub failures: Vec<String>,
    /// The flight log, if there was a flight that ran to its end.
    pub log: Option<FlightLog>,
}

/// Flies `scenario` once with an overall `limit`.
pub async fn run_scenario(
    mission: &Mission,
    plan: &DiscretePlan,
    scenario: &Scenario,
    limit: Duration,
) -> Result<ScenarioReport, HarnessError> {
    let faults: Vec<FaultSpec> = scenario
        .faults
        .iter()
        .map(|f| fly::parse_fault(f))
        .collect::<Result<_, _>>()?;
    let configs = crate::bundled_sitl::vehicle_configs(mission, plan, scenario.flavour, &faults)?;
    let (swarm, links) = crate::bundled_sitl::start(configs, mission.link.setpoint_rate_hz).await?;
    let mut options = crate::bundled_sitl::fly_options(links);
    options.replan = scenario.replan;
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let started = std::time::Instant::now();
    let done = AtomicBool::new(false);
    let flight = async {
        let result = tokio::time::timeout(limit, fly::fly(mission, plan, &options, abort_rx)).await;
        done.store(true, Ordering::Relaxed);
        result
    };
    let ellipsoid = mission
        .limits
        .is_ellipsoid()
        .then(|| mission.limits.separation());
    let (result, (truth_m, truth_scaled, ever_airborne)) =
        tokio::join!(flight, watch_truth(&swarm, ellipsoid, &done));
    let duration_s = started.elapsed().as_secs_f64();
    let still_armed: Vec<u8> = (0..swarm.len())
        .map(|i| swarm.snapshot(i))
        .filter(|s| s.armed)
        .map(|s| s.system_id)
        .collect();
    swarm.shutdown().await;
    let flown = Flown {
        result,
        truth_m,
        truth_scaled,
        ever_airborne,
        still_armed,
        duration_s,
    };
    Ok(flown.judge(mission, scenario, limit))
}

/// A scenario's flight and what the simulator saw of it.
struct Flown {
    /// The flight's result, or `Err` if it hit the limit.
    result: Result<Result<FlightLog, FlyError>, tokio::time::error::Elapsed>,
    /// Smallest true distance between two airborne vehicles, metres.
    truth_m: f64,
    /// Under an ellipsoid, the smallest true scaled separation of two airborne
    /// vehicles.
    truth_scaled: Option<f64>,
    /// Whether any vehicle left the ground.
    ever_airborne: bool,
    /// System ids armed after the flight.
    still_armed: Vec<u8>,
    /// Wall time of the flight, seconds.
    duration_s: f64,
}

impl Flown {
    /// The report: what happened against what `scenario` promises.
    fn judge(self, mission: &Mission, scenario: &Scenario, limit: Duration) -> ScenarioReport {
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

/// Samples the simulator's true positions at 50 Hz until `done`: the smallest
/// distance between two airborne vehicles, and whether anyone left the ground.
async fn watch_truth(
    swarm: &Swarm,
    ellipsoid: Option<Separation>,
    done: &AtomicBool,
) -> (f64, Option<f64>, bool) {
    let mut min_m = f64::INFINITY;
    let mut min_scaled = ellipsoid.map(|_| f64::INFINITY);
    let mut ever_airborne = false;
    let mut airborne = Vec::with_capacity(swarm.len());
    while !done.load(Ordering::Relaxed) {
        min_m = min_m.min(crate::true_min_separation_m(swarm, &mut airborne));
        if let (Some(e), Some(min)) = (&ellipsoid, &mut min_scaled) {
            *min = min.min(crate::true_min_scaled_separation(&airborne, e));
        }
        ever_airborne |= !airborne.is_empty();
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    (min_m, min_scaled, ever_airborne)
}

fn describe_error(e: &FlyError) -> String {
    let text: Vec<String> = e
        .to_string()
        .lines()
        .map(|l| l.trim().to_string())
        .collect();
    format!("refused: {}", text.join(" "))
}

fn describe_log(log: &FlightLog) -> String {
    let s = &log.summary;
    let mut parts = vec![if s.completed {
        format!(
            "completed, plan {:.1} s (planned {:.1} s)",
            s.executed_makespan_s.unwrap_or(f64::NAN),
            s.planned_makespan_s
        )
    } else {
        "not completed".to_string()
    }];
    if !s.lost.is_empty() {
        parts.push(format!("lost {}", s.lost.join(",")));
    }
    if !s.retired.is_empty() {
        parts.push(format!("retired {}", s.retired.join(",")));
    }
    if !s.handed_over.is_empty() {
        parts.push(format!("handed over {}", s.handed_over.join(",")));
    }
    for r in &s.replans {
        parts.push(match (&r.fallback, r.new_makespan_s) {
            (None, Some(new_s)) => format!(
                "replanned without {} in {:.1} ms (flying {:.2} s after the loss; new plan {:.1} s)",
                r.left_out.join(","),
                1e3 * r.planning_s,
                r.latency_s,
                new_s
            ),
            (why, _) => format!("no replan ({})", why.as_deref().unwrap_or("no plan")),
        });
    }
    let losses: usize = log.drones.iter().map(|d| d.link_losses).sum();
    if losses > 0 {
        parts.push(format!("{losses} link losses"));
    }
    parts.push(format!("{} gating waits", s.gating_waits));
    parts.join("; ")
}

/// The matrix as a Markdown table (what the README shows).
pub fn markdown_table(reports: &[ScenarioReport]) -> String {
    let mut out = String::from(
        "| Scenario | Faults | Expected | Observed | Min sep. telemetry / truth (safety) | Result |\n|---|---|---|---|---|---|\n",
    );
    for r in reports {
        let metres = |m: f64| {
            if m.is_finite() {
                format!("{m:.2} m")
            } else {
                "—".into()
            }
        };
        let scaled = r
            .scaled_telemetry_truth
            .map_or(String::new(), |(telemetry, truth)| {
                let show = |x: f64| {
                    if x.is_finite() {
                        format!("{x:.2}")
                    } else {
                        "—".into()
                    }
                };
                format!("; scaled {} / {} (≥ 1)", show(telemetry), show(truth))
            });
        out.push_str(&format!(
            "| {} | `{}` | {} | {} | {} / {} ({:.2} m){scaled} | {} |\n",
            r.name,
            r.faults,
            r.expected,
            r.observed,
            metres(r.min_separation_telemetry_m),
            metres(r.min_separation_truth_m),
            r.safety_distance_m,
            if r.passed {
                "pass".to_string()
            } else {
                format!("FAIL: {}", r.failures.join("; "))
            }
        ));
    }
    out
}
