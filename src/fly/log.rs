//! The flight log: every drone's telemetry and a summary of how the flight went.

pub use super::last_known::LastKnown;
use super::lateness::{EventLateness, LatenessSummary};
use crate::compiled::CheckFigures;
use serde::{Deserialize, Serialize};

/// Telemetry speed may exceed the mission's limit by this fraction before the
/// summary calls the limit broken: vehicles track setpoints with some overshoot,
/// and telemetry velocity is a noisy estimate.
pub const SPEED_TOLERANCE: f64 = 0.05;

/// The event that starts the plan clock: every drone hovers above its pad.
pub const PLAN_STARTED: &str = "all drones above their pads: executing the plan";

/// Written as JSON by `swarmctl fly --log`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FlightLog {
    /// The mission's name.
    pub mission: String,
    /// How the flight went, in numbers.
    pub summary: Summary,
    /// Every drone's record, in plan order.
    pub drones: Vec<DroneLog>,
    /// Notable moments in order: link losses, aborts, refusals.
    pub events: Vec<LogEvent>,
    /// When the first arm command went out, seconds since the Unix epoch (UTC):
    /// event and sample times are seconds after it. `None` in older logs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub armed_at_unix_s: Option<f64>,
    /// The start instant asked for (`fly --start-at`), seconds since the Unix
    /// epoch: plan time 0 ([`PLAN_STARTED`] in `events`) is measured against it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_at_unix_s: Option<f64>,
}

/// How the flight went: completion, timing, separation and speed against the
/// mission's limits, and which drones left the plan.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Summary {
    /// Every drone flew its plan to its pad and landed, the measured separation
    /// never fell below the safety distance, and no drone broke the speed limit.
    /// After a replan "every drone" is every drone still in the plan: the
    /// survivors reached the goals left to them and landed (see `replans`; a lost
    /// drone is still listed in `lost`).
    pub completed: bool,
    /// The measured separation never fell below the safety distance.
    #[serde(default)]
    pub safety_held: bool,
    /// From the first arm command to the last drone landed (or the abort), seconds.
    pub duration_s: f64,
    /// The schedule's makespan: how long plan execution should take.
    pub planned_makespan_s: f64,
    /// What the independent trajectory checker measured before anything was
    /// started, on the very trajectories flown (`compiled::compile_plan`);
    /// `None` in logs written before `fly` ran it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub check: Option<CheckFigures>,
    /// How long plan execution took (all drones above their pads to all above the
    /// pads they land on).
    pub executed_makespan_s: Option<f64>,
    /// Smallest distance between two drones over the whole flight, pad to pad, from
    /// telemetry. Omitted from the JSON (∞ in Rust) when no two drones were ever
    /// heard from: JSON has no infinity, and `null` would not read back as a number.
    #[serde(default = "infinity", skip_serializing_if = "not_finite")]
    pub min_separation_m: f64,
    /// The two drones that came closest, and when (seconds since the first arm).
    pub closest_pair: Option<(String, String, f64)>,
    /// The mission's safety distance, to read `min_separation_m` against, metres
    /// (an ellipsoid's horizontal radius).
    pub safety_distance_m: f64,
    /// An ellipsoid's vertical radius, metres; `None` for a sphere.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical_separation_m: Option<f64>,
    /// Under an ellipsoid, the smallest scaled separation from telemetry over the
    /// whole flight, pad to pad: `√((dx/H)² + (dy/H)² + (dz/V)²)`, separated when at
    /// least 1; `safety_held` reads it. `None` for a sphere; omitted from the JSON
    /// when nothing was measured.
    #[serde(default, skip_serializing_if = "not_finite_option")]
    pub min_scaled_separation: Option<f64>,
    /// The two drones behind `min_scaled_separation`, and when.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub closest_scaled_pair: Option<(String, String, f64)>,
    /// Highest speed reported by any drone's telemetry, over the whole flight.
    pub max_speed_mps: f64,
    /// The drone that flew fastest, and when (seconds since the first arm).
    #[serde(default)]
    pub fastest: Option<(String, f64)>,
    /// `max_speed_mps` stayed within the limit plus [`SPEED_TOLERANCE`].
    #[serde(default)]
    pub speed_held: bool,
    /// The mission's speed limit, to read `max_speed_mps` against.
    pub speed_limit_mps: f64,
    /// Times a drone stopped (or could not start) because a TPG predecessor was late.
    pub gating_waits: usize,
    /// Total time drones spent waiting at a closed gate, summed over drones,
    /// seconds (several waiting at once count several times: the summary prints
    /// `longest_gating_wait` instead).
    pub gating_wait_s: f64,
    /// The longest single wait at a closed gate: which drone, how long (seconds).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub longest_gating_wait: Option<(String, f64)>,
    /// How late the drones reached their events against the schedule (`None`
    /// when no event was reached).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lateness: Option<LatenessSummary>,
    /// The drone with the largest 95th-percentile tracking error, and that error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst_tracking: Option<(String, TrackingError)>,
    /// The tracking error the mission trusts the vehicles to keep, metres.
    #[serde(default)]
    pub tracking_bound_m: f64,
    /// No drone's measured tracking error exceeded the bound.
    #[serde(default)]
    pub tracking_held: bool,
    /// Times a setpoint waited for its vehicle to come back within the bound.
    #[serde(default)]
    pub tracking_holds: usize,
    /// Total time setpoints waited so, seconds.
    #[serde(default)]
    pub tracking_hold_s: f64,
    /// Largest final distance from a drone to the pad-layer cell it lands from
    /// (before touchdown), metres; lost and handed-over drones are left out (they
    /// did not land under swarmctl: the summary lists them).
    pub max_final_distance_to_goal_m: f64,
    /// Drones given up for lost (nothing heard for the mission's `link.lost_after_s`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lost: Vec<String>,
    /// Where each lost drone was last heard from, and in what state: an operator
    /// goes looking for it there.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lost_last_known: Vec<LastKnown>,
    /// Drones that left the plan early and landed (low battery, autopilot failsafe).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub retired: Vec<String>,
    /// Drones that could not land safely and were left in the autopilot's hold.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub handed_over: Vec<String>,
    /// Every replan tried in flight (see `fly::replan`), in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub replans: Vec<ReplanRecord>,
    /// Every drone the flight cannot say is on the ground (lost, handed over, given
    /// up in the air), in plan order: an operator must go and find each. A flight
    /// with any is no success, however well the survivors did ([`Summary::succeeded`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub unaccounted: Vec<Unaccounted>,
}

/// A drone not known to be on the ground when the flight ended.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Unaccounted {
    /// The drone's mission id.
    pub id: String,
    /// The phase it was left in, as the status view names it (`LOST`, `HANDED OVER`).
    pub phase: String,
    /// Why it was given up, when the flight knows (a refused command).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

impl ReplanRecord {
    /// Its line in the summary `swarmctl fly` prints.
    pub fn line(&self) -> String {
        let r = self;
        match (&r.fallback, r.new_makespan_s) {
            (None, Some(new_s)) => format!(
                "  replanned            at {:.1} s without {}: new plan {:.1} s (old {:.1} s), planned in {:.1} ms, flying {:.2} s after the loss was noticed{}",
                r.at_s,
                r.left_out.join(", "),
                new_s,
                r.old_makespan_s,
                1e3 * r.planning_s,
                r.latency_s,
                r.check.as_ref().map_or(String::new(), |c| format!(
                    "; checked: min separation ≥ {:.3} m (need {:.3} m), max speed {:.2} m/s",
                    c.min_separation_bound_m, c.required_separation_m, c.max_speed_mps
                ))
            ),
            (why, _) => format!(
                "  NOT replanned        at {:.1} s without {}: {}",
                r.at_s,
                r.why,
                why.as_deref().unwrap_or("no plan")
            ),
        }
    }
}

/// One replan in flight: when and why, how long it took, and what came of it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReplanRecord {
    /// When the loss or retirement was noticed, seconds since the first arm command.
    pub at_s: f64,
    /// Who left the plan and why ("b1 (lost)").
    pub why: String,
    /// Drones the new plan flies without (empty when none was spliced).
    pub left_out: Vec<String>,
    /// Planning, the independent check and scheduling, seconds.
    pub planning_s: f64,
    /// From the loss being noticed to the new plan executing (the freeze and the
    /// planning), or to the fallback, seconds.
    pub latency_s: f64,
    /// The makespan of the plan being flown before, seconds.
    pub old_makespan_s: f64,
    /// The new plan's makespan from the splice, seconds; `None` without one.
    pub new_makespan_s: Option<f64>,
    /// Why the flight fell back to holding the dependants; `None` when spliced.
    pub fallback: Option<String>,
    /// What the trajectory checker measured on the spliced trajectories (the
    /// re-centring runs, the new plan, each touchdown); `None` when the replan
    /// never got that far.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub check: Option<CheckFigures>,
}

/// One drone's record: which vehicle flew it, how close it got, how long it
/// waited, and its whole telemetry track.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DroneLog {
    /// The drone's mission id.
    pub id: String,
    /// The vehicle's MAVLink system id.
    pub system_id: u8,
    /// The vehicle's MAVLink address.
    pub endpoint: String,
    /// `px4` or `ardupilot`, as its HEARTBEAT said.
    pub autopilot: Option<String>,
    /// Goal voxel centre, ENU metres.
    pub goal_m: [f64; 3],
    /// Distance to the goal when plan execution ended (before landing), metres.
    pub final_distance_to_goal_m: Option<f64>,
    /// Times it stopped (or could not start) because a TPG predecessor was late.
    pub gating_waits: usize,
    /// Time it spent waiting at closed gates, seconds.
    pub gating_wait_s: f64,
    /// Its longest single wait at a closed gate, seconds.
    #[serde(default)]
    pub longest_gating_wait_s: f64,
    /// Every event its telemetry reached: scheduled and reached, plan clock.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lateness: Vec<EventLateness>,
    /// Times its link was lost (nothing heard for the mission's link timeout).
    pub link_losses: usize,
    /// Telemetry against the streamed setpoint while it flew on our setpoints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tracking_error: Option<TrackingError>,
    /// Times its setpoint waited for it to come back within the tracking bound.
    #[serde(default)]
    pub tracking_holds: usize,
    /// Seconds its setpoint waited so.
    #[serde(default)]
    pub tracking_hold_s: f64,
    /// How pre-flight placed its vehicle's local frame.
    pub frame: super::placement::FrameFix,
    /// Mission ENU position of its vehicle's local origin, metres.
    pub local_origin_enu_m: [f64; 3],
    /// What its link carried from arming to the end of the flight, measured at
    /// the controller, beside the link budget; `None` in older logs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub link_traffic: Option<super::link_traffic::LinkTraffic>,
    /// Telemetry samples `[t_s, x_m, y_m, z_m]` (ENU; t from the first arm command).
    pub samples: Vec<[f64; 4]>,
}

/// How closely a vehicle followed the setpoints streamed to it, metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrackingError {
    /// Half the samples were closer than this.
    pub median_m: f64,
    /// 95 % of the samples were closer than this.
    pub p95_m: f64,
    /// The largest distance seen.
    pub max_m: f64,
}

/// A notable moment of the flight: a link loss, an abort, a refusal.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LogEvent {
    /// Seconds since the first arm command.
    pub t_s: f64,
    /// The drone it concerns (mission id), or `None` for the whole swarm.
    pub drone: Option<String>,
    /// What happened, for people (tests match on these texts).
    pub message: String,
}

impl LogEvent {
    /// An event `t_s` seconds after the first arm command.
    pub fn new(t_s: f64, drone: Option<&str>, message: &str) -> Self {
        Self {
            t_s,
            drone: drone.map(str::to_string),
            message: message.to_string(),
        }
    }
}

fn infinity() -> f64 {
    f64::INFINITY
}

fn not_finite(value: &f64) -> bool {
    !value.is_finite()
}

fn not_finite_option(value: &Option<f64>) -> bool {
    !value.is_some_and(f64::is_finite)
}

/// A separation for people: metres, or why there is none.
fn separation_text(separation_m: f64) -> String {
    if separation_m.is_finite() {
        format!("{separation_m:.3} m")
    } else {
        "none measured (never two drones heard from)".to_string()
    }
}

impl Summary {
    /// Under an ellipsoid, the scaled separation line of the summary.
    fn scaled_line(&self) -> Option<String> {
        self.min_scaled_separation.map(|scaled| {
            format!(
                "  scaled separation    {} pad to pad (ellipsoid {:.3} m beside × {:.3} m above and below; separated at 1 or more){}",
                if scaled.is_finite() { format!("{scaled:.3}") } else { "none measured".to_string() },
                self.safety_distance_m,
                self.vertical_separation_m.unwrap_or(self.safety_distance_m),
                self.closest_scaled_pair
                    .as_ref()
                    .map_or(String::new(), |(a, b, t)| format!(", {a}–{b} at {t:.1} s"))
            )
        })
    }

    /// Whether the separation held, and if not by how much and where.
    fn safety_line(&self) -> String {
        format!(
            "  safety               {}",
            if self.safety_held {
                "held".to_string()
            } else if let Some(scaled) = self.min_scaled_separation {
                format!(
                    "VIOLATED (scaled {scaled:.3} < 1{})",
                    self.closest_scaled_pair
                        .as_ref()
                        .map_or(String::new(), |(a, b, t)| format!(", {a}–{b} at {t:.1} s"))
                )
            } else {
                format!(
                    "VIOLATED ({} < {:.3} m{})",
                    separation_text(self.min_separation_m),
                    self.safety_distance_m,
                    self.closest_pair
                        .as_ref()
                        .map_or(String::new(), |(a, b, t)| format!(", {a}–{b} at {t:.1} s"))
                )
            }
        )
    }

    /// How long plan execution took against the plan, and the ratio: `40.1 s
    /// (planned 39.8 s, 1.01×)`. Where the time went is on the lines after it
    /// (lateness, gating waits, tracking holds, replans).
    fn execution_line(&self) -> String {
        let planned_s = self.planned_makespan_s;
        let Some(executed_s) = self.executed_makespan_s else {
            return format!("  plan execution       not finished (planned {planned_s:.1} s)");
        };
        let ratio = if planned_s > 0.0 {
            format!(", {:.2}×", executed_s / planned_s)
        } else {
            String::new()
        };
        let replanned = if self.replans.is_empty() {
            ""
        } else {
            "; replanned in flight"
        };
        format!(
            "  plan execution       {executed_s:.1} s (planned {planned_s:.1} s{ratio}{replanned})"
        )
    }

    /// The lines `swarmctl fly` prints.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![
            format!(
                "  completed            {}",
                match (self.completed, self.all_accounted_for()) {
                    (true, true) => "yes",
                    (true, false) => "survivors only: not every drone landed",
                    (false, _) => "NO",
                }
            ),
            format!(
                "  duration             {:.1} s (arm to landed)",
                self.duration_s
            ),
            self.execution_line(),
            format!(
                "  min separation       {} pad to pad (safety distance {:.3} m){}",
                separation_text(self.min_separation_m),
                self.safety_distance_m,
                self.closest_pair
                    .as_ref()
                    .map_or(String::new(), |(a, b, t)| format!(", {a}–{b} at {t:.1} s"))
            ),
            self.safety_line(),
            format!(
                "  max speed            {:.2} m/s (limit {:.2} m/s, {:.0} % tolerance): {}{}",
                self.max_speed_mps,
                self.speed_limit_mps,
                100.0 * SPEED_TOLERANCE,
                if self.speed_held { "held" } else { "EXCEEDED" },
                self.fastest
                    .as_ref()
                    .filter(|_| !self.speed_held)
                    .map_or(String::new(), |(d, t)| format!(", {d} at {t:.1} s"))
            ),
            match &self.worst_tracking {
                Some((id, t)) => format!(
                    "  tracking error       worst {id}: median {:.3} m, p95 {:.3} m, max {:.3} m (telemetry to setpoint)",
                    t.median_m, t.p95_m, t.max_m
                ),
                None => "  tracking error       none measured".to_string(),
            },
            format!(
                "  tracking bound       {:.3} m: {} (setpoints held {} times, {:.1} s in total)",
                self.tracking_bound_m,
                if self.tracking_held {
                    "held"
                } else {
                    "EXCEEDED"
                },
                self.tracking_holds,
                self.tracking_hold_s
            ),
            format!(
                "  gating waits         {}{}",
                self.gating_waits,
                self.longest_gating_wait
                    .as_ref()
                    .map_or(String::new(), |(id, s)| format!(
                        " (longest {s:.1} s, {id})"
                    ))
            ),
            format!(
                "  final pad distance   ≤ {:.3} m (before touchdown)",
                self.max_final_distance_to_goal_m
            ),
        ];
        // After the min separation line.
        if let Some(scaled) = self.scaled_line() {
            lines.insert(4, scaled);
        }
        // After the plan execution line.
        if let Some(lateness) = &self.lateness {
            lines.insert(3, lateness.line());
        }
        lines.extend(
            self.check
                .as_ref()
                .map(|c| format!("  {:<20} {}", "pre-flight check", c.line())),
        );
        lines.extend(self.replans.iter().map(ReplanRecord::line));
        if !self.retired.is_empty() {
            lines.push(format!(
                "  retired early        {}",
                self.retired.join(", ")
            ));
        }
        lines.extend(self.unaccounted_line());
        lines
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ellipsoid_summary_judges_by_the_scaled_separation() {
        let mut s = summary(0.6);
        s.vertical_separation_m = Some(0.75);
        s.min_scaled_separation = Some(0.8);
        s.closest_scaled_pair = Some(("a".into(), "b".into(), 12.0));
        s.safety_held = false;
        let text = s.lines().join("\n");
        assert!(
            text.contains("scaled separation    0.800 pad to pad"),
            "{text}"
        );
        assert!(
            text.contains("VIOLATED (scaled 0.800 < 1, a–b at 12.0 s)"),
            "{text}"
        );
        let json = serde_json::to_string(&s).unwrap();
        let back: Summary = serde_json::from_str(&json).unwrap();
        assert_eq!(back.min_scaled_separation, Some(0.8));
        // A sphere's summary has no scaled line.
        assert!(!summary(0.6).lines().join("\n").contains("scaled"));
    }

    fn summary(min_separation_m: f64) -> Summary {
        Summary {
            completed: false,
            safety_held: true,
            duration_s: 1.0,
            planned_makespan_s: 1.0,
            executed_makespan_s: None,
            min_separation_m,
            closest_pair: None,
            vertical_separation_m: None,
            min_scaled_separation: None,
            closest_scaled_pair: None,
            safety_distance_m: 0.25,
            max_speed_mps: 0.0,
            fastest: None,
            speed_held: true,
            speed_limit_mps: 1.0,
            gating_waits: 0,
            gating_wait_s: 0.0,
            longest_gating_wait: None,
            lateness: None,
            max_final_distance_to_goal_m: 0.0,
            worst_tracking: None,
            tracking_bound_m: 0.3,
            tracking_held: true,
            tracking_holds: 0,
            tracking_hold_s: 0.0,
            lost: Vec::new(),
            lost_last_known: Vec::new(),
            retired: Vec::new(),
            handed_over: Vec::new(),
            replans: Vec::new(),
            check: None,
            unaccounted: Vec::new(),
        }
    }

    #[test]
    fn a_late_plan_says_where_the_time_went_and_a_lost_drone_where_it_was() {
        let mut s = summary(0.6);
        s.planned_makespan_s = 40.0;
        s.executed_makespan_s = Some(44.5);
        s.gating_waits = 7;
        s.gating_wait_s = 6.3;
        s.longest_gating_wait = Some(("r2".into(), 2.4));
        s.tracking_holds = 2;
        s.tracking_hold_s = 1.5;
        s.lost = vec!["b3".into()];
        s.lost_last_known = vec![LastKnown {
            id: "b3".into(),
            t_s: Some(14.7),
            position_m: Some([1.0, 2.5, 1.5]),
            armed: true,
            landed_state: Some("in the air".into()),
            battery_pct: Some(81),
        }];
        let text = s.lines().join("\n");
        assert!(
            text.contains("plan execution       44.5 s (planned 40.0 s, 1.11×)"),
            "{text}"
        );
        assert!(
            text.contains("gating waits         7 (longest 2.4 s, r2)"),
            "{text}"
        );
        // Lost, and listed once whether or not the log kept `unaccounted`.
        s.completed = true;
        assert!(!s.succeeded());
        for unaccounted in [
            Vec::new(),
            vec![Unaccounted {
                id: "b3".into(),
                phase: "LOST".into(),
                reason: None,
            }],
        ] {
            s.unaccounted = unaccounted;
            let text = s.lines().join("\n");
            assert!(
                text.contains("  unaccounted for      1 drone: LOST b3 (last position (1.00, 2.50, 1.50) m ENU at 14.7 s; armed, in the air, battery 81 %)"),
                "{text}"
            );
            assert_eq!(text.matches("LOST b3").count(), 1, "{text}");
        }
        let text = s.lines().join("\n");
        assert!(
            text.contains("completed            survivors only: not every drone landed"),
            "{text}"
        );
        s.executed_makespan_s = Some(40.0);
        assert!(
            s.lines()
                .join("\n")
                .contains("plan execution       40.0 s (planned 40.0 s, 1.00×)\n")
        );
    }

    #[test]
    fn broken_limits_are_named_in_the_summary() {
        let mut s = summary(0.2);
        s.safety_held = false;
        s.closest_pair = Some(("b3".into(), "b4".into(), 22.0));
        s.max_speed_mps = 1.46;
        s.speed_held = false;
        s.fastest = Some(("r2".into(), 9.5));
        let text = s.lines().join("\n");
        assert!(
            text.contains("safety               VIOLATED (0.200 m < 0.250 m, b3–b4 at 22.0 s)"),
            "{text}"
        );
        assert!(text.contains("EXCEEDED, r2 at 9.5 s"), "{text}");
        assert!(text.contains("completed            NO"), "{text}");
    }

    #[test]
    fn unmeasured_separation_is_omitted_not_null_and_reads_back() {
        let json = serde_json::to_string(&summary(f64::INFINITY)).expect("serialises");
        assert!(!json.contains("min_separation"), "{json}");
        let back: Summary = serde_json::from_str(&json).expect("reads back");
        assert!(back.min_separation_m.is_infinite());
        let json = serde_json::to_string(&summary(0.5)).expect("serialises");
        assert!(json.contains("\"min_separation_m\":0.5"), "{json}");
    }

    #[test]
    fn the_pre_flight_check_is_one_summary_line_and_reads_back() {
        let mut s = summary(0.9);
        s.check = Some(CheckFigures {
            drones: 8,
            samples: 812,
            sample_period_s: 0.05,
            min_separation_bound_m: 0.612,
            required_separation_m: 0.4,
            min_scaled_bound: None,
            closest: Some(("b1".into(), "r2".into(), 12.5)),
            max_speed_mps: 0.95,
            max_accel_mps2: 1.9,
            max_jerk_mps3: 2.4,
            check_s: 0.0031,
            violations: Vec::new(),
        });
        let lines: Vec<String> = s
            .lines()
            .into_iter()
            .filter(|l| l.contains("pre-flight check"))
            .collect();
        assert_eq!(lines.len(), 1, "{lines:?}");
        assert!(
            lines[0].contains("min separation ≥ 0.612 m (setpoints need 0.400 m)")
                && lines[0].contains("8 drones × 812 samples in 3.1 ms"),
            "{}",
            lines[0]
        );
        let json = serde_json::to_string(&s).expect("serialises");
        let back: Summary = serde_json::from_str(&json).expect("reads back");
        assert_eq!(back.check, s.check);
        // A log from before the check was logged reads back without it.
        let old = json.replace(",\"check\":", ",\"unused\":");
        let back: Summary = serde_json::from_str(&old).expect("reads back");
        assert_eq!(back.check, None);
    }

    #[test]
    fn replans_are_in_the_summary_with_their_outcome() {
        let mut s = summary(0.9);
        let record = |fallback: Option<&str>| ReplanRecord {
            at_s: 17.4,
            why: "b1 (lost)".into(),
            left_out: if fallback.is_none() {
                vec!["b1".into()]
            } else {
                Vec::new()
            },
            planning_s: 0.0042,
            latency_s: 1.4,
            old_makespan_s: 39.8,
            new_makespan_s: fallback.is_none().then_some(31.5),
            fallback: fallback.map(String::from),
            check: None,
        };
        s.replans = vec![
            record(None),
            record(Some("planning took 3.20 s, over the 3.0 s deadline")),
        ];
        let text = s.lines().join("\n");
        assert!(
            text.contains("replanned            at 17.4 s without b1: new plan 31.5 s (old 39.8 s), planned in 4.2 ms, flying 1.40 s after the loss was noticed"),
            "{text}"
        );
        assert!(
            text.contains("NOT replanned        at 17.4 s without b1 (lost): planning took 3.20 s"),
            "{text}"
        );
        let json = serde_json::to_string(&s).expect("serialises");
        let back: Summary = serde_json::from_str(&json).expect("reads back");
        assert_eq!(back.replans, s.replans);
    }
}
