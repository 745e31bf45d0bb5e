//! Lateness: when each drone's telemetry reached each of its events against when
//! the schedule said it would, and the swarm's figures an operator reads (median,
//! 95th percentile, worst, and who was latest where).
//!
//! Times are on the plan clock of the plan being flown: after a replan, the
//! events of the new plan are measured against the new plan's schedule.

use crate::schedule::EventKind;
use crate::world::Voxel;
use serde::{Deserialize, Serialize};

/// One event of one drone: scheduled, and reached as telemetry showed it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EventLateness {
    /// The event's index along the drone's route.
    pub event: usize,
    /// Start, marker or arrival.
    pub kind: EventKind,
    /// The voxel the event is about.
    pub voxel: Voxel,
    /// When the schedule reaches it, plan-clock seconds.
    pub scheduled_s: f64,
    /// When telemetry showed the drone there, plan-clock seconds.
    pub reached_s: f64,
    /// The same moment in seconds since the first arm command (the flight's
    /// timeline, on which a replan does not restart the clock).
    #[serde(default)]
    pub flight_s: f64,
}

impl EventLateness {
    /// Seconds behind the schedule (negative: early, within the reach tolerance).
    pub fn lateness_s(&self) -> f64 {
        self.reached_s - self.scheduled_s
    }

    /// What happens at the event, in words: `entering [3, 4, 1]`.
    pub fn what(&self) -> String {
        let verb = match self.kind {
            EventKind::Start => "starting at",
            EventKind::Enter => "entering",
            EventKind::Leave => "leaving",
            EventKind::Arrive => "arriving at",
        };
        format!("{verb} {}", self.voxel)
    }
}

/// The swarm's lateness over every event reached in the flight.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LatenessSummary {
    /// Events measured.
    pub events: usize,
    /// Median lateness, seconds.
    pub p50_s: f64,
    /// 95th-percentile lateness, seconds.
    pub p95_s: f64,
    /// Largest lateness, seconds.
    pub max_s: f64,
    /// The drone behind `max_s`.
    pub latest_drone: String,
    /// Its event behind `max_s`.
    pub latest: EventLateness,
}

impl LatenessSummary {
    /// Summarises `drones`' records (`(drone id, its records)`); `None` when no
    /// event was reached.
    pub fn of<'a>(
        drones: impl IntoIterator<Item = (&'a str, &'a [EventLateness])>,
    ) -> Option<Self> {
        let mut all: Vec<(f64, &str, EventLateness)> = drones
            .into_iter()
            .flat_map(|(id, records)| records.iter().map(move |r| (r.lateness_s(), id, *r)))
            .collect();
        all.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (max_s, latest_drone, latest) = *all.last()?;
        let at = |q: f64| all[((all.len() - 1) as f64 * q).round() as usize].0;
        Some(Self {
            events: all.len(),
            p50_s: at(0.5),
            p95_s: at(0.95),
            max_s,
            latest_drone: latest_drone.to_string(),
            latest,
        })
    }

    /// Its line in the summary `swarmctl fly` prints.
    pub fn line(&self) -> String {
        format!(
            "  lateness             p50 {:.2} s, p95 {:.2} s, max {:.2} s over {} events (latest: {} {}, scheduled at {:.1} s)",
            self.p50_s,
            self.p95_s,
            self.max_s,
            self.events,
            self.latest_drone,
            self.latest.what(),
            self.latest.scheduled_s,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(event: usize, scheduled_s: f64, reached_s: f64) -> EventLateness {
        EventLateness {
            event,
            kind: EventKind::Arrive,
            voxel: Voxel::new(1, 2, 3),
            scheduled_s,
            reached_s,
            flight_s: reached_s,
        }
    }

    #[test]
    fn the_summary_names_the_latest_drone_and_event() {
        let a = [at(0, 0.0, 0.0), at(1, 2.0, 2.1), at(2, 4.0, 4.2)];
        let b = [at(0, 0.0, 0.05), at(1, 3.0, 4.5)];
        let s = LatenessSummary::of([("a", &a[..]), ("b", &b[..])]).expect("events");
        assert_eq!(s.events, 5);
        assert!((s.max_s - 1.5).abs() < 1e-12);
        assert_eq!((s.latest_drone.as_str(), s.latest.event), ("b", 1));
        assert!((s.p50_s - 0.1).abs() < 1e-12, "{}", s.p50_s);
        assert!(LatenessSummary::of([("a", &[][..])]).is_none());
        assert!(
            s.line().contains(
                "max 1.50 s over 5 events (latest: b arriving at [1, 2, 3], scheduled at 3.0 s)"
            ),
            "{}",
            s.line()
        );
    }
}
