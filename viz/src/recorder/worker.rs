//! The recorder thread: wakes every `poll_period_s`, handles control
//! messages, swaps the sample buffer out and places the samples into rows,
//! and every `flush_period_s` sends the rows as columns; at the end the flown
//! paths and the limit lines.
//!
//! Events are the only thing logged with the stream's current time, which is
//! per thread: it is set and used here with nothing in between.

use super::control::Message;
use super::options::RecorderOptions;
use super::rows::FlightRows;
use super::samples::{CloseOnDrop, Compact};
use super::stats::RecorderStats;
use crate::error::log_err;
use crate::plan::PlanRows;
use crate::swarm::Column;
use crate::{Scene, TimeAxis, VizError, paths, swarm};
use rerun::RecordingStream;
use std::sync::Arc;
use std::sync::atomic::AtomicU64;
use std::sync::mpsc::{Receiver, TryRecvError};
use std::time::{Duration, Instant};

/// Everything the recorder thread owns.
pub(super) struct Worker {
    rec: RecordingStream,
    /// The flight timeline, unshifted.
    axis: TimeAxis,
    options: RecorderOptions,
    scene: Scene,
    /// The plan's rows, to log again on the flight timeline once it starts.
    plan: PlanRows,
    plan_logged_on_flight: bool,
    rows: FlightRows,
}

impl Worker {
    /// A worker logging the flight of `scene`'s drones into `rec`; samples it
    /// cannot place are counted in `dropped`.
    pub(super) fn new(
        rec: RecordingStream,
        scene: &Scene,
        plan: PlanRows,
        options: RecorderOptions,
        dropped: Arc<AtomicU64>,
    ) -> Self {
        Self {
            rec,
            axis: TimeAxis {
                timeline: crate::FLIGHT_TIMELINE,
                offset_s: 0.0,
            },
            rows: FlightRows::new(scene, &options, dropped),
            options,
            scene: scene.clone(),
            plan,
            plan_logged_on_flight: false,
        }
    }

    /// The thread's body: runs until `Finish` (or every handle is gone), then
    /// flushes everything and reports.
    pub(super) fn run(
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
            samples.0.swap_out(&mut taken);
            let drained = taken.len();
            for compact in taken.drain(..) {
                self.rows.sample(compact.into());
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
        self.rows.close_rows(f64::INFINITY);
        self.flush()?;
        self.finish_static()?;
        self.rec
            .flush_blocking()
            .map_err(|e| VizError::Flush(e.to_string()))?;
        Ok(RecorderStats {
            samples_logged: self.rows.logged,
            samples_dropped: 0,
            events_dropped: 0,
            rows_logged: self.rows.rows_logged,
            thread_wall_s: started.elapsed().as_secs_f64(),
        })
    }

    fn handle(&mut self, message: Message) -> Result<(), VizError> {
        match message {
            Message::Event(e) => self.event(e.t_s, e.drone.as_deref(), &e.text),
            Message::PlanStart(t_s) => self.plan_start(t_s),
            Message::Lateness(drone_series) => {
                let (drone, series) = *drone_series;
                let entity = paths::lateness("flight", &drone);
                swarm::send_series(&self.rec, &entity, &self.axis, &series)
            }
            Message::Finish => Ok(()),
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

    /// Sends the buffered rows and series as columns: five chunks in all (six
    /// under an ellipsoid, with the scaled separation).
    fn flush(&mut self) -> Result<(), VizError> {
        let rows = &mut self.rows;
        let n = rows.tracks.len();
        let (rec, axis) = (&self.rec, &self.axis);
        let points = Column::Points(&rows.row_positions);
        swarm::send_column(rec, "flight", axis, &rows.row_times_s, n, points)?;
        rows.row_times_s.clear();
        rows.row_positions.clear();
        let times = &rows.series_times_s;
        let spheres = Column::Spheres(&rows.series_positions);
        swarm::send_column(rec, "flight", axis, times, n, spheres)?;
        let speeds = Column::Speeds(std::mem::take(&mut rows.series_speeds));
        swarm::send_column(rec, "flight", axis, times, n, speeds)?;
        rows.series_times_s.clear();
        rows.series_positions.clear();
        let separation = std::mem::take(&mut rows.separation);
        swarm::send_series(rec, &paths::min_separation("flight"), axis, &separation)?;
        let scaled = std::mem::take(&mut rows.scaled);
        swarm::send_series(rec, &paths::min_scaled_separation("flight"), axis, &scaled)
    }

    /// At the end: the flown paths as line strips, the safety-distance line and,
    /// under an ellipsoid, the scaled separation's limit.
    fn finish_static(&mut self) -> Result<(), VizError> {
        let strips: Vec<(usize, Vec<[f32; 3]>)> = self
            .rows
            .tracks
            .iter_mut()
            .enumerate()
            .filter(|(_, t)| !t.path.is_empty())
            .map(|(i, t)| (i, std::mem::take(&mut t.path)))
            .collect();
        swarm::log_paths(&self.rec, &self.scene, "flight", &strips)?;
        let Some(first) = self.rows.first_t_s else {
            return Ok(());
        };
        let span = [(first, 0.0), (self.rows.last_t_s, 0.0)];
        let (rec, axis) = (&self.rec, &self.axis);
        let distance_m = self.scene.safety_distance_m;
        swarm::send_limit_line(
            rec,
            &paths::safety_distance("flight"),
            axis,
            &span,
            distance_m,
        )?;
        if self.scene.scaled_radii_m().is_some() {
            swarm::send_limit_line(rec, &paths::scaled_limit("flight"), axis, &span, 1.0)?;
        }
        Ok(())
    }
}
