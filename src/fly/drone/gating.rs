//! Waiting at the plan's gates: which of the route's events the commanded motion
//! has passed, and the waits behind late predecessors the flight log reports.

/// One drone's record at the TPG gates of its route.
#[derive(Debug, Default)]
pub(super) struct Gating {
    /// Events already behind the commanded position (see `gate::closed_gate`).
    pub(super) passed_events: usize,
    /// Times it stopped (or could not start) because a TPG predecessor was late.
    pub(super) waits: usize,
    /// Seconds it spent waiting at closed gates.
    pub(super) wait_s: f64,
    /// Seconds of the wait under way (0 when not waiting).
    pub(super) current_s: f64,
    /// Its longest single wait, seconds.
    pub(super) longest_s: f64,
    /// The drone (plan order) it waits for at a closed gate.
    pub(super) waiting_for: Option<u32>,
}

impl Gating {
    /// Counts one tick of `dt_s`: held at a gate that `blocker` keeps closed (a new
    /// wait unless it `was_gated` the tick before), or not waiting for anyone.
    pub(super) fn count(&mut self, gated: bool, was_gated: bool, blocker: Option<u32>, dt_s: f64) {
        if gated {
            if !was_gated {
                self.waits += 1;
                self.current_s = 0.0;
            }
            self.wait_s += dt_s;
            self.current_s += dt_s;
            self.longest_s = self.longest_s.max(self.current_s);
            self.waiting_for = blocker;
        } else {
            self.current_s = 0.0;
            self.waiting_for = None;
        }
    }

    /// A replan's new route: all of its gates lie ahead. The waits so far stay
    /// counted.
    pub(super) fn restart(&mut self) {
        self.passed_events = 0;
        self.waiting_for = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wait_is_counted_once_however_many_ticks_it_lasts() {
        let mut g = Gating::default();
        g.count(true, false, Some(3), 0.05);
        g.count(true, true, Some(3), 0.05);
        assert_eq!((g.waits, g.waiting_for), (1, Some(3)));
        assert!((g.wait_s - 0.1).abs() < 1e-12);
        g.count(false, true, Some(3), 0.05);
        assert_eq!(g.waiting_for, None);
        g.count(true, false, None, 0.05);
        assert_eq!(g.waits, 2);
        assert!(
            (g.longest_s - 0.1).abs() < 1e-12,
            "the first wait, not the sum"
        );
        g.passed_events = 4;
        g.restart();
        assert_eq!((g.passed_events, g.waits), (0, 2));
    }
}
