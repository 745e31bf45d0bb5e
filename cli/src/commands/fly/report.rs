//! Reporting a flight: where its log goes, writing it, and the summary printed
//! after it.

use anyhow::Context;
use std::path::{Path, PathBuf};
use swarmctl::fly;
use swarmctl::mission::Mission;

/// `flights/<mission file name>-<unix time>.json`: named after the file the user
/// typed (`missions/formation-change.yaml` → `flights/formation-change-….json`),
/// with anything but letters, digits, `-` and `_` replaced.
pub(super) fn default_log_path(mission_file: &Path) -> PathBuf {
    let unix_s = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let stem = mission_file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mission".into());
    let name: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    PathBuf::from("flights").join(format!("{name}-{unix_s}.json"))
}

/// Writes the flight log to `path`, creating its directory.
pub(super) fn write_log(path: &Path, log: &fly::FlightLog) -> anyhow::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    std::fs::write(path, serde_json::to_string(log)?)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// Prints how the flight went: the summary, every event, and where the log is.
pub(super) fn print_report(mission: &Mission, log: &fly::FlightLog, path: &Path) {
    println!("{}: flew {} drones", mission.name, log.drones.len());
    for line in log.summary.lines() {
        println!("{line}");
    }
    if let Some(line) = traffic_line(log) {
        println!("{line}");
    }
    if let Some(at_s) = log.start_at_unix_s {
        let asked = std::time::UNIX_EPOCH + std::time::Duration::from_secs_f64(at_s.max(0.0));
        let started = match fly::plan_start_delay_s(log) {
            Some(delay_s) => format!("plan time 0 came {delay_s:.3} s after it"),
            None => "the plan never started".to_string(),
        };
        println!(
            "  start instant        {}: {started}",
            humantime::format_rfc3339_millis(asked)
        );
    }
    for e in &log.events {
        println!(
            "  event {:6.1} s {}{}",
            e.t_s,
            e.drone
                .as_deref()
                .map(|d| format!("{d}: "))
                .unwrap_or_default(),
            e.message
        );
    }
    println!("  log                  {}", path.display());
}

/// The busiest drone's measured link each way against the budget, if measured.
fn traffic_line(log: &fly::FlightLog) -> Option<String> {
    let traffic: Vec<(&str, &fly::LinkTraffic)> = log
        .drones
        .iter()
        .filter_map(|d| d.link_traffic.as_ref().map(|t| (d.id.as_str(), t)))
        .collect();
    let busiest = |kbps: fn(&fly::LinkTraffic) -> f64| {
        traffic
            .iter()
            .max_by(|a, b| kbps(a.1).total_cmp(&kbps(b.1)))
            .map(|(id, t)| (*id, kbps(t)))
    };
    let (up_id, up_kbps) = busiest(|t| t.up_kbps)?;
    let (down_id, down_kbps) = busiest(|t| t.down_kbps)?;
    let budget = traffic.first()?.1;
    Some(format!(
        "  link (measured)      up {up_kbps:.1} kbit/s ({up_id}; budget {:.1}), down {down_kbps:.1} kbit/s ({down_id}; budget {:.1}) per drone",
        budget.budget_up_kbps, budget.budget_down_kbps
    ))
}
