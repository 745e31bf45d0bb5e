//! The live status view: phase counts, progress, the slowest drone and how far
//! behind schedule it is, and the minimum separation so far. A spinner line on a
//! terminal, a plain line every few seconds otherwise (logs, CI), or nothing.
//!
//! A line reads
//! `t= 24.0s  6 flying, 2 at goal  progress  63%  slowest b3 1.2s behind (waiting for r1)  2 gated  min sep so far 0.87m`:
//! seconds since the first arm command; how many drones are in each phase
//! (`LINK LOST` while a drone is silent past `link.link_timeout_s`, `LOST` once
//! given up after `link.lost_after_s`); the share of the plan's events reached
//! (landed drones count as done); the flying drone furthest behind its schedule
//! and whom it waits for; how many drones wait at a gate now; and the smallest
//! distance between two drones measured since takeoff (not the distance now).

//!
//! It is a [`FlightObserver`]: the flight executor hands it the swarm's status
//! once per control tick, and it draws from that alone.

use indicatif::{ProgressBar, ProgressStyle};
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};
use swarmctl::fly::LogEvent;
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

/// Writes one status line to stderr, ignoring a closed stderr (a pipe whose
/// reader left): `eprintln!` would panic inside the executor's tick, mid-flight.
fn show(line: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "{line}");
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
        // A landed drone is done, whatever events a replan or an abort left it.
        let progress = drones
            .iter()
            .map(|d| if d.phase == "landed" { 1.0 } else { d.progress })
            .sum::<f64>()
            / drones.len().max(1) as f64;
        let mut line = format!(
            "t={since_arm_s:5.1}s  {}  progress {:3.0}%",
            phases.join(", "),
            100.0 * progress
        );
        if let Some(t) = t_exec_s {
            // Only drones still flying their plan can be behind it: a lost or
            // landed drone's next event never comes, and would grow forever.
            let slowest = drones
                .iter()
                .filter(|d| d.phase == "flying")
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
            line += &format!("  min sep so far {min_separation_m:.2}m");
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
            show(&line);
            self.last_line = Some((line, true));
            return;
        }
        self.last_line = Some((line, false));
    }

    /// Ends the view on the final state.
    fn finish(&mut self) {
        let last = self.last_line.take();
        if let Some(bar) = self.bar.take() {
            // Clear the spinner and print its last line as an ordinary, ended
            // line: the summary that follows (on stdout) starts on a line of its own.
            bar.finish_and_clear();
            if let Some((line, _)) = last {
                show(&line);
            }
        } else if self.plain
            && let Some((line, false)) = last
        {
            show(&line);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarmctl::fly::DroneStatus;

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
            line.ends_with("min sep so far 0.73m (scaled 1.30, separated at 1)"),
            "{line}"
        );
        assert!(Monitor::line(&status(None)).ends_with("min sep so far 0.73m"));
    }

    fn drone(
        id: &str,
        phase: &'static str,
        progress: f64,
        next_reach_s: Option<f64>,
    ) -> DroneStatus {
        DroneStatus {
            id: id.into(),
            phase,
            progress,
            next_reach_s,
            waiting_for: None,
        }
    }

    #[test]
    fn lost_and_landed_drones_are_never_behind_and_landed_is_done() {
        let mut s = status(None);
        s.t_exec_s = Some(60.0);
        s.drones = vec![
            drone("b1", "LOST", 0.4, Some(10.0)),
            drone("b2", "landed", 0.9, Some(58.0)),
            drone("b3", "flying", 0.5, Some(57.5)),
        ];
        let line = Monitor::line(&s);
        assert!(line.contains("1 LOST, 1 flying, 1 landed"), "{line}");
        assert!(line.contains("slowest b3 2.5s behind"), "{line}");
        assert!(line.contains("progress  63%"), "{line}");
        s.drones = vec![drone("b2", "landed", 0.9, Some(58.0))];
        let line = Monitor::line(&s);
        assert!(
            line.contains("progress 100%") && !line.contains("behind"),
            "{line}"
        );
    }
}
