//! The load runs side by side as a Markdown table (what the README shows).

use super::LoadReport;
use crate::median;

/// The runs side by side, one column each, as a Markdown table.
pub fn markdown_table(reports: &[LoadReport]) -> String {
    let mut rows = Rows {
        reports,
        rows: Vec::new(),
    };
    flight_rows(&mut rows);
    cpu_and_setpoint_rows(&mut rows);
    link_rows(&mut rows);
    separation_and_resource_rows(&mut rows);
    let mut out = String::from("| Metric |");
    for r in reports {
        out.push_str(&format!(" {} vehicles |", r.vehicles));
    }
    out.push_str("\n|---|");
    out.push_str(&"---|".repeat(reports.len()));
    out.push('\n');
    for (name, cells) in rows.rows {
        out.push_str(&format!("| {name} | {} |\n", cells.join(" | ")));
    }
    out
}

/// The table's rows so far: a name and one cell per report.
struct Rows<'a> {
    reports: &'a [LoadReport],
    rows: Vec<(String, Vec<String>)>,
}

impl Rows<'_> {
    /// Adds row `name` with `cell` of every report.
    fn row(&mut self, name: &str, cell: impl Fn(&LoadReport) -> String) {
        let cells = self.reports.iter().map(cell).collect();
        self.rows.push((name.to_string(), cells));
    }
}

/// Seconds as milliseconds, one decimal.
fn ms(s: f64) -> String {
    format!("{:.1}", s * 1e3)
}

/// Metres, two decimals, or a dash for ∞ (nobody to be close to).
fn metres(m: f64) -> String {
    if m.is_finite() {
        format!("{m:.2}")
    } else {
        "—".into()
    }
}

/// CPU seconds of `r`'s flight as percent of one core.
fn pct(r: &LoadReport, cpu_s: f64) -> String {
    format!("{:.1}", r.cpu.percent(cpu_s))
}

/// Bytes in MiB.
fn mib(bytes: u64) -> f64 {
    bytes as f64 / 1048576.0
}

/// The mission, planning, and how the flight ended.
fn flight_rows(rows: &mut Rows) {
    rows.row("Mission", |r| format!("`{}`", r.mission));
    rows.row("Planning time, median of runs (s)", |r| {
        format!(
            "{:.3} ({} runs)",
            median(&r.plan_times_s),
            r.plan_times_s.len()
        )
    });
    rows.row("Makespan (steps / planned s / flown s)", |r| {
        let s = r.log.as_ref().map(|l| &l.summary);
        format!(
            "{} / {} / {}",
            r.makespan_steps,
            s.map_or("—".into(), |s| format!("{:.1}", s.planned_makespan_s)),
            s.and_then(|s| s.executed_makespan_s)
                .map_or("—".into(), |t| format!("{t:.1}"))
        )
    });
    rows.row("Flight (wall s)", |r| format!("{:.1}", r.flight_wall_s));
    rows.row("Completed", |r| {
        if r.completed() { "yes" } else { "NO" }.to_string()
    });
    rows.row("Landed at goal (truth)", |r| {
        format!(
            "{}/{} (worst {:.2} m)",
            r.at_goal, r.vehicles, r.max_goal_error_m
        )
    });
    rows.row("Still armed", |r| r.still_armed.len().to_string());
}

/// CPU by thread kind, and setpoint timing where the vehicles received them.
fn cpu_and_setpoint_rows(rows: &mut Rows) {
    rows.row("CPU total (% of one core; busiest 5 s)", |r| {
        format!(
            "{} ({:.1})",
            pct(r, r.cpu.total_s),
            100.0 * r.cpu.peak_total_share
        )
    });
    rows.row("CPU controller (%; busiest 5 s)", |r| {
        format!(
            "{} ({:.1})",
            pct(r, r.cpu.controller_s()),
            100.0 * r.cpu.peak_controller_share
        )
    });
    rows.row("CPU SITL (%)", |r| pct(r, r.cpu.sitl_s));
    rows.row("CPU truth watcher (%)", |r| pct(r, r.cpu.watch_s));
    rows.row("Setpoint interval p50 / p99 / max (ms)", |r| {
        format!(
            "{} / {} / {}",
            ms(r.setpoints.quantile_s(0.5)),
            ms(r.setpoints.quantile_s(0.99)),
            ms(r.setpoints.max_s())
        )
    });
    rows.row("Worst vehicle's p99 (ms)", |r| ms(r.worst_vehicle_p99_s));
    rows.row("Setpoint intervals (> 100 ms / > 500 ms)", |r| {
        format!(
            "{} ({} / {})",
            r.setpoints.count(),
            r.setpoints.count_above(0.1),
            r.setpoints.count_above(0.5)
        )
    });
}

/// The link from both ends, and the SITL's physics ticker.
fn link_rows(rows: &mut Rows) {
    rows.row("Vehicle link rx / tx datagrams", |r| {
        format!("{} / {}", r.link.rx_datagrams, r.link.tx_datagrams)
    });
    rows.row("Vehicle tx errors / undecodable rx", |r| {
        format!("{} / {}", r.link.tx_errors, r.link.rx_undecodable)
    });
    rows.row("Controller link losses", |r| {
        r.controller_link_losses.to_string()
    });
    rows.row("SITL physics missed / skipped steps", |r| {
        format!(
            "{} / {} of {}",
            r.ticks.missed_ticks, r.ticks.skipped_steps, r.ticks.steps
        )
    });
}

/// Separation against the safety distance, memory, open files, and the verdict.
fn separation_and_resource_rows(rows: &mut Rows) {
    rows.row("Min separation telemetry / truth, pad to pad (m)", |r| {
        format!(
            "{} / {}",
            metres(r.min_separation_telemetry_m),
            metres(r.min_separation_truth_m)
        )
    });
    rows.row("Safety distance (m)", |r| match r.scaled_telemetry_truth {
        Some((telemetry, truth)) => format!(
            "{:.2} across; scaled separation telemetry / truth {} / {} (≥ 1)",
            r.safety_distance_m,
            scaled(telemetry),
            scaled(truth)
        ),
        None => format!("{:.2}", r.safety_distance_m),
    });
    rows.row("Peak RSS, process / in flight (MiB)", |r| {
        format!(
            "{:.1} / {:.1}",
            mib(r.peak_rss_bytes),
            mib(r.flight_max_rss_bytes)
        )
    });
    rows.row("Open fds before / max in flight / after", |r| {
        format!("{} / {} / {}", r.fds_before, r.fds_max, r.fds_after)
    });
    rows.row("Result", |r| {
        if r.passed() {
            "pass".to_string()
        } else {
            format!("FAIL: {}", r.failures.join("; "))
        }
    });
}

/// A scaled separation, or a dash when none was measured.
fn scaled(value: f64) -> String {
    if value.is_finite() {
        format!("{value:.2}")
    } else {
        "—".to_string()
    }
}
