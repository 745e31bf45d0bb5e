//! The sample buffer between the executor and the recorder thread: senders
//! append under a lock they only try to take, the recorder swaps the whole
//! buffer out at each wake-up.

use crate::VizError;
use crate::style::f32x3;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// One telemetry sample: drone index into the scene's drones, time since the
/// first arm command, ENU position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightSample {
    /// Index of the drone in the scene's drones, the scene the recorder was started with.
    pub drone: usize,
    /// Flight time of the sample: seconds since the first arm command.
    pub t_s: f64,
    /// Position, mission ENU metres.
    pub position_m: [f64; 3],
}

/// A sample as queued: 24 bytes, positions in `f32` (what the recording stores
/// anyway), so the buffer the executor writes stays small and in cache.
#[derive(Clone, Copy)]
pub(super) struct Compact {
    drone: u32,
    position_m: [f32; 3],
    t_s: f64,
}

impl From<FlightSample> for Compact {
    fn from(s: FlightSample) -> Self {
        Self {
            // An index past u32 is as unknown as any other: dropped and counted there.
            drone: u32::try_from(s.drone).unwrap_or(u32::MAX),
            position_m: f32x3(s.position_m),
            t_s: s.t_s,
        }
    }
}

impl From<Compact> for FlightSample {
    fn from(c: Compact) -> Self {
        Self {
            drone: usize::try_from(c.drone).unwrap_or(usize::MAX),
            t_s: c.t_s,
            position_m: c.position_m.map(f64::from),
        }
    }
}

/// Samples waiting for the recorder thread, which swaps the whole buffer out.
pub(super) struct Samples {
    queue: Mutex<Vec<Compact>>,
    capacity: usize,
    /// Set once the recorder thread has stopped: later samples are dropped.
    closed: AtomicBool,
}

impl Samples {
    /// An open, empty buffer holding at most `capacity` samples (at least one).
    pub(super) fn new(capacity: usize) -> Self {
        let capacity = capacity.max(1);
        Self {
            queue: Mutex::new(Vec::with_capacity(capacity)),
            capacity,
            closed: AtomicBool::new(false),
        }
    }

    /// Appends without blocking: false if the buffer is closed, full or being
    /// swapped out at this instant.
    pub(super) fn try_push(&self, sample: Compact) -> bool {
        !self.closed.load(Ordering::Relaxed)
            && self.queue.try_lock().is_ok_and(|mut queue| {
                let room = queue.len() < self.capacity;
                if room {
                    queue.push(sample);
                }
                room
            })
    }

    /// Appends, waiting for the lock: `Ok(false)` if the buffer is full (the
    /// caller wakes the recorder and retries), an error once it is closed.
    pub(super) fn push_if_room(&self, sample: Compact) -> Result<bool, VizError> {
        if self.closed.load(Ordering::Acquire) {
            return Err(VizError::RecorderGone);
        }
        let mut queue = self.queue.lock().map_err(|_| VizError::RecorderGone)?;
        if queue.len() < self.capacity {
            queue.push(sample);
            return Ok(true);
        }
        Ok(false)
    }

    /// Swaps the buffered samples into `taken` (which should be empty), leaving
    /// its allocation for the senders.
    pub(super) fn swap_out(&self, taken: &mut Vec<Compact>) {
        // A poisoned lock only means a sender panicked mid-push: the data is fine.
        let mut queue = self.queue.lock().unwrap_or_else(|e| e.into_inner());
        std::mem::swap(&mut *queue, taken);
    }
}

/// Marks the samples closed when the recorder thread ends, however it ends.
pub(super) struct CloseOnDrop(pub(super) Arc<Samples>);

impl Drop for CloseOnDrop {
    fn drop(&mut self) {
        self.0.closed.store(true, Ordering::Release);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queued_samples_stay_small() {
        assert_eq!(std::mem::size_of::<Compact>(), 24);
    }
}
