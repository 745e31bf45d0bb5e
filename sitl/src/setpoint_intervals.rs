//! How regularly a vehicle's setpoints arrive: the gaps its offboard
//! watchdog would see, as a bounded histogram.

use tokio::time::Instant;

/// Width of one [`SetpointIntervals`] bucket, seconds.
const INTERVAL_BUCKET_S: f64 = 0.001;
/// Number of [`SetpointIntervals`] buckets (1 ms each, so up to one second).
const INTERVAL_BUCKETS: usize = 1000;

/// Wall-clock time between consecutive setpoints (SET_POSITION_TARGET_LOCAL_NED
/// or _GLOBAL_INT) as a vehicle received them, after fault injection: what a real
/// autopilot's offboard watchdog would see. A 1 ms histogram up to one second
/// (longer gaps are counted above it) and the exact largest gap, so memory stays
/// bounded however long the vehicle runs.
#[derive(Debug, Clone, PartialEq)]
pub struct SetpointIntervals {
    buckets: Vec<u32>,
    above: u64,
    count: u64,
    max_s: f64,
    last: Option<Instant>,
}

impl Default for SetpointIntervals {
    fn default() -> Self {
        Self {
            buckets: vec![0; INTERVAL_BUCKETS],
            above: 0,
            count: 0,
            max_s: 0.0,
            last: None,
        }
    }
}

impl SetpointIntervals {
    /// Records one interval of `interval_s` seconds.
    pub fn record(&mut self, interval_s: f64) {
        let interval_s = interval_s.max(0.0);
        let bucket = (interval_s / INTERVAL_BUCKET_S) as usize;
        match self.buckets.get_mut(bucket) {
            Some(n) => *n = n.saturating_add(1),
            None => self.above += 1,
        }
        self.count += 1;
        self.max_s = self.max_s.max(interval_s);
    }

    /// A copy for callers: the histogram alone, without the time of the last
    /// arrival (an `Instant` means nothing outside this process's run).
    pub(crate) fn histogram(&self) -> Self {
        Self {
            last: None,
            ..self.clone()
        }
    }

    /// Notes a setpoint's arrival at `now`, recording the gap since the previous one.
    pub(crate) fn arrived(&mut self, now: Instant) {
        if let Some(last) = self.last.replace(now) {
            self.record(now.saturating_duration_since(last).as_secs_f64());
        }
    }

    /// Adds another vehicle's intervals (for swarm-wide quantiles).
    pub fn merge(&mut self, other: &SetpointIntervals) {
        for (a, b) in self.buckets.iter_mut().zip(&other.buckets) {
            *a = a.saturating_add(*b);
        }
        self.above += other.above;
        self.count += other.count;
        self.max_s = self.max_s.max(other.max_s);
    }

    /// Intervals recorded (one fewer than the setpoints received).
    pub fn count(&self) -> u64 {
        self.count
    }

    /// The largest interval, seconds (0 if none).
    pub fn max_s(&self) -> f64 {
        self.max_s
    }

    /// Intervals longer than `threshold_s` seconds, to bucket resolution (1 ms).
    pub fn count_above(&self, threshold_s: f64) -> u64 {
        let first = ((threshold_s / INTERVAL_BUCKET_S).ceil().max(0.0)) as usize;
        let within: u64 = self.buckets.iter().skip(first).map(|&n| u64::from(n)).sum();
        within + self.above
    }

    /// Nearest-rank quantile `q` in [0, 1], seconds: the upper edge of its 1 ms
    /// bucket (at most 1 ms above the true value, never below it, never above the
    /// maximum); the exact maximum for intervals beyond the histogram; 0 if none.
    pub fn quantile_s(&self, q: f64) -> f64 {
        if self.count == 0 {
            return 0.0;
        }
        let rank = ((q.clamp(0.0, 1.0) * self.count as f64).ceil() as u64).clamp(1, self.count);
        let mut seen = 0;
        for (i, &n) in self.buckets.iter().enumerate() {
            seen += u64::from(n);
            if seen >= rank {
                return ((i + 1) as f64 * INTERVAL_BUCKET_S).min(self.max_s);
            }
        }
        self.max_s
    }
}

#[cfg(test)]
mod tests {
    use super::SetpointIntervals;

    #[test]
    fn setpoint_interval_quantiles_round_up_to_the_millisecond() {
        let mut h = SetpointIntervals::default();
        assert_eq!(h.quantile_s(0.99), 0.0);
        for _ in 0..98 {
            h.record(0.0502);
        }
        h.record(0.0701);
        h.record(2.5);
        assert_eq!(h.count(), 100);
        assert!((h.quantile_s(0.5) - 0.051).abs() < 1e-9);
        assert!((h.quantile_s(0.99) - 0.071).abs() < 1e-9);
        assert_eq!(h.quantile_s(1.0), 2.5);
        assert_eq!(h.max_s(), 2.5);
        assert_eq!(h.count_above(0.06), 2);
        let mut merged = SetpointIntervals::default();
        merged.merge(&h);
        merged.merge(&h);
        assert_eq!(merged.count(), 200);
        assert!((merged.quantile_s(0.5) - 0.051).abs() < 1e-9);
    }
}
