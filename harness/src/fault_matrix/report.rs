//! The outcome in words: one scenario's report, the descriptions of a refusal
//! or a flight log that fill its "Observed" column, and the matrix as a
//! Markdown table.

use swarmctl::fly::{FlightLog, FlyError};

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

/// A refused flight, in one line.
pub(super) fn describe_error(e: &FlyError) -> String {
    let text: Vec<String> = e
        .to_string()
        .lines()
        .map(|l| l.trim().to_string())
        .collect();
    format!("refused: {}", text.join(" "))
}

/// A flown flight: completion, losses, retirements, hand-overs, replans, link
/// losses and gating waits.
pub(super) fn describe_log(log: &FlightLog) -> String {
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
