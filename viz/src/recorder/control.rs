//! What goes through the recorder's control channel: rarely, events, the
//! plan's start, the lateness known once a flight is over, and the end. Samples take the cheaper buffer in `samples`.

/// Control messages queued at most (events are rare).
pub(super) const CONTROL_CAPACITY: usize = 1024;

/// One control message, from a handle to the recorder thread.
pub(super) enum Message {
    /// A text event to log at its flight time.
    Event(Box<Event>),
    /// Plan execution began at this flight time: log the plan on the flight timeline.
    PlanStart(f64),
    /// One drone's lateness: `(flight time, seconds late)` at each event it reached.
    Lateness(Box<(String, Vec<(f64, f64)>)>),
    /// Log what is queued before this, flush and stop (handles may still exist).
    Finish,
}

/// A text event as sent: boxed in [`Message`] so the channel's slots stay small.
pub(super) struct Event {
    /// Flight time of the event, seconds.
    pub(super) t_s: f64,
    /// The drone it concerns, if any (its id, shown before the text).
    pub(super) drone: Option<String>,
    /// What happened.
    pub(super) text: String,
}
