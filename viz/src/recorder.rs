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
//! - the safety spheres, speeds (one series per drone, also one entity each) and
//!   the swarm's minimum separation on a coarser `series_period_s` grid;
//! - everything buffered and sent as columns every `flush_period_s`: a handful of
//!   chunks per flush, whatever the number of drones;
//! - the flown paths once, at the end; events as they come.
//!
//! Events are the only thing logged with the stream's current time, which is
//! per thread: it is set and used on the recorder thread with nothing in between.

use crate::plan::{PlanRows, log_err};
use crate::style::f32x3;
use crate::{Scene, TimeAxis, VizError, metrics, paths, swarm};
use rerun::RecordingStream;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, SyncSender, TryRecvError, TrySendError, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// One telemetry sample: drone index into the scene's drones, time since the
/// first arm command, ENU position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlightSample {
    pub drone: usize,
    pub t_s: f64,
    pub position_m: [f64; 3],
}

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
    pub fn for_sink(sink: &crate::Sink) -> Self {
        let flush_period_s = match sink {
            crate::Sink::File(_) => 5.0,
            crate::Sink::Spawn | crate::Sink::Connect(_) => 1.0,
        };
        Self {
            flush_period_s,
            ..Self::default()
        }
    }
}

/// What the recorder did, reported when it finishes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RecorderStats {
    /// Samples the recorder thread logged.
    pub samples_logged: u64,
    /// Samples dropped because the channel was full (or named an unknown drone).
    pub samples_dropped: u64,
    /// Events dropped because the channel was full.
    pub events_dropped: u64,
    /// Position rows logged (each holds every drone).
    pub rows_logged: u64,
    /// CPU time of the recorder thread itself (not rerun's own writer threads).
    pub thread_cpu_s: f64,
    /// Wall time the recorder thread ran.
    pub thread_wall_s: f64,
}

/// What goes through the control channel (rarely: events, the plan's start, the end).
enum Message {
    Event(Box<Event>),
    /// Plan execution began at this flight time: log the plan on the flight timeline.
    PlanStart(f64),
    /// Log what is queued before this, flush and stop (handles may still exist).
    Finish,
}

/// A sample as queued: 24 bytes, positions in `f32` (what the recording stores
/// anyway), so the buffer the executor writes stays small and in cache.
#[derive(Clone, Copy)]
struct Compact {
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
struct Samples {
    queue: Mutex<Vec<Compact>>,
    capacity: usize,
    /// Set once the recorder thread has stopped: later samples are dropped.
    closed: AtomicBool,
}

/// Marks the samples closed when the recorder thread ends, however it ends.
struct CloseOnDrop(Arc<Samples>);

impl Drop for CloseOnDrop {
    fn drop(&mut self) {
        self.0.closed.store(true, Ordering::Release);
    }
}

/// Control messages queued at most (events are rare).
const CONTROL_CAPACITY: usize = 1024;

struct Event {
    t_s: f64,
    drone: Option<String>,
    text: String,
}

/// A cheap, cloneable sending side for the executor's tasks.
#[derive(Clone)]
pub struct RecorderHandle {
    tx: SyncSender<Message>,
    samples: Arc<Samples>,
    dropped: Arc<AtomicU64>,
    events_dropped: Arc<AtomicU64>,
    /// The recorder thread, to wake it when a blocking send finds the channel full.
    thread: std::thread::Thread,
}

/// Owns the recorder thread; [`Recorder::finish`] flushes and joins it (so does
/// dropping it, minus the report).
pub struct Recorder {
    handle: RecorderHandle,
    thread: Option<JoinHandle<Result<RecorderStats, VizError>>>,
}

impl RecorderHandle {
    /// Queues a sample without blocking; returns false (and counts it) if dropped.
    pub fn try_sample(&self, sample: FlightSample) -> bool {
        let samples = &*self.samples;
        let queued = !samples.closed.load(Ordering::Relaxed)
            && samples.queue.try_lock().is_ok_and(|mut queue| {
                let room = queue.len() < samples.capacity;
                if room {
                    queue.push(sample.into());
                }
                room
            });
        if !queued {
            self.dropped.fetch_add(1, Ordering::Relaxed);
        }
        queued
    }

    /// Queues a sample, waiting for room: for replays, where nothing is flying.
    pub fn sample_blocking(&self, sample: FlightSample) -> Result<(), VizError> {
        let compact = Compact::from(sample);
        loop {
            if self.samples.closed.load(Ordering::Acquire) {
                return Err(VizError::RecorderGone);
            }
            {
                let mut queue = self
                    .samples
                    .queue
                    .lock()
                    .map_err(|_| VizError::RecorderGone)?;
                if queue.len() < self.samples.capacity {
                    queue.push(compact);
                    return Ok(());
                }
            }
            self.thread.unpark();
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// Sends, waking the recorder first if the channel is full.
    fn send_blocking(&self, message: Message) -> Result<(), VizError> {
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
        let message = Message::Event(Box::new(Event {
            t_s,
            drone: drone.map(str::to_string),
            text: text.to_string(),
        }));
        let sent = self.tx.try_send(message).is_ok();
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
        let message = Message::Event(Box::new(Event {
            t_s,
            drone: drone.map(str::to_string),
            text: text.to_string(),
        }));
        self.send_blocking(message)
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
        let rec = crate::sink::open(&scene.name, sink, crate::FLIGHT_TIMELINE)?;
        let plan = crate::plan::log_scene(&rec, scene, plan_axes)?;
        let members: Vec<usize> = (0..scene.drones.len()).collect();
        swarm::log_styles(&rec, scene, "flight", &members)?;
        swarm::log_series_styles(&rec, "flight")?;
        let (tx, rx) = sync_channel(CONTROL_CAPACITY);
        let capacity = options.capacity.max(1);
        let samples = Arc::new(Samples {
            queue: Mutex::new(Vec::with_capacity(capacity)),
            capacity,
            closed: AtomicBool::new(false),
        });
        let dropped = Arc::new(AtomicU64::new(0));
        let events_dropped = Arc::new(AtomicU64::new(0));
        let worker = Worker::new(rec, scene, plan, options, Arc::clone(&dropped));
        let queue = CloseOnDrop(Arc::clone(&samples));
        let thread = std::thread::Builder::new()
            .name("rerun-recorder".into())
            .spawn(move || worker.run(rx, queue))
            .map_err(|_| VizError::RecorderGone)?;
        let handle = RecorderHandle {
            tx,
            samples,
            dropped,
            events_dropped,
            thread: thread.thread().clone(),
        };
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
        stats.samples_dropped += self.handle.dropped.load(Ordering::Relaxed);
        stats.events_dropped += self.handle.events_dropped.load(Ordering::Relaxed);
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

/// Per-drone state on the recorder thread.
#[derive(Default)]
struct Track {
    /// Newest sample `(t_s, position)`.
    latest: Option<(f64, [f64; 3])>,
    /// The sample the last speed was measured from.
    anchor: Option<(f64, [f64; 3])>,
    speed_mps: f64,
    path: Vec<[f32; 3]>,
}

struct Worker {
    rec: RecordingStream,
    axis: TimeAxis,
    options: RecorderOptions,
    scene: Scene,
    plan: PlanRows,
    plan_logged_on_flight: bool,
    tracks: Vec<Track>,
    /// Drones that have reported at least once.
    reporting: usize,
    /// Index of the next row to close (its time is `index × row_period_s`), once
    /// the first sample has arrived.
    next_row: Option<u64>,
    first_t_s: Option<f64>,
    last_t_s: f64,
    rows_since_series: usize,
    rows_per_series: usize,
    row_times_s: Vec<f64>,
    row_positions: Vec<[f32; 3]>,
    series_times_s: Vec<f64>,
    /// Safety-sphere centres at the series times: every drone per row.
    series_positions: Vec<[f32; 3]>,
    series_speeds: Vec<f64>,
    separation: Vec<(f64, f64)>,
    pairwise: metrics::Pairwise,
    dropped: Arc<AtomicU64>,
    logged: u64,
    rows_logged: u64,
}

impl Worker {
    fn new(
        rec: RecordingStream,
        scene: &Scene,
        plan: PlanRows,
        options: RecorderOptions,
        dropped: Arc<AtomicU64>,
    ) -> Self {
        let row_period_s = options.row_period_s.max(1e-3);
        Self {
            rec,
            axis: TimeAxis {
                timeline: crate::FLIGHT_TIMELINE,
                offset_s: 0.0,
            },
            rows_per_series: ((options.series_period_s / row_period_s).round() as usize).max(1),
            options: RecorderOptions {
                row_period_s,
                ..options
            },
            scene: scene.clone(),
            plan,
            plan_logged_on_flight: false,
            tracks: scene.drones.iter().map(|_| Track::default()).collect(),
            reporting: 0,
            next_row: None,
            first_t_s: None,
            last_t_s: 0.0,
            rows_since_series: 0,
            row_times_s: Vec::new(),
            row_positions: Vec::new(),
            series_times_s: Vec::new(),
            series_positions: Vec::new(),
            series_speeds: Vec::new(),
            separation: Vec::new(),
            pairwise: metrics::Pairwise::default(),
            dropped,
            logged: 0,
            rows_logged: 0,
        }
    }

    fn run(
        mut self,
        rx: Receiver<Message>,
        samples: CloseOnDrop,
    ) -> Result<RecorderStats, VizError> {
        let started = Instant::now();
        let poll = Duration::from_secs_f64(self.options.poll_period_s.clamp(0.001, 5.0));
        let flush_period = Duration::from_secs_f64(self.options.flush_period_s.max(0.001));
        // Took this many at once: the buffer was filling, so look again at once.
        let busy = (self.options.capacity / 4).max(1);
        let mut next_flush = Instant::now() + flush_period;
        let mut open = true;
        let mut taken: Vec<Compact> = Vec::with_capacity(self.options.capacity.max(1));
        while open {
            // Control first: once `Finish` is seen, every sample queued before it is
            // in the buffer taken below.
            loop {
                match rx.try_recv() {
                    Ok(Message::Finish) | Err(TryRecvError::Disconnected) => {
                        open = false;
                        break;
                    }
                    Ok(message) => self.handle(message)?,
                    Err(TryRecvError::Empty) => break,
                }
            }
            {
                // A poisoned lock only means a sender panicked mid-push: the data is fine.
                let mut queue = samples.0.queue.lock().unwrap_or_else(|e| e.into_inner());
                std::mem::swap(&mut *queue, &mut taken);
            }
            let drained = taken.len();
            for compact in taken.drain(..) {
                self.sample(compact.into());
            }
            if Instant::now() >= next_flush {
                self.flush()?;
                next_flush = Instant::now() + flush_period;
            }
            if open && drained < busy {
                // Woken early only by `Recorder::stop` (or spuriously: harmless).
                std::thread::park_timeout(
                    poll.min(next_flush.saturating_duration_since(Instant::now())),
                );
            }
        }
        self.close_rows(f64::INFINITY);
        self.flush()?;
        self.finish_static()?;
        self.rec
            .flush_blocking()
            .map_err(|e| VizError::Flush(e.to_string()))?;
        Ok(RecorderStats {
            samples_logged: self.logged,
            samples_dropped: 0,
            events_dropped: 0,
            rows_logged: self.rows_logged,
            thread_cpu_s: thread_cpu_s(),
            thread_wall_s: started.elapsed().as_secs_f64(),
        })
    }

    fn handle(&mut self, message: Message) -> Result<(), VizError> {
        match message {
            Message::Event(e) => self.event(e.t_s, e.drone.as_deref(), &e.text),
            Message::PlanStart(t_s) => self.plan_start(t_s),
            Message::Finish => Ok(()),
        }
    }

    fn sample(&mut self, s: FlightSample) {
        if s.drone >= self.tracks.len() || !s.t_s.is_finite() {
            self.dropped.fetch_add(1, Ordering::Relaxed);
            return;
        }
        // Rows up to this sample's time are complete: telemetry arrives in time order
        // up to the executor's tick, which is shorter than a row.
        if self.next_row.is_none() {
            self.next_row = Some((s.t_s / self.options.row_period_s).ceil().max(0.0) as u64);
            self.first_t_s = Some(s.t_s);
        }
        self.close_rows(s.t_s);
        let step_m = self.options.path_step_m;
        let track = &mut self.tracks[s.drone];
        if track.latest.is_none() {
            self.reporting += 1;
            track.anchor = Some((s.t_s, s.position_m));
        }
        track.latest = Some((s.t_s, s.position_m));
        let p = f32x3(s.position_m);
        let moved = track.path.last().is_none_or(|q| {
            let d2: f32 = (0..3).map(|i| (p[i] - q[i]).powi(2)).sum();
            f64::from(d2.sqrt()) >= step_m
        });
        if moved {
            track.path.push(p);
        }
        self.logged += 1;
        self.last_t_s = self.last_t_s.max(s.t_s);
    }

    /// Closes every row whose time is before `t_s` (all of them for infinity).
    fn close_rows(&mut self, t_s: f64) {
        let (Some(first_t_s), Some(mut next)) = (self.first_t_s, self.next_row) else {
            return;
        };
        let period = self.options.row_period_s;
        // At the end, one more row so that the last samples are shown.
        let end = if t_s.is_finite() {
            t_s
        } else {
            self.last_t_s + period
        };
        // Until every drone has reported (or a while has passed), hold rows back.
        let waiting = self.reporting < self.tracks.len()
            && t_s.is_finite()
            && t_s - first_t_s < self.options.first_row_wait_s;
        if waiting {
            return;
        }
        while (next as f64) * period < end {
            self.close_row(next as f64 * period);
            next += 1;
        }
        self.next_row = Some(next);
    }

    fn close_row(&mut self, t_s: f64) {
        self.row_times_s.push(t_s);
        self.rows_logged += 1;
        let row_start = self.row_positions.len();
        for (track, drone) in self.tracks.iter().zip(&self.scene.drones) {
            let p = track.latest.map_or(drone.start_m, |(_, p)| p);
            self.row_positions.push(f32x3(p));
        }
        self.rows_since_series += 1;
        if self.rows_since_series < self.rows_per_series {
            return;
        }
        self.rows_since_series = 0;
        self.series_times_s.push(t_s);
        self.series_positions
            .extend_from_slice(&self.row_positions[row_start..]);
        for track in &mut self.tracks {
            if let (Some((t1, p1)), Some((t0, p0))) = (track.latest, track.anchor)
                && t1 > t0
            {
                let d2: f64 = (0..3).map(|i| (p1[i] - p0[i]).powi(2)).sum();
                track.speed_mps = d2.sqrt() / (t1 - t0);
                track.anchor = track.latest;
            }
            self.series_speeds.push(track.speed_mps);
        }
        let reported = self.tracks.iter().filter_map(|t| t.latest.map(|(_, p)| p));
        if let Some(d) = self.pairwise.min_m(reported) {
            self.separation.push((t_s, d));
        }
    }

    fn event(&mut self, t_s: f64, drone: Option<&str>, text: &str) -> Result<(), VizError> {
        let entity = paths::events("flight");
        let line = drone.map_or(text.to_string(), |d| format!("{d}: {text}"));
        // Set the time and log on this thread with nothing in between.
        self.rec.set_duration_secs(self.axis.timeline, t_s);
        let result = self.rec.log(
            entity.clone(),
            &rerun::TextLog::new(line).with_level(rerun::TextLogLevel::WARN),
        );
        self.rec.disable_timeline(self.axis.timeline);
        result.map_err(log_err(&entity))
    }

    /// The plan on the flight timeline from `t_s`, once.
    fn plan_start(&mut self, t_s: f64) -> Result<(), VizError> {
        if std::mem::replace(&mut self.plan_logged_on_flight, true) {
            return Ok(());
        }
        let axis = TimeAxis {
            timeline: crate::FLIGHT_TIMELINE,
            offset_s: t_s,
        };
        crate::plan::log_plan_axis(&self.rec, &self.plan, &axis)
    }

    /// Sends the buffered rows and series as columns: five chunks in all.
    fn flush(&mut self) -> Result<(), VizError> {
        let n = self.tracks.len();
        let (rec, axis) = (&self.rec, &self.axis);
        swarm::send_points(
            rec,
            "flight",
            axis,
            &self.row_times_s,
            n,
            &self.row_positions,
        )?;
        self.row_times_s.clear();
        self.row_positions.clear();
        let times = &self.series_times_s;
        swarm::send_spheres(rec, "flight", axis, times, n, &self.series_positions)?;
        let speeds = std::mem::take(&mut self.series_speeds);
        swarm::send_speeds(rec, "flight", axis, times, n, speeds)?;
        self.series_times_s.clear();
        self.series_positions.clear();
        let separation = std::mem::take(&mut self.separation);
        swarm::send_series(
            &self.rec,
            &paths::min_separation("flight"),
            &self.axis,
            &separation,
        )
    }

    /// At the end: the flown paths as line strips and the safety-distance line.
    fn finish_static(&mut self) -> Result<(), VizError> {
        let strips: Vec<(usize, Vec<[f32; 3]>)> = self
            .tracks
            .iter_mut()
            .enumerate()
            .filter(|(_, t)| !t.path.is_empty())
            .map(|(i, t)| (i, std::mem::take(&mut t.path)))
            .collect();
        swarm::log_paths(&self.rec, &self.scene, "flight", &strips)?;
        if let Some(first) = self.first_t_s {
            let line = [
                (first, self.scene.safety_distance_m),
                (self.last_t_s, self.scene.safety_distance_m),
            ];
            swarm::send_series(
                &self.rec,
                &paths::safety_distance("flight"),
                &self.axis,
                &line,
            )?;
        }
        Ok(())
    }
}

/// CPU time (user + system) of the calling thread, seconds.
fn thread_cpu_s() -> f64 {
    // SAFETY: getrusage only writes into the zeroed struct we pass.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: RUSAGE_THREAD with a valid pointer is always defined on Linux.
    if unsafe { libc::getrusage(libc::RUSAGE_THREAD, &mut usage) } != 0 {
        return f64::NAN;
    }
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    secs(usage.ru_utime) + secs(usage.ru_stime)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Drone;

    #[test]
    fn queued_samples_stay_small() {
        assert_eq!(std::mem::size_of::<Compact>(), 24);
    }

    fn scene(n: usize) -> Scene {
        Scene {
            name: "test".into(),
            voxel_size_m: 1.0,
            safety_distance_m: 0.25,
            drones: (0..n)
                .map(|i| Drone {
                    id: format!("d{i}"),
                    start_m: [i as f64, 0.0, 0.0],
                    ..Drone::default()
                })
                .collect(),
            ..Scene::default()
        }
    }

    fn worker(n: usize) -> Worker {
        let (rec, _storage) = rerun::RecordingStreamBuilder::new("recorder-test")
            .memory()
            .expect("memory stream");
        let options = RecorderOptions {
            row_period_s: 0.1,
            series_period_s: 0.2,
            ..RecorderOptions::default()
        };
        Worker::new(
            rec,
            &scene(n),
            PlanRows::default(),
            options,
            Arc::new(AtomicU64::new(0)),
        )
    }

    fn sample(drone: usize, t_s: f64, x: f64) -> FlightSample {
        FlightSample {
            drone,
            t_s,
            position_m: [x, 0.0, 0.0],
        }
    }

    #[test]
    fn rows_hold_every_drones_newest_position() {
        let mut w = worker(2);
        w.sample(sample(0, 0.01, 0.0));
        w.sample(sample(1, 0.02, 5.0));
        w.sample(sample(0, 0.11, 1.0));
        w.sample(sample(1, 0.12, 5.0));
        w.sample(sample(0, 0.21, 2.0));
        w.sample(sample(1, 0.22, 5.0));
        // Rows at 0.1 and 0.2 closed; the one at 0.3 waits for later samples.
        assert_eq!(w.row_times_s.len(), 2);
        assert!((w.row_times_s[0] - 0.1).abs() < 1e-12);
        assert_eq!(w.row_positions[..2], [[0.0, 0.0, 0.0], [5.0, 0.0, 0.0]]);
        assert_eq!(w.row_positions[2..], [[1.0, 0.0, 0.0], [5.0, 0.0, 0.0]]);
        // One series row (every second row): drone 0 moved 1 m in 0.1 s.
        assert_eq!(w.series_times_s.len(), 1);
        assert!((w.series_speeds[0] - 10.0).abs() < 1e-9);
        assert_eq!(w.series_speeds[1], 0.0);
        assert_eq!(w.separation.len(), 1);
        assert!((w.separation[0].1 - 4.0).abs() < 1e-12);
        w.close_rows(f64::INFINITY);
        assert_eq!(*w.row_positions.last().expect("rows"), [5.0, 0.0, 0.0]);
        assert_eq!(w.logged, 6);
    }

    #[test]
    fn rows_wait_for_every_drone_then_show_the_silent_one_at_its_start() {
        let mut w = worker(2);
        w.sample(sample(0, 0.0, 0.0));
        w.sample(sample(0, 0.5, 0.0));
        assert!(w.row_times_s.is_empty());
        w.sample(sample(0, 1.05, 0.0));
        assert_eq!(w.row_times_s.len(), 11);
        assert_eq!(w.row_positions[1], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn unknown_drones_are_dropped_and_counted() {
        let mut w = worker(1);
        w.sample(sample(3, 0.0, 0.0));
        assert_eq!(w.dropped.load(Ordering::Relaxed), 1);
        assert_eq!(w.logged, 0);
    }
}
