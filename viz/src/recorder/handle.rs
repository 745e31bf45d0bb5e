//! The sending side: what the executor's tasks hold to hand samples, events
//! and the plan's start to the recorder thread without waiting for it.

use super::control::{Event, Message};
use super::samples::{Compact, FlightSample, Samples};
use crate::VizError;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{SyncSender, TrySendError};
use std::time::Duration;

/// A cheap, cloneable sending side for the executor's tasks.
#[derive(Clone)]
pub struct RecorderHandle {
    tx: SyncSender<Message>,
    samples: Arc<Samples>,
    /// Samples dropped on the sending side (shared with the recorder thread,
    /// which adds the ones it cannot place).
    dropped: Arc<AtomicU64>,
    events_dropped: Arc<AtomicU64>,
    /// The recorder thread, to wake it when a blocking send finds the channel full.
    thread: std::thread::Thread,
}

impl RecorderHandle {
    /// A handle on the recorder `thread`, sending control messages on `tx` and
    /// samples into `samples`, counting dropped samples in `dropped`.
    pub(super) fn new(
        tx: SyncSender<Message>,
        samples: Arc<Samples>,
        dropped: Arc<AtomicU64>,
        thread: std::thread::Thread,
    ) -> Self {
        Self {
            tx,
            samples,
            dropped,
            events_dropped: Arc::new(AtomicU64::new(0)),
            thread,
        }
    }

    /// Samples and events dropped so far, in that order.
    pub(super) fn dropped_counts(&self) -> (u64, u64) {
        (
            self.dropped.load(Ordering::Relaxed),
            self.events_dropped.load(Ordering::Relaxed),
        )
    }

    /// Queues a sample without blocking; returns false (and counts it) if dropped.
    pub fn try_sample(&self, sample: FlightSample) -> bool {
        let queued = self.samples.try_push(sample.into());
        if !queued {
            self.dropped.fetch_add(1, Ordering::Relaxed);
        }
        queued
    }

    /// Queues a sample, waiting for room: for replays, where nothing is flying.
    pub fn sample_blocking(&self, sample: FlightSample) -> Result<(), VizError> {
        let compact = Compact::from(sample);
        while !self.samples.push_if_room(compact)? {
            self.thread.unpark();
            std::thread::sleep(Duration::from_millis(1));
        }
        Ok(())
    }

    /// Sends, waking the recorder first if the channel is full.
    pub(super) fn send_blocking(&self, message: Message) -> Result<(), VizError> {
        match self.tx.try_send(message) {
            Ok(()) => Ok(()),
            Err(TrySendError::Full(message)) => {
                self.thread.unpark();
                self.tx.send(message).map_err(|_| VizError::RecorderGone)
            }
            Err(TrySendError::Disconnected(_)) => Err(VizError::RecorderGone),
        }
    }

    /// Queues a text event without blocking; returns false (and counts it) if dropped.
    pub fn try_event(&self, t_s: f64, drone: Option<&str>, text: &str) -> bool {
        let sent = self.tx.try_send(event(t_s, drone, text)).is_ok();
        if !sent {
            self.events_dropped.fetch_add(1, Ordering::Relaxed);
        }
        sent
    }

    /// Queues a text event, waiting for room.
    pub fn event_blocking(
        &self,
        t_s: f64,
        drone: Option<&str>,
        text: &str,
    ) -> Result<(), VizError> {
        self.send_blocking(event(t_s, drone, text))
    }

    /// Plan execution began `t_s` seconds into the flight: the plan is logged on
    /// the flight timeline from there, beside the flown drones. Never blocks;
    /// returns false if the channel was full (the caller may retry later).
    pub fn try_plan_start(&self, t_s: f64) -> bool {
        self.tx.try_send(Message::PlanStart(t_s)).is_ok()
    }

    /// [`Self::try_plan_start`], waiting for room: once nothing is flying.
    pub fn plan_start_blocking(&self, t_s: f64) -> Result<(), VizError> {
        self.send_blocking(Message::PlanStart(t_s))
    }

    /// Drone `drone`'s lateness against the schedule, `(flight time, seconds
    /// late)` at each event it reached, as one series; waits for room (the flight
    /// log has it only once the flight is over).
    pub fn lateness_blocking(&self, drone: &str, series: Vec<(f64, f64)>) -> Result<(), VizError> {
        self.send_blocking(Message::Lateness(Box::new((drone.to_string(), series))))
    }
}

/// The control message for a text event.
fn event(t_s: f64, drone: Option<&str>, text: &str) -> Message {
    Message::Event(Box::new(Event {
        t_s,
        drone: drone.map(str::to_string),
        text: text.to_string(),
    }))
}
