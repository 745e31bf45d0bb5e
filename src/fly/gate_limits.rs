//! The gate check a moving drone passes every tick, and a drone at rest before it
//! starts a run: where along the run it must be able to stop, and whether braking
//! one tick from now would still stop there.

use super::course::Course;
use super::gate::GateAhead;
use super::path::RouteRun;
use crate::profile::{Brake, Kinematics, State};

/// Stop this far short of a closed gate's marker (the schedule budgets each
/// hand-over's decision with the same margin).
pub(super) const STOP_MARGIN_M: f64 = crate::schedule::GATE_STOP_MARGIN_M;

/// Where a run's gate check looks, metres along the current run.
#[derive(Debug, Clone, Copy)]
pub(super) struct GateLimits {
    /// Stop by here unless the first gate opens before the drone reaches it.
    stop_x_m: f64,
    /// Stop by here in any case (the first gate not committed to open).
    hard_stop_x_m: f64,
    /// The first closed gate.
    gate_x_m: f64,
    /// When every gate before the hard limit has opened at the latest.
    opens_by_s: f64,
}

impl GateLimits {
    /// The limits a run keeps: [`STOP_MARGIN_M`] short of a gate inside it, but
    /// all the way to its end for a gate right there. The run ends at rest at that
    /// point, where the schedule holds the drone before the event (its departure)
    /// and where the next run starts held anyway; stopping a centimetre short
    /// instead cost a creep of half a second once the gate opened.
    pub(super) fn on(run: &RouteRun, gate: GateAhead) -> Self {
        let stop_short_of = |gate_arc_m: f64| {
            let x_m = gate_arc_m - run.arc_start_m;
            if (x_m - run.length_m).abs() <= 1e-9 {
                run.length_m + 1e-9
            } else {
                x_m - STOP_MARGIN_M
            }
        };
        Self {
            stop_x_m: stop_short_of(gate.arc_m),
            hard_stop_x_m: stop_short_of(gate.hard_arc_m),
            gate_x_m: gate.arc_m - run.arc_start_m,
            opens_by_s: gate.opens_by_s,
        }
    }

    /// Whether a drone flying `course` from `x0_m`, begun at `t0_s`, must brake
    /// now, `dt_s` being the period: braking at the next tick would stop past a
    /// gate not committed to open, or past the first closed gate when it would
    /// reach that gate before it opens.
    pub(super) fn must_brake(
        &self,
        (x0_m, course, t0_s): (f64, Course, f64),
        (t_s, dt_s): (f64, f64),
        limits: Kinematics,
    ) -> bool {
        let next = course.state_at(t_s + dt_s - t0_s);
        let stop_next_m = Brake::new(
            State {
                x_m: x0_m + next.x_m,
                ..next
            },
            limits,
        )
        .stop_m();
        // Past the point where it could still stop before the first gate, it
        // flies on only if it reaches that gate after it opens.
        let too_early = stop_next_m > self.stop_x_m
            && !(self.gate_x_m <= x0_m + course.length_m()
                && t0_s + course.time_at_distance_s(self.gate_x_m - x0_m) >= self.opens_by_s);
        stop_next_m > self.hard_stop_x_m || too_early
    }
}
