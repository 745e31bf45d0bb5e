//! The relay load benchmark's report: one row per metric, the run through
//! relays beside the one-process baseline.

use super::{RelayIntervals, RelayRun};
use crate::load::LoadReport;
use crate::median;
use swarmctl::mission::Mission;

/// Rows of the table: a metric, its value through relays, and the baseline's.
#[derive(Default)]
struct Table {
    rows: Vec<(String, String, String)>,
}

impl Table {
    fn row(&mut self, name: &str, relayed: String, baseline: Option<String>) {
        self.rows.push((
            name.to_string(),
            relayed,
            baseline.unwrap_or_else(|| "—".into()),
        ));
    }
}

/// The Markdown table: the run through relays, and the baseline (the load
/// benchmark's one-process run of the same mission) beside it when flown.
pub fn markdown_table(run: &RelayRun, mission: &Mission, base: Option<&LoadReport>) -> String {
    let mut t = Table::default();
    flight_rows(&mut t, run, mission, base);
    resource_rows(&mut t, run, base);
    let mut out = String::from(
        "| Metric | through relays (Zenoh) | one process (baseline) |\n|---|---|---|\n",
    );
    for (name, relayed, baseline) in t.rows {
        out.push_str(&format!("| {name} | {relayed} | {baseline} |\n"));
    }
    out
}

/// Completion, timing, setpoint intervals, separation and speed.
fn flight_rows(t: &mut Table, run: &RelayRun, mission: &Mission, base: Option<&LoadReport>) {
    let mut row =
        |name: &str, relayed: String, baseline: Option<String>| t.row(name, relayed, baseline);
    let summary = run.log.as_ref().map(|l| &l.summary);
    row(
        "planning (median)",
        format!("{:.2} s", median(&run.plan_times_s)),
        base.map(|b| format!("{:.2} s", median(&b.plan_times_s))),
    );
    row(
        "completed",
        summary.map_or("no (time limit)".into(), |s| yes(s.completed)),
        base.map(|b| yes(b.completed())),
    );
    row(
        "plan execution vs planned",
        summary.map_or("—".into(), |s| {
            format!(
                "{:.1} s vs {:.1} s",
                s.executed_makespan_s.unwrap_or(f64::NAN),
                s.planned_makespan_s
            )
        }),
        base.and_then(|b| b.log.as_ref()).map(|l| {
            format!(
                "{:.1} s vs {:.1} s",
                l.summary.executed_makespan_s.unwrap_or(f64::NAN),
                l.summary.planned_makespan_s
            )
        }),
    );
    let intervals: Vec<&RelayIntervals> = run
        .relays
        .iter()
        .filter_map(|r| r.setpoint_interval_ms.as_ref())
        .collect();
    let worst = |f: fn(&RelayIntervals) -> f64| intervals.iter().map(|i| f(i)).fold(0.0, f64::max);
    row(
        "setpoint interval at the vehicles p50 / p99 / max (worst relay)",
        format!(
            "{:.1} / {:.1} / {:.1} ms ({} setpoints)",
            worst(|i| i.p50_ms),
            worst(|i| i.p99_ms),
            worst(|i| i.max_ms),
            intervals.iter().map(|i| i.count).sum::<u64>()
        ),
        base.map(|b| {
            format!(
                "{:.1} / {:.1} / {:.1} ms ({} setpoints)",
                b.setpoints.quantile_s(0.5) * 1e3,
                b.setpoints.quantile_s(0.99) * 1e3,
                b.setpoints.max_s() * 1e3,
                b.setpoints.count()
            )
        }),
    );
    row(
        "min separation telemetry / truth",
        format!(
            "{} / {:.3} m (limit {:.2} m)",
            summary.map_or("—".into(), |s| format!("{:.3}", s.min_separation_m)),
            run.truth.min_separation_m,
            mission.limits.safety_distance_m
        ),
        base.map(|b| {
            format!(
                "{:.3} / {:.3} m",
                b.min_separation_telemetry_m, b.min_separation_truth_m
            )
        }),
    );
    if let Some(scaled) = run.truth.min_scaled_separation {
        row(
            "min scaled separation telemetry / truth (separated at 1)",
            format!(
                "{} / {scaled:.3}",
                summary
                    .and_then(|s| s.min_scaled_separation)
                    .map_or("—".into(), |v| format!("{v:.3}"))
            ),
            base.and_then(|b| b.scaled_telemetry_truth)
                .map(|(t, u)| format!("{t:.3} / {u:.3}")),
        );
    }
    row(
        "top speed telemetry / truth",
        format!(
            "{} / {:.2} m/s (limit {:.2} + 5 %)",
            summary.map_or("—".into(), |s| format!("{:.2}", s.max_speed_mps)),
            run.truth.top_speed_mps,
            mission.limits.max_speed_mps
        ),
        None,
    );
}

/// Processes, their CPU time and peak memory.
fn resource_rows(t: &mut Table, run: &RelayRun, base: Option<&LoadReport>) {
    let mut row =
        |name: &str, relayed: String, baseline: Option<String>| t.row(name, relayed, baseline);
    row(
        "drones / processes",
        format!(
            "{} / 1 controller + {} relays",
            run.drones,
            run.relays.len()
        ),
        base.map(|b| format!("{} / 1", b.vehicles)),
    );
    row(
        "CPU, controller (% of one core over the flight)",
        format!(
            "{:.0} % ({:.1} s in {:.0} s)",
            100.0 * run.controller_cpu_s / run.wall_s.max(1e-9),
            run.controller_cpu_s,
            run.wall_s
        ),
        base.map(|b| {
            format!(
                "{:.0} % (controller threads)",
                b.cpu.percent(b.cpu.controller_s())
            )
        }),
    );
    for r in &run.relays {
        row(
            &format!(
                "CPU, relay {} ({} vehicles; process lifetime)",
                r.relay, r.drones
            ),
            r.cpu_s.map_or("—".into(), |c| format!("{c:.1} s")),
            None,
        );
    }
    row(
        "peak memory, controller / relays",
        format!(
            "{} / {}",
            mib(run.controller_peak_rss_bytes),
            run.relays
                .iter()
                .map(|r| mib(r.peak_rss_bytes.unwrap_or(0)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        base.map(|b| mib(b.peak_rss_bytes)),
    );
}

fn yes(b: bool) -> String {
    if b { "yes".into() } else { "no".into() }
}

fn mib(bytes: u64) -> String {
    format!("{:.0} MiB", bytes as f64 / (1024.0 * 1024.0))
}
