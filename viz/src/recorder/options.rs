//! Tuning for the recorder thread: how often it wakes, flushes and samples rows.

use crate::Sink;

/// Tuning for the recorder thread.
#[derive(Debug, Clone, PartialEq)]
pub struct RecorderOptions {
    /// Samples waiting for the recorder (between its wake-ups) beyond which
    /// new ones are dropped.
    pub capacity: usize,
    /// How long the recorder thread sleeps between draining the channel,
    /// wall-clock seconds. The channel must hold this long's worth of samples;
    /// finishing does not wait for it.
    pub poll_period_s: f64,
    /// How often buffered rows are sent to the stream, wall-clock seconds: a viewer
    /// lags the flight by up to this much. Each flush sends four chunks, and every
    /// chunk costs a fixed amount to encode and write (most of the recording's
    /// cost in rerun's threads), so [`RecorderOptions::for_sink`] flushes files
    /// less often than viewers.
    pub flush_period_s: f64,
    /// Spacing of position rows, flight seconds (each row holds every drone).
    pub row_period_s: f64,
    /// Spacing of the safety spheres, speeds and minimum separation, flight
    /// seconds (rounded to a whole number of rows).
    pub series_period_s: f64,
    /// A flown position is added to the drawn path only after moving this far, metres.
    pub path_step_m: f64,
    /// Rows wait at most this long (flight seconds) for every drone's first sample;
    /// until then a silent drone is shown at its start.
    pub first_row_wait_s: f64,
}

impl Default for RecorderOptions {
    fn default() -> Self {
        Self {
            capacity: 8192,
            poll_period_s: 0.5,
            flush_period_s: 2.0,
            row_period_s: 0.05,
            series_period_s: 0.1,
            path_step_m: 0.05,
            first_row_wait_s: 1.0,
        }
    }
}

impl RecorderOptions {
    /// The defaults, flushing every second for a viewer watching live and every
    /// 5 s for a file, which nobody reads before the flight ends.
    pub fn for_sink(sink: &Sink) -> Self {
        let flush_period_s = match sink {
            Sink::File(_) => 5.0,
            Sink::Spawn | Sink::Connect(_) => 1.0,
        };
        Self {
            flush_period_s,
            ..Self::default()
        }
    }
}
