//! The streaming flight recorder: telemetry in, Rerun out, on its own OS thread.
//!
//! Flying must never wait for logging. The executor hands samples over with
//! [`RecorderHandle::try_sample`], which never blocks: it appends to a bounded
//! buffer under a lock it only *tries* to take, and when the buffer is full (or,
//! rarely, the recorder is swapping it out at that instant) the sample is dropped
//! and counted. Appending to a plain buffer costs the sender less than a channel
//! slot per sample. Events and control messages go through a bounded channel,
//! also with `try_send`. The recorder thread does not wake per sample: it sleeps
//! for `poll_period_s`, then takes the whole buffer at once (every wake-up has a
//! price, high in a virtual machine, so it wakes rarely).
//!
//! What it logs is built to cost little next to the flight itself:
//!
//! - positions as rows on a `row_period_s` grid, each row holding every drone's
//!   newest position (one entity for all drones);
//! - the separation spheres or ellipsoids, speeds (one series per drone, also
//!   one entity each) and the swarm's minimum separation (and scaled separation,
//!   under an ellipsoid) on a coarser `series_period_s` grid;
//! - everything buffered and sent as columns every `flush_period_s`: a handful of
//!   chunks per flush, whatever the number of drones;
//! - the flown paths once, at the end; events as they come.
//!
//! Here: [`Recorder`], which starts and stops the thread. The sending side is
//! `handle` (through `samples`, the buffer, and `control`, the channel's
//! messages); the thread is `worker`, which places samples with `rows` and
//! reports [`RecorderStats`].

mod control;
mod handle;
mod options;
mod rows;
mod samples;
mod stats;
mod worker;

pub use handle::RecorderHandle;
pub use options::RecorderOptions;
pub use samples::FlightSample;
pub use stats::RecorderStats;

use crate::{Scene, TimeAxis, VizError, swarm};
use control::{CONTROL_CAPACITY, Message};
use samples::{CloseOnDrop, Samples};
use std::sync::Arc;
use std::sync::atomic::AtomicU64;
use std::sync::mpsc::sync_channel;
use std::thread::JoinHandle;
use worker::Worker;

/// Name of the recorder thread, as `/proc/self/task/*/comm` shows it, so a
/// benchmark can find it and read its CPU time. Rerun's own threads do the
/// encoding and writing; `comm` shows their names cut to 15 bytes:
/// `RecordingStream` (`RecordingStream::batcher_to_sink`), `ChunkBatcher::c`
/// (`ChunkBatcher::cmds_to_chunks`), `file_writer` and, streaming to a viewer,
/// `message_proxy_c` (`message_proxy_client`).
pub const RECORDER_THREAD: &str = "rerun-recorder";

/// Owns the recorder thread; [`Recorder::finish`] flushes and joins it (so does
/// dropping it, minus the report).
pub struct Recorder {
    handle: RecorderHandle,
    thread: Option<JoinHandle<Result<RecorderStats, VizError>>>,
}

impl Recorder {
    /// Opens the recording, logs `scene` (world, and the plan on each of
    /// `plan_axes`; drones without a trajectory show only their markers), the
    /// flight's static styling, and starts the recorder thread. Samples name
    /// drones by their index in `scene.drones`.
    pub fn start(
        sink: &crate::Sink,
        scene: &Scene,
        plan_axes: &[TimeAxis],
        options: RecorderOptions,
    ) -> Result<Self, VizError> {
        let rec = crate::sink::open(scene, sink, crate::FLIGHT_TIMELINE)?;
        let plan = crate::plan::log_scene(&rec, scene, plan_axes)?;
        let members: Vec<usize> = (0..scene.drones.len()).collect();
        swarm::log_styles(&rec, scene, "flight", &members)?;
        swarm::log_series_styles(&rec, scene, "flight")?;
        let (tx, rx) = sync_channel(CONTROL_CAPACITY);
        let samples = Arc::new(Samples::new(options.capacity));
        let dropped = Arc::new(AtomicU64::new(0));
        let worker = Worker::new(rec, scene, plan, options, Arc::clone(&dropped));
        let queue = CloseOnDrop(Arc::clone(&samples));
        let thread = std::thread::Builder::new()
            .name(RECORDER_THREAD.into())
            .spawn(move || worker.run(rx, queue))
            .map_err(|_| VizError::RecorderGone)?;
        let handle = RecorderHandle::new(tx, samples, dropped, thread.thread().clone());
        Ok(Self {
            handle,
            thread: Some(thread),
        })
    }

    /// A sending side to give to the executor.
    pub fn handle(&self) -> RecorderHandle {
        self.handle.clone()
    }

    /// Waits for everything queued so far to be logged, flushes the stream and
    /// stops the thread. Clones of the handle may outlive it: what they send
    /// afterwards is dropped and counted.
    pub fn finish(mut self) -> Result<RecorderStats, VizError> {
        let mut stats = self.stop()?;
        let (samples_dropped, events_dropped) = self.handle.dropped_counts();
        stats.samples_dropped += samples_dropped;
        stats.events_dropped += events_dropped;
        Ok(stats)
    }

    fn stop(&mut self) -> Result<RecorderStats, VizError> {
        let thread = self.thread.take().ok_or(VizError::RecorderGone)?;
        // Fails only if the thread already stopped (on an error it will report).
        let _ = self.handle.send_blocking(Message::Finish);
        // Cut its sleep short.
        thread.thread().unpark();
        thread.join().map_err(|_| VizError::RecorderGone)?
    }
}

impl Drop for Recorder {
    fn drop(&mut self) {
        if self.thread.is_some() {
            let _ = self.stop();
        }
    }
}
