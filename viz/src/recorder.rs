//! The streaming flight recorder: telemetry in, Rerun out, on its own OS thread.
//!
//! Flying must never wait for logging. The executor hands samples over a bounded
//! channel with [`RecorderHandle::try_sample`], which never blocks: when the
//! channel is full the sample is dropped and counted. The recorder thread
//! buffers samples per drone and sends them as columns every `flush_period_s`
//! (one chunk per drone instead of one row per sample), which keeps its CPU cost
//! small and never depends on the stream's per-thread current time for samples.

use crate::plan::{log_drone_styles, log_err, log_series, log_series_styles, ser_err};
use crate::style::{self, f32x3};
use crate::{Scene, TimeAxis, VizError, metrics, paths};
use rerun::{RecordingStream, TimeColumn};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, SyncSender, TrySendError, sync_channel};
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
    /// Channel capacity in messages; beyond it samples are dropped.
    pub capacity: usize,
    /// How often buffered samples are sent to the stream, wall-clock seconds. Each
    /// flush makes one chunk per drone and entity; chunks carry fixed overhead, so
    /// at 100 drones x 20 Hz 0.25 s cost ~15% of a core in rerun's threads, 2 s ~4%.
    pub flush_period_s: f64,
    /// How often the swarm's minimum separation is evaluated, flight seconds.
    pub separation_period_s: f64,
    /// A flown position is added to the drawn path only after moving this far, metres.
    pub path_step_m: f64,
}

impl Default for RecorderOptions {
    fn default() -> Self {
        Self {
            capacity: 8192,
            flush_period_s: 2.0,
            separation_period_s: 0.1,
            path_step_m: 0.02,
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
    /// CPU time of the recorder thread itself (not rerun's own writer threads).
    pub thread_cpu_s: f64,
    /// Wall time the recorder thread ran.
    pub thread_wall_s: f64,
}

enum Message {
    Sample(FlightSample),
    Event {
        t_s: f64,
        drone: Option<String>,
        text: String,
    },
}

/// A cheap, cloneable sending side for the executor's tasks.
#[derive(Clone)]
pub struct RecorderHandle {
    tx: SyncSender<Message>,
    dropped: Arc<AtomicU64>,
}

/// Owns the recorder thread; [`Recorder::finish`] flushes and joins it.
pub struct Recorder {
    handle: RecorderHandle,
    thread: JoinHandle<Result<RecorderStats, VizError>>,
}

impl RecorderHandle {
    /// Queues a sample without blocking; returns false (and counts it) if dropped.
    pub fn try_sample(&self, sample: FlightSample) -> bool {
        match self.tx.try_send(Message::Sample(sample)) {
            Ok(()) => true,
            Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) => {
                self.dropped.fetch_add(1, Ordering::Relaxed);
                false
            }
        }
    }

    /// Queues a sample, waiting for room: for replays, where nothing is flying.
    pub fn sample_blocking(&self, sample: FlightSample) -> Result<(), VizError> {
        self.tx
            .send(Message::Sample(sample))
            .map_err(|_| VizError::RecorderGone)
    }

    /// Queues a text event (never blocks; events are rare, a full channel drops it).
    pub fn try_event(&self, t_s: f64, drone: Option<&str>, text: &str) -> bool {
        let message = Message::Event {
            t_s,
            drone: drone.map(str::to_string),
            text: text.to_string(),
        };
        self.tx.try_send(message).is_ok()
    }

    /// Queues a text event, waiting for room.
    pub fn event_blocking(
        &self,
        t_s: f64,
        drone: Option<&str>,
        text: &str,
    ) -> Result<(), VizError> {
        let message = Message::Event {
            t_s,
            drone: drone.map(str::to_string),
            text: text.to_string(),
        };
        self.tx.send(message).map_err(|_| VizError::RecorderGone)
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
        crate::plan::log_scene(&rec, scene, plan_axes)?;
        log_drone_styles(&rec, scene, "flight")?;
        log_series_styles(&rec, scene, "flight")?;
        let (tx, rx) = sync_channel(options.capacity.max(1));
        let dropped = Arc::new(AtomicU64::new(0));
        let worker = Worker::new(rec, scene, options, Arc::clone(&dropped));
        let thread = std::thread::Builder::new()
            .name("rerun-recorder".into())
            .spawn(move || worker.run(rx))
            .map_err(|_| VizError::RecorderGone)?;
        Ok(Self {
            handle: RecorderHandle { tx, dropped },
            thread,
        })
    }

    /// A sending side to give to the executor.
    pub fn handle(&self) -> RecorderHandle {
        self.handle.clone()
    }

    /// Closes the channel, waits for everything queued to be logged, flushes the stream.
    pub fn finish(self) -> Result<RecorderStats, VizError> {
        let Self { handle, thread } = self;
        let dropped = Arc::clone(&handle.dropped);
        drop(handle);
        let mut stats = thread.join().map_err(|_| VizError::RecorderGone)??;
        stats.samples_dropped += dropped.load(Ordering::Relaxed);
        Ok(stats)
    }
}

/// Per-drone state on the recorder thread.
#[derive(Default)]
struct Track {
    id: String,
    last: Option<[f64; 4]>,
    latest_m: Option<[f64; 3]>,
    times_s: Vec<f64>,
    positions: Vec<[f32; 3]>,
    speed: Vec<(f64, f64)>,
    path: Vec<[f32; 3]>,
}

struct Worker {
    rec: RecordingStream,
    axis: TimeAxis,
    options: RecorderOptions,
    tracks: Vec<Track>,
    separation: Vec<(f64, f64)>,
    next_separation_s: f64,
    first_t_s: Option<f64>,
    last_t_s: f64,
    safety_distance_m: f64,
    colors: Vec<[u8; 3]>,
    line_radius_m: f32,
    dropped: Arc<AtomicU64>,
    logged: u64,
}

impl Worker {
    fn new(
        rec: RecordingStream,
        scene: &Scene,
        options: RecorderOptions,
        dropped: Arc<AtomicU64>,
    ) -> Self {
        Self {
            rec,
            axis: TimeAxis {
                timeline: crate::FLIGHT_TIMELINE,
                offset_s: 0.0,
            },
            tracks: scene
                .drones
                .iter()
                .map(|d| Track {
                    id: d.id.clone(),
                    ..Track::default()
                })
                .collect(),
            colors: scene
                .drones
                .iter()
                .map(|d| style::flown(scene.drone_color(d)))
                .collect(),
            line_radius_m: style::line_radius_m(scene.voxel_size_m),
            safety_distance_m: scene.safety_distance_m,
            separation: Vec::new(),
            next_separation_s: 0.0,
            first_t_s: None,
            last_t_s: 0.0,
            options,
            dropped,
            logged: 0,
        }
    }

    fn run(mut self, rx: Receiver<Message>) -> Result<RecorderStats, VizError> {
        let started = Instant::now();
        let period = Duration::from_secs_f64(self.options.flush_period_s.max(0.001));
        let mut next_flush = Instant::now() + period;
        loop {
            let wait = next_flush.saturating_duration_since(Instant::now());
            match rx.recv_timeout(wait) {
                Ok(Message::Sample(s)) => self.sample(s),
                Ok(Message::Event { t_s, drone, text }) => {
                    self.event(t_s, drone.as_deref(), &text)?
                }
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => break,
            }
            if Instant::now() >= next_flush {
                self.flush()?;
                next_flush = Instant::now() + period;
            }
        }
        self.flush()?;
        self.finish_static()?;
        self.rec
            .flush_blocking()
            .map_err(|e| VizError::Flush(e.to_string()))?;
        Ok(RecorderStats {
            samples_logged: self.logged,
            samples_dropped: 0,
            thread_cpu_s: thread_cpu_s(),
            thread_wall_s: started.elapsed().as_secs_f64(),
        })
    }

    fn sample(&mut self, s: FlightSample) {
        let step_m = self.options.path_step_m;
        let Some(track) = self.tracks.get_mut(s.drone) else {
            self.dropped.fetch_add(1, Ordering::Relaxed);
            return;
        };
        let [x, y, z] = s.position_m;
        let now = [s.t_s, x, y, z];
        if let Some(last) = track.last
            && let Some(&(_, v)) = metrics::speeds(&[last, now]).first()
        {
            track.speed.push((s.t_s, v));
        }
        let p = f32x3(s.position_m);
        let moved = track.path.last().is_none_or(|q| {
            let d2: f32 = (0..3).map(|i| (p[i] - q[i]).powi(2)).sum();
            f64::from(d2.sqrt()) >= step_m
        });
        if moved {
            track.path.push(p);
        }
        track.last = Some(now);
        track.latest_m = Some(s.position_m);
        track.times_s.push(s.t_s);
        track.positions.push(p);
        self.logged += 1;
        self.first_t_s.get_or_insert(s.t_s);
        self.last_t_s = self.last_t_s.max(s.t_s);
        // Separation ticks follow flight time as seen in the samples.
        while s.t_s >= self.next_separation_s {
            let latest: Vec<[f64; 3]> = self.tracks.iter().filter_map(|t| t.latest_m).collect();
            if let Some(d) = metrics::min_pairwise_m(&latest) {
                self.separation.push((self.next_separation_s, d));
            }
            self.next_separation_s += self.options.separation_period_s.max(1e-3);
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

    /// Sends every drone's buffered samples as columns, then the separation series.
    fn flush(&mut self) -> Result<(), VizError> {
        for track in &mut self.tracks {
            if track.times_s.is_empty() {
                continue;
            }
            let times = std::mem::take(&mut track.times_s);
            let positions = std::mem::take(&mut track.positions);
            let column =
                |name: &'static str| TimeColumn::new_duration_secs(name, times.iter().copied());
            let entity = paths::drone("flight", &track.id);
            let columns = rerun::Points3D::update_fields()
                .with_positions(positions.iter().copied())
                .columns_of_unit_batches()
                .map_err(ser_err(&entity))?;
            self.rec
                .send_columns(entity.clone(), [column(self.axis.timeline)], columns)
                .map_err(log_err(&entity))?;
            let entity = paths::safety("flight", &track.id);
            let columns = rerun::Ellipsoids3D::update_fields()
                .with_centers(positions)
                .columns_of_unit_batches()
                .map_err(ser_err(&entity))?;
            self.rec
                .send_columns(entity.clone(), [column(self.axis.timeline)], columns)
                .map_err(log_err(&entity))?;
            let speed = std::mem::take(&mut track.speed);
            log_series(
                &self.rec,
                &paths::speed("flight", &track.id),
                &self.axis,
                &speed,
            )?;
        }
        let separation = std::mem::take(&mut self.separation);
        log_series(
            &self.rec,
            &paths::min_separation("flight"),
            &self.axis,
            &separation,
        )
    }

    /// At the end: the flown paths as line strips and the safety-distance line.
    fn finish_static(&mut self) -> Result<(), VizError> {
        for (track, rgb) in self.tracks.iter().zip(&self.colors) {
            if track.path.len() < 2 {
                continue;
            }
            let entity = paths::flown_path(&track.id);
            self.rec
                .log_static(
                    entity.clone(),
                    &rerun::LineStrips3D::new([track.path.clone()])
                        .with_colors([style::color(*rgb)])
                        .with_radii([self.line_radius_m]),
                )
                .map_err(log_err(&entity))?;
        }
        if let Some(first) = self.first_t_s {
            let line = [
                (first, self.safety_distance_m),
                (self.last_t_s, self.safety_distance_m),
            ];
            log_series(
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
