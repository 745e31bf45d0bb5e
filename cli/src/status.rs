//! The live status view: phase counts, progress, the slowest drone and how far
//! behind schedule it is, and the minimum separation so far. A spinner line on a
//! terminal, a plain line every few seconds otherwise (logs, CI), or nothing.

//!
//! It is a [`FlightObserver`]: the flight executor hands it the swarm's status
//! once per control tick, and it draws from that alone.

use indicatif::{ProgressBar, ProgressStyle};
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};
use swarmctl::fly::log::LogEvent;
use swarmctl::fly::{FlightObserver, FlightStatus};

/// How to show status.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StatusMode {
    /// Spinner on a terminal, plain lines otherwise.
    Auto,
    /// A plain line every few seconds.
    Plain,
    /// Nothing.
    Quiet,
}

/// The status view of one flight. Give it to the flight as an observer, then call
/// [`StatusView::finish`] once the flight has returned.
pub struct StatusView {
    inner: Mutex<Monitor>,
}

impl StatusView {
    /// A view in `mode` (a spinner only when stderr is a terminal).
    pub fn new(mode: StatusMode) -> Self {
        Self {
            inner: Mutex::new(Monitor::new(mode)),
        }
    }

    /// Ends the view on the flight's final state.
    pub fn finish(&self) {
        if let Ok(mut monitor) = self.inner.lock() {
            monitor.finish();
        }
    }
}

impl FlightObserver for StatusView {
    fn sample(&self, _drone: usize, _t_s: f64, _position_m: [f64; 3]) {}

    fn event(&self, _event: &LogEvent) {}

    fn status(&self, status: &FlightStatus) {
        // Never wait on the executor's tick: a view busy drawing skips one update.
        if let Ok(mut monitor) = self.inner.try_lock() {
            monitor.update(status);
        }
    }

    fn wants_status(&self) -> bool {
        true
    }
}

struct Monitor {
    bar: Option<ProgressBar>,
    plain: bool,
    last_print: Option<Instant>,
    plain_period: Duration,
    /// The newest line, and whether it has been shown; `finish` shows it, so the
    /// view ends on the final state ("N landed") rather than a stale one.
    last_line: Option<(String, bool)>,
}

impl Monitor {
    fn new(mode: StatusMode) -> Self {
        let tty = std::io::stderr().is_terminal();
        let bar = (mode == StatusMode::Auto && tty).then(|| {
            let bar = ProgressBar::new_spinner();
            if let Ok(style) = ProgressStyle::with_template("{spinner} {msg}") {
                bar.set_style(style);
            }
            bar.enable_steady_tick(Duration::from_millis(200));
            bar
        });
        Monitor {
            plain: bar.is_none() && mode != StatusMode::Quiet,
            bar,
            last_print: None,
            plain_period: Duration::from_secs(3),
            last_line: None,
        }
    }

    /// One status line from the current state of every drone.
    fn line(status: &FlightStatus) -> String {
        let (since_arm_s, t_exec_s) = (status.since_arm_s, status.t_exec_s);
        let (min_separation_m, drones) = (status.min_separation_m, &status.drones);
        let mut phases: BTreeMap<&str, usize> = BTreeMap::new();
        for d in drones {
            *phases.entry(d.phase).or_default() += 1;
        }
        let phases: Vec<String> = phases.iter().map(|(p, n)| format!("{n} {p}")).collect();
        let progress = drones.iter().map(|d| d.progress).sum::<f64>() / drones.len().max(1) as f64;
        let mut line = format!(
            "t={since_arm_s:5.1}s  {}  progress {:3.0}%",
            phases.join(", "),
            100.0 * progress
        );
        if let Some(t) = t_exec_s {
            let slowest = drones
                .iter()
                .filter_map(|d| d.next_reach_s.map(|r| (d, t - r)))
                .max_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((d, behind_s)) = slowest.filter(|(_, b)| *b > 0.0) {
                line += &format!("  slowest {} {behind_s:.1}s behind", d.id);
                if let Some(w) = d.waiting_for.and_then(|w| drones.get(w as usize)) {
                    line += &format!(" (waiting for {})", w.id);
                }
            }
            let waiting = drones.iter().filter(|d| d.waiting_for.is_some()).count();
            if waiting > 0 {
                line += &format!("  {waiting} gated");
            }
        }
        if min_separation_m.is_finite() {
            line += &format!("  min sep {min_separation_m:.2}m");
        }
        if let Some(scaled) = status.min_scaled_separation.filter(|s| s.is_finite()) {
            line += &format!(" (scaled {scaled:.2}, separated at 1)");
        }
        line
    }

    fn update(&mut self, status: &FlightStatus) {
        let line = Self::line(status);
        if let Some(bar) = &self.bar {
            bar.set_message(line.clone());
        } else if self.plain
            && self
                .last_print
                .is_none_or(|t| t.elapsed() >= self.plain_period)
        {
            self.last_print = Some(Instant::now());
            eprintln!("{line}");
            self.last_line = Some((line, true));
            return;
        }
        self.last_line = Some((line, false));
    }

    /// Ends the view on the final state.
    fn finish(&mut self) {
        let last = self.last_line.take();
        if let Some(bar) = self.bar.take() {
            bar.finish_with_message(last.map(|(line, _)| line).unwrap_or_default());
        } else if self.plain
            && let Some((line, false)) = last
        {
            eprintln!("{line}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(min_scaled_separation: Option<f64>) -> FlightStatus {
        FlightStatus {
            since_arm_s: 12.0,
            t_exec_s: None,
            min_separation_m: 0.73,
            min_scaled_separation,
            drones: Vec::new(),
        }
    }

    #[test]
    fn an_ellipsoid_flight_shows_its_scaled_separation() {
        let line = Monitor::line(&status(Some(1.304)));
        assert!(
            line.ends_with("min sep 0.73m (scaled 1.30, separated at 1)"),
            "{line}"
        );
        assert!(Monitor::line(&status(None)).ends_with("min sep 0.73m"));
    }
}
