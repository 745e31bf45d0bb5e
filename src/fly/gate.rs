//! Which events each drone has passed, and which gates are therefore still
//! closed for the others.
//!
//! An event is *reached* when telemetry shows the drone at or past it along its
//! route (within [`REACH_TOLERANCE_M`], which absorbs the vehicle's sensor noise
//! at rest points); that is what lateness is measured on. It is *released* — it
//! no longer holds anyone up — once reached, or earlier, once the drone's
//! commanded setpoint has passed it while the vehicle is trusted: its telemetry
//! fresh and within the mission's tracking bound of its setpoint (see
//! [`Progress::release_commanded`] and the argument in `crate::schedule`). A drone
//! that is late, lost, or off its setpoint is never trusted, so it still holds up
//! exactly the drones whose events depend on it until telemetry shows it past,
//! and a drone whose link is lost holds them up until it is heard again.

use super::path::Route;

/// Telemetry within this distance short of an event counts as reaching it.
pub const REACH_TOLERANCE_M: f64 = 0.03;

/// Observed and released progress of one drone along its route.
#[derive(Debug, Clone, Default)]
pub struct Progress {
    /// Events `0..reached` have been observed reached.
    pub reached: usize,
    /// Events `0..released` no longer hold anyone up (`released ≥ reached`).
    pub released: usize,
    /// When each of the events `released..released + committed.len()` will have
    /// been passed by the drone's setpoint at the latest, plan-clock seconds: its
    /// setpoint is committed to pass them (see [`Progress::commit`]).
    pub committed_by_s: Vec<f64>,
    /// When each of the events `0..released` was released, plan-clock seconds.
    pub released_at_s: Vec<f64>,
    /// The run the telemetry is on (advances only when its end is observed).
    pub observed_run: usize,
    /// Observed arc length along the route (monotone).
    pub observed_arc_m: f64,
    /// When each of the events `0..reached` was observed reached, plan-clock seconds.
    pub reached_at_s: Vec<f64>,
}

impl Progress {
    /// Folds in a telemetry position (ENU) given the commanded `(arc, run)`, at
    /// plan-clock time `t_s`.
    ///
    /// The run telemetry is on ends when the commanded motion has moved on and
    /// telemetry is within `settle_tolerance_m` (plus [`REACH_TOLERANCE_M`]) of
    /// its end: the follower starts the next run only once telemetry settled that
    /// close, and a vehicle that settled a few centimetres short and then turned
    /// the corner would otherwise never be seen to finish the run — and hold
    /// everyone gated on it for ever.
    pub fn observe(
        &mut self,
        route: &Route,
        position_m: [f64; 3],
        (commanded_arc_m, commanded_run): (f64, usize),
        t_s: f64,
        settle_tolerance_m: f64,
    ) {
        let run_end_tolerance_m = REACH_TOLERANCE_M.max(settle_tolerance_m) + REACH_TOLERANCE_M;
        while let Some(run) = route.runs.get(self.observed_run) {
            let along = run.project_m(position_m);
            self.observed_arc_m = self.observed_arc_m.max(run.arc_start_m + along);
            if along >= run.length_m - run_end_tolerance_m && self.observed_run < commanded_run {
                // The run's end counts as reached: the next run starts from it.
                self.observed_arc_m = self.observed_arc_m.max(run.arc_start_m + run.length_m);
                self.observed_run += 1;
            } else {
                break;
            }
        }
        let arc = self.observed_arc_m.min(commanded_arc_m);
        while let Some(e) = route.events.get(self.reached) {
            if arc >= e.arc_m - REACH_TOLERANCE_M {
                self.reached += 1;
                self.reached_at_s.push(t_s);
            } else {
                break;
            }
        }
        self.release_to(self.reached, t_s);
    }

    /// Releases the events the commanded setpoint has passed (`commanded_arc_m`,
    /// the arc length of the setpoint last streamed), at plan-clock time `t_s`. The
    /// caller vouches that the vehicle is trusted right now: telemetry fresh and
    /// within the tracking bound of its setpoint, on our setpoints. A vehicle within
    /// `e` of a setpoint that has left a voxel's hold is where the schedule's
    /// argument (run with `d + 2e`) wants it; its setpoint only moves on from there.
    pub fn release_commanded(&mut self, route: &Route, commanded_arc_m: f64, t_s: f64) {
        const PASSED_EPS_M: f64 = 1e-6;
        let passed = route.events[self.released.min(route.events.len())..]
            .iter()
            .take_while(|e| e.arc_m <= commanded_arc_m + PASSED_EPS_M)
            .count();
        self.release_to(self.released + passed, t_s);
    }

    /// Records by when the setpoint will have passed the events it is committed to:
    /// `latest_pass_s(arc)` is the latest plan-clock time the setpoint passes `arc`
    /// whatever it does next (braking now is the slowest it can go), `None` past
    /// where it could stop. The caller vouches the vehicle is trusted, as for
    /// [`Progress::release_commanded`]; `clear` forgets every commitment.
    pub fn commit(&mut self, route: &Route, latest_pass_s: impl Fn(f64) -> Option<f64>) {
        self.committed_by_s.clear();
        for e in route.events.iter().skip(self.released) {
            match latest_pass_s(e.arc_m) {
                Some(t_s) => self.committed_by_s.push(t_s),
                None => break,
            }
        }
    }

    /// Forgets every commitment (the vehicle is not trusted right now).
    pub fn clear_commitments(&mut self) {
        self.committed_by_s.clear();
    }

    /// By when event `index`'s drone will have passed it at the latest, if its
    /// setpoint is committed to (∞ when not, −∞ once released).
    fn passed_by_s(&self, index: u32) -> f64 {
        let i = index as usize;
        if i < self.released {
            return f64::NEG_INFINITY;
        }
        self.committed_by_s
            .get(i - self.released)
            .copied()
            .unwrap_or(f64::INFINITY)
    }

    /// Every event of the route released (a retired drone that is down and out
    /// of everyone's way); no release times are recorded.
    pub fn release_all(&mut self, events: usize) {
        self.released = self.released.max(events);
    }

    fn release_to(&mut self, count: usize, t_s: f64) {
        while self.released < count {
            self.released += 1;
            self.released_at_s.push(t_s);
            if !self.committed_by_s.is_empty() {
                self.committed_by_s.remove(0);
            }
        }
    }

    /// When event `index` was released, plan-clock seconds.
    pub fn released_at_s(&self, index: u32) -> Option<f64> {
        self.released_at_s.get(index as usize).copied()
    }
}

/// The closed gates ahead of a drone, as its follower needs them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GateAhead {
    /// Arc length of the first closed gate (∞ if none).
    pub arc_m: f64,
    /// Arc length of the first closed gate not known to open in time: every closed
    /// gate before it has predecessors whose setpoints are committed to pass them
    /// (∞ if none; `arc_m` when the first one is not).
    pub hard_arc_m: f64,
    /// By when the closed gates before `hard_arc_m` will all have opened at the
    /// latest, plan-clock seconds (−∞ when there are none).
    pub opens_by_s: f64,
}

impl GateAhead {
    /// No closed gate ahead.
    pub const OPEN: Self = Self {
        arc_m: f64::INFINITY,
        hard_arc_m: f64::INFINITY,
        opens_by_s: f64::NEG_INFINITY,
    };

    /// One closed gate at `arc_m`, not known to open (tests).
    #[cfg(test)]
    pub fn closed_at(arc_m: f64) -> Self {
        Self {
            arc_m,
            hard_arc_m: arc_m,
            opens_by_s: f64::NEG_INFINITY,
        }
    }
}

/// The closed gates ahead of `commanded_arc_m` at plan-clock time `t_s` (events
/// whose predecessors are not all released, or released less than its hold ago),
/// and the drone the first waits for. Gates whose predecessors are committed to
/// pass (see [`Progress::commit`]) are told apart up to the first that is not, so
/// the follower may fly through them if it reaches them no earlier than they open.
/// `passed` counts the events already behind the commanded position (kept by the
/// caller, monotone).
pub fn closed_gate(
    route: &Route,
    passed: &mut usize,
    all: &[Progress],
    commanded_arc_m: f64,
    t_s: f64,
) -> (GateAhead, Option<u32>) {
    const PASSED_EPS_M: f64 = 1e-6;
    while let Some(e) = route.events.get(*passed) {
        if e.arc_m < commanded_arc_m - PASSED_EPS_M {
            *passed += 1;
        } else {
            break;
        }
    }
    let mut ahead = GateAhead::OPEN;
    let mut first_blocker = None;
    for e in &route.events[*passed..] {
        let mut closed_by = None;
        let mut opens_by_s = f64::NEG_INFINITY;
        for id in &e.after {
            let by_s = all
                .get(id.drone as usize)
                .map_or(f64::INFINITY, |p| p.passed_by_s(id.index));
            if by_s > f64::NEG_INFINITY {
                closed_by.get_or_insert(id.drone);
                opens_by_s = opens_by_s.max(by_s);
            }
        }
        if closed_by.is_none() && e.hold_s > 0.0 {
            // The whole swarm is in formation: hold it for `hold_s` after the last
            // of them arrived (released its arrival).
            let last = e
                .after
                .iter()
                .filter_map(|id| Some((all.get(id.drone as usize)?.released_at_s(id.index)?, id)))
                .max_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((at_s, id)) = last
                && t_s < at_s + e.hold_s
            {
                closed_by = Some(id.drone);
                opens_by_s = f64::INFINITY;
            }
        }
        let Some(blocker) = closed_by else {
            continue;
        };
        if first_blocker.is_none() {
            first_blocker = Some(blocker);
            ahead.arc_m = e.arc_m;
        }
        // A hold is never committed: its drones' arrivals are not enough.
        if opens_by_s.is_finite() && e.hold_s <= 0.0 {
            ahead.opens_by_s = ahead.opens_by_s.max(opens_by_s);
        } else {
            ahead.hard_arc_m = e.arc_m;
            break;
        }
    }
    (ahead, first_blocker)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::path::RouteEvent;
    use crate::schedule::EventId;

    fn route(events: Vec<RouteEvent>) -> Route {
        Route {
            id: "a".into(),
            start_m: [0.0; 3],
            runs: Vec::new(),
            events,
        }
    }

    fn run(from_m: [f64; 3], to_m: [f64; 3], arc_start_m: f64) -> crate::fly::path::RouteRun {
        let length_m = crate::fly::path::distance_m(from_m, to_m);
        crate::fly::path::RouteRun {
            from_m,
            to_m,
            length_m,
            arc_start_m,
            scheduled_start_s: 0.0,
            profile: crate::trajectory::Profile::new(
                length_m,
                crate::profile::Kinematics {
                    max_speed_mps: 1.0,
                    max_accel_mps2: 1.0,
                    max_jerk_mps3: 5.0,
                },
            ),
        }
    }

    /// A vehicle that settled 7 cm short of a corner (within the 5 cm settle
    /// tolerance the follower starts the next run on, plus the 3 cm reach tolerance)
    /// and turned it is seen to have
    /// finished the first run: its events at the corner, and those it passes on the
    /// second run, count as reached. Seen only along the first run's line, it never
    /// would be, and every drone gated on it would wait for ever.
    #[test]
    fn a_corner_cut_inside_the_settle_tolerance_still_counts() {
        let event = |arc_m: f64| RouteEvent {
            kind: crate::schedule::EventKind::Arrive,
            voxel: crate::world::Voxel::new(0, 0, 0),
            step: 0,
            position_m: [arc_m, 0.0, 0.0],
            arc_m,
            reach_s: 0.0,
            after: Vec::new(),
            hold_s: 0.0,
        };
        let mut r = route(vec![event(1.0), event(1.5)]);
        r.runs = vec![
            run([0.0; 3], [1.0, 0.0, 0.0], 0.0),
            run([1.0, 0.0, 0.0], [1.0, 1.0, 0.0], 1.0),
        ];
        let mut p = Progress::default();
        // Settled 7 cm short; the follower has moved on to run 1.
        p.observe(&r, [0.93, 0.0, 0.0], (1.0, 1), 1.0, 0.05);
        assert_eq!(p.observed_run, 1);
        assert_eq!(p.reached, 1, "the corner's event");
        p.observe(&r, [0.95, 0.6, 0.0], (1.6, 1), 2.0, 0.05);
        assert_eq!(p.reached, 2, "and the one half-way along run 1");
        // With no settle tolerance only the 3 cm reach tolerance is left twice: missed.
        let mut strict = Progress::default();
        strict.observe(&r, [0.93, 0.0, 0.0], (1.0, 1), 1.0, 0.0);
        assert_eq!((strict.observed_run, strict.reached), (0, 0));
    }

    /// A setpoint past an event releases it for the drones gated on it before
    /// telemetry reaches it; reaching it (lateness is measured on that) comes later
    /// and releases nothing twice.
    #[test]
    fn the_commanded_setpoint_releases_events_before_telemetry_reaches_them() {
        let event = |arc_m: f64| RouteEvent {
            kind: crate::schedule::EventKind::Arrive,
            voxel: crate::world::Voxel::new(0, 0, 0),
            step: 0,
            position_m: [arc_m, 0.0, 0.0],
            arc_m,
            reach_s: 0.0,
            after: Vec::new(),
            hold_s: 0.0,
        };
        let mut r = route(vec![event(0.5), event(1.0)]);
        r.runs = vec![run([0.0; 3], [1.0, 0.0, 0.0], 0.0)];
        let waiter = route(vec![RouteEvent {
            after: vec![EventId { drone: 1, index: 0 }],
            ..event(0.2)
        }]);
        let mut all = vec![Progress::default(), Progress::default()];
        let mut passed = 0;
        assert_eq!(closed_gate(&waiter, &mut passed, &all, 0.0, 1.0).1, Some(1));
        all[1].release_commanded(&r, 0.6, 1.0);
        assert_eq!((all[1].reached, all[1].released), (0, 1));
        assert_eq!(closed_gate(&waiter, &mut passed, &all, 0.0, 1.0).1, None);
        // Telemetry catches up: reached, nothing released again.
        all[1].observe(&r, [0.55, 0.0, 0.0], (0.6, 0), 1.2, 0.05);
        assert_eq!((all[1].reached, all[1].released), (1, 1));
        assert_eq!(all[1].released_at_s, vec![1.0]);
        assert_eq!(all[1].reached_at_s, vec![1.2]);
        // A setpoint short of the second event releases nothing more.
        all[1].release_commanded(&r, 0.9, 1.3);
        assert_eq!(all[1].released, 1);
    }

    /// A predecessor committed to pass its event tells the gate by when it opens;
    /// the first gate whose predecessor is not committed is where the drone must
    /// be able to stop.
    #[test]
    fn committed_predecessors_say_by_when_their_gates_open() {
        let event = |arc_m: f64, after: Vec<EventId>| RouteEvent {
            kind: crate::schedule::EventKind::Enter,
            voxel: crate::world::Voxel::new(0, 0, 0),
            step: 0,
            position_m: [arc_m, 0.0, 0.0],
            arc_m,
            reach_s: 0.0,
            after,
            hold_s: 0.0,
        };
        let a = |index: u32| EventId { drone: 1, index };
        let waiter = route(vec![event(0.5, vec![a(0)]), event(1.5, vec![a(1)])]);
        let leader = route(vec![event(1.0, vec![]), event(2.0, vec![])]);
        let mut all = vec![Progress::default(), Progress::default()];
        let mut passed = 0;
        let (gate, blocker) = closed_gate(&waiter, &mut passed, &all, 0.0, 0.0);
        assert_eq!((gate, blocker), (GateAhead::closed_at(0.5), Some(1)));
        // Committed to pass its first event by 3 s, not its second.
        all[1].commit(&leader, |arc_m| (arc_m <= 1.2).then_some(3.0));
        let (gate, _) = closed_gate(&waiter, &mut passed, &all, 0.0, 0.0);
        assert_eq!(
            (gate.arc_m, gate.hard_arc_m, gate.opens_by_s),
            (0.5, 1.5, 3.0)
        );
        // Released: the committed time moves on with it; the second gate is first.
        all[1].release_commanded(&leader, 1.0, 2.5);
        assert!(all[1].committed_by_s.is_empty());
        let (gate, _) = closed_gate(&waiter, &mut passed, &all, 0.0, 2.5);
        assert_eq!(gate, GateAhead::closed_at(1.5));
    }

    #[test]
    fn a_hold_keeps_the_gate_closed_until_it_has_passed_since_the_last_arrival() {
        let other = EventId { drone: 1, index: 0 };
        let r = route(vec![RouteEvent {
            kind: crate::schedule::EventKind::Start,
            voxel: crate::world::Voxel::new(0, 0, 0),
            step: 0,
            position_m: [0.0; 3],
            arc_m: 0.0,
            reach_s: 0.0,
            after: vec![other],
            hold_s: 2.0,
        }]);
        let mut all = vec![Progress::default(), Progress::default()];
        let mut passed = 0;
        // Not reached yet: closed, waiting for drone 1.
        assert_eq!(
            closed_gate(&r, &mut passed, &all, 0.0, 5.0),
            (GateAhead::closed_at(0.0), Some(1))
        );
        all[1].released = 1;
        all[1].released_at_s = vec![5.0];
        assert_eq!(
            closed_gate(&r, &mut passed, &all, 0.0, 6.9),
            (GateAhead::closed_at(0.0), Some(1))
        );
        assert_eq!(closed_gate(&r, &mut passed, &all, 0.0, 7.0).1, None);
    }
}
