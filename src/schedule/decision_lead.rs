//! How long before a hand-over the drone that waits for it must already know that
//! the gate will be open: the gap budgeted on a type-2 edge so that a flight on
//! time flies through its gates instead of braking at them.
//!
//! The executor lets a drone B fly past the point where it could still stop short
//! of a closed gate only if the gate's predecessor A is *committed* to open it in
//! time: A's setpoint, braking from where it is now, still passes A's event by
//! when B reaches its own (`fly::gate::Progress::commit`). With the bare edge
//! (B leaves its event no earlier than A reaches its own) B must decide a
//! stopping distance and a tick or two before its event, but A is committed only
//! once braking would carry it past its event, and braking passes it later than
//! flying on does: A still speeding up at its event commits late, and even a
//! cruising A commits to a time after B's arrival. B then brakes at the
//! hand-over although A is on time. [`DecisionLead`] gives each edge the least
//! extra gap that lets B fly on.
//!
//! With `dt` the setpoint period, B's run passing its event at offset `t_B`, and
//! `u_B` the first offset where braking from B's state would stop past the gate
//! (less [`GATE_STOP_MARGIN_M`]), B decides at a tick within `dt` before `u_B`,
//! on A's commitment of a tick before that: A's state is read
//! `λ = t_B − u_B + 2·dt` before B reaches its event, plus one `dt` for the tick
//! phase. Along A's run, `pass(τ)` — when braking from A's state at offset `τ`
//! passes A's event (∞ if it stops short, `t_A` from `t_A` on) — only falls, as
//! braking later never passes a point later. The gap `g` must satisfy
//! `pass(t_A + g − λ) ≤ t_A + g`, which holds at `g = λ` and, once it holds,
//! for every larger `g`; the least such `g` is found by bisection. An event
//! where B's run ends or starts needs none: B stops there anyway, right at the
//! gate, or sets off from rest once the gate has opened.
//!
//! The gap only delays runs, so every argument of the schedule stands.

use crate::profile::{Brake, Kinematics, Profile};
use std::collections::HashMap;

/// A run's gate check stops this far short of a closed gate inside the run
/// (`fly::gate_limits`, which uses this very constant), metres.
pub const GATE_STOP_MARGIN_M: f64 = 0.01;

/// A setpoint braking to a stop this close short of an event counts as passing
/// it (`fly::follower` commits with the same tolerance): a run that comes to rest
/// at its event brakes exactly as hard as braking now, and rounding puts its stop
/// a hair either side of the event.
pub const COMMIT_TOLERANCE_M: f64 = 1e-6;

/// Bisection stops once the gap is known to this, seconds.
const GAP_TOLERANCE_S: f64 = 1e-5;

/// One side of a hand-over: a run and the offset in it at which the event is
/// passed (A reaches it, or B leaves it).
#[derive(Debug, Clone, Copy)]
pub struct RunPoint<'a> {
    pub profile: &'a Profile,
    pub offset_s: f64,
}

/// The gap budget of hand-overs for one setpoint period and one set of limits,
/// remembered per run length and offset (a plan has few distinct ones).
#[derive(Debug)]
pub struct DecisionLead {
    period_s: f64,
    limits: Kinematics,
    leads: HashMap<(u64, u64), f64>,
    gaps: HashMap<(u64, u64, u64), f64>,
}

impl DecisionLead {
    /// The budget for setpoints streamed every `period_s` (0 budgets nothing) on
    /// runs flown within `limits`.
    pub fn new(period_s: f64, limits: Kinematics) -> Self {
        Self {
            period_s,
            limits,
            leads: HashMap::new(),
            gaps: HashMap::new(),
        }
    }

    /// The least time, seconds, from A passing its event (`from`) to B leaving
    /// its own (`to`) that lets B fly through its gate at full speed.
    pub fn gap_s(&mut self, from: RunPoint, to: RunPoint) -> f64 {
        if self.period_s <= 0.0 {
            return 0.0;
        }
        let decision_s = self.lead_s(to);
        if decision_s <= 0.0 {
            return 0.0;
        }
        let lead_s = decision_s + 3.0 * self.period_s;
        let key = (
            from.profile.length_m.to_bits(),
            from.offset_s.to_bits(),
            lead_s.to_bits(),
        );
        if let Some(&gap) = self.gaps.get(&key) {
            return gap;
        }
        let gap = least_gap_s(from, lead_s, self.limits);
        self.gaps.insert(key, gap);
        gap
    }

    /// How long before passing its event B must decide whether to brake for it:
    /// from the first offset where braking would stop past the gate, seconds (0
    /// for an event at the end of the run, where B stops anyway, and at its start,
    /// where B sets off once the gate has opened).
    fn lead_s(&mut self, to: RunPoint) -> f64 {
        let key = (to.profile.length_m.to_bits(), to.offset_s.to_bits());
        if let Some(&lead) = self.leads.get(&key) {
            return lead;
        }
        let x_m = to.profile.distance_at_m(to.offset_s);
        let lead = if x_m >= to.profile.length_m - 1e-9 {
            0.0
        } else {
            let stop_x_m = x_m - GATE_STOP_MARGIN_M;
            let stops_past =
                |u_s: f64| Brake::new(to.profile.state_at(u_s), self.limits).stop_m() > stop_x_m;
            // The stopping point only moves on along a profile: bisect for the
            // first offset past it.
            let (mut lo, mut hi) = (0.0, to.offset_s);
            if stops_past(lo) {
                hi = lo;
            }
            while hi - lo > GAP_TOLERANCE_S {
                let mid = 0.5 * (lo + hi);
                if stops_past(mid) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            to.offset_s - hi
        };
        self.leads.insert(key, lead);
        lead
    }
}

/// When braking from A's state at offset `tau_s` passes A's event at `x_m`,
/// offset seconds in A's run (∞ if it stops short; the event's own offset from there on).
fn pass_s(from: RunPoint, x_m: f64, tau_s: f64, limits: Kinematics) -> f64 {
    if tau_s >= from.offset_s {
        return from.offset_s;
    }
    if tau_s < 0.0 {
        return f64::INFINITY;
    }
    Brake::new(from.profile.state_at(tau_s), limits)
        .time_to_pass_s(x_m - COMMIT_TOLERANCE_M)
        .map_or(f64::INFINITY, |after_s| tau_s + after_s)
}

/// The least gap `g` in `[0, lead_s]` with `pass(t_A + g − lead) ≤ t_A + g`.
fn least_gap_s(from: RunPoint, lead_s: f64, limits: Kinematics) -> f64 {
    let x_m = from.profile.distance_at_m(from.offset_s);
    let t_a = from.offset_s;
    let holds = |g: f64| pass_s(from, x_m, t_a + g - lead_s, limits) <= t_a + g + 1e-9;
    if holds(0.0) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, lead_s);
    while hi - lo > GAP_TOLERANCE_S {
        let mid = 0.5 * (lo + hi);
        if holds(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: Kinematics = Kinematics {
        max_speed_mps: 1.0,
        max_accel_mps2: 1.0,
        max_jerk_mps3: 2.0,
    };

    /// The follower's rule, replayed at one tick phase: B runs `to` from
    /// `start_b_s`; A runs `from` from 0. At each tick B looks at A's commitment
    /// of the tick before and brakes if braking a tick later would stop past its
    /// gate while A is not committed to pass its event by B's arrival there.
    fn b_brakes(from: RunPoint, to: RunPoint, start_b_s: f64, dt_s: f64, phase_s: f64) -> bool {
        let x_a = from.profile.distance_at_m(from.offset_s);
        let x_b = to.profile.distance_at_m(to.offset_s);
        let arrive_b_s = start_b_s + to.offset_s;
        let mut t = phase_s;
        while t < arrive_b_s {
            let u = t - start_b_s;
            if u >= 0.0 {
                let next = to.profile.state_at(u + dt_s);
                let stop_next = Brake::new(next, LIMITS).stop_m();
                if stop_next > x_b - GATE_STOP_MARGIN_M {
                    let seen = pass_s(from, x_a, t - dt_s, LIMITS);
                    if seen > arrive_b_s {
                        return true;
                    }
                }
            }
            t += dt_s;
        }
        false
    }

    #[test]
    fn a_dependant_flies_on_with_the_gap_and_brakes_without_it() {
        let dt_s = 0.05;
        let long = Profile::new(4.0, LIMITS);
        // A passes its event still speeding up, 0.2 m into its run; B crosses its
        // own at cruise halfway along.
        let from = RunPoint {
            profile: &long,
            offset_s: long.time_at_distance_s(0.2),
        };
        let to = RunPoint {
            profile: &long,
            offset_s: long.time_at_distance_s(2.0),
        };
        let mut budget = DecisionLead::new(dt_s, LIMITS);
        let gap_s = budget.gap_s(from, to);
        assert!(gap_s > 0.2, "{gap_s}");
        let phases = || (0..10).map(|k| dt_s * f64::from(k) / 10.0);
        let start_with = from.offset_s + gap_s - to.offset_s;
        for phase_s in phases() {
            assert!(
                !b_brakes(from, to, start_with, dt_s, phase_s),
                "phase {phase_s}"
            );
        }
        let start_short = start_with - 2.0 * dt_s;
        assert!(phases().any(|phase_s| b_brakes(from, to, start_short, dt_s, phase_s)));
    }

    #[test]
    fn a_predecessor_braking_to_its_event_is_committed_as_it_brakes() {
        let dt_s = 0.05;
        let (short, long) = (Profile::new(1.0, LIMITS), Profile::new(4.0, LIMITS));
        let stopping = RunPoint {
            profile: &short,
            offset_s: short.duration_s(),
        };
        let cruising = RunPoint {
            profile: &long,
            offset_s: long.time_at_distance_s(2.0),
        };
        let gap_s = DecisionLead::new(dt_s, LIMITS).gap_s(stopping, cruising);
        assert_eq!(gap_s, 0.0);
        assert!(!b_brakes(
            stopping,
            cruising,
            stopping.offset_s - cruising.offset_s,
            dt_s,
            0.0
        ));
    }

    #[test]
    fn no_gap_at_the_end_of_the_dependants_run_or_without_a_period() {
        let p = Profile::new(2.0, LIMITS);
        let end = RunPoint {
            profile: &p,
            offset_s: p.duration_s(),
        };
        let mid = RunPoint {
            profile: &p,
            offset_s: p.time_at_distance_s(1.0),
        };
        assert_eq!(DecisionLead::new(0.05, LIMITS).gap_s(end, end), 0.0);
        assert_eq!(DecisionLead::new(0.0, LIMITS).gap_s(end, mid), 0.0);
    }

    #[test]
    fn a_predecessor_still_speeding_up_needs_more_than_one_cruising() {
        let dt_s = 0.05;
        let long = Profile::new(6.0, LIMITS);
        let cruising = RunPoint {
            profile: &long,
            offset_s: long.time_at_distance_s(3.0),
        };
        let speeding_up = RunPoint {
            profile: &long,
            offset_s: long.time_at_distance_s(0.2),
        };
        let mut budget = DecisionLead::new(dt_s, LIMITS);
        let after_cruise = budget.gap_s(cruising, cruising);
        let after_start = budget.gap_s(speeding_up, cruising);
        assert!(
            after_cruise < after_start,
            "{after_cruise} vs {after_start}"
        );
        assert!(after_cruise > 0.0, "{after_cruise}");
    }
}
