//! What the recorder did, reported when it finishes.

/// What the recorder did, reported when it finishes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RecorderStats {
    /// Samples the recorder thread logged.
    pub samples_logged: u64,
    /// Samples dropped: the buffer was full (or being swapped out at that
    /// instant), the recorder had stopped, or the sample named an unknown drone
    /// or had no finite time.
    pub samples_dropped: u64,
    /// Events dropped because the channel was full.
    pub events_dropped: u64,
    /// Position rows logged (each holds every drone).
    pub rows_logged: u64,
    /// Wall time the recorder thread ran, seconds.
    pub thread_wall_s: f64,
}
