//! Recording a flight live: a [`FlightObserver`] that feeds the Rerun recorder
//! while the executor flies.
//!
//! The observer only queues: every call is a `try_send` on the recorder's bounded
//! channel, so the setpoint streams never wait for logging. When the recorder
//! falls behind, samples are dropped and counted (see [`RecorderStats`]). All
//! Rerun calls happen on the recorder's own thread, which also keeps rerun's
//! per-thread current time away from the executor's tasks.

use super::{RecordError, Sink, prepare};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use swarmctl::compiled::CompiledPlan;
use swarmctl::fly::LogEvent;
use swarmctl::fly::{FlightLog, FlightObserver};
use swarmctl::mission::Mission;
use swarmctl_viz::{
    FlightSample, Recorder, RecorderHandle, RecorderOptions, RecorderStats, TimeAxis,
};

/// A flight being recorded. Start it before takeoff, hand [`LiveFlight::observer`]
/// to `FlyOptions::observer`, and [`LiveFlight::finish`] it with the flight log.
/// Dropping it without `finish` still closes the recording properly.
pub struct LiveFlight {
    recorder: Recorder,
    tap: Arc<Tap>,
}

/// The executor's side: plan-order drone indices in, recorder messages out.
struct Tap {
    handle: RecorderHandle,
    /// Scene index of each drone in plan order.
    scene_index: Vec<usize>,
    plan_started: AtomicBool,
}

impl FlightObserver for Tap {
    fn sample(&self, drone: usize, t_s: f64, position_m: [f64; 3]) {
        self.handle.try_sample(FlightSample {
            // An index the recorder does not know is dropped and counted there.
            drone: self.scene_index.get(drone).copied().unwrap_or(usize::MAX),
            t_s,
            position_m,
        });
    }

    fn event(&self, event: &LogEvent) {
        self.handle
            .try_event(event.t_s, event.drone.as_deref(), &event.message);
        if event.message == swarmctl::fly::PLAN_STARTED
            && !self.plan_started.load(Ordering::Relaxed)
            && self.handle.try_plan_start(event.t_s)
        {
            self.plan_started.store(true, Ordering::Relaxed);
        }
    }
}

impl LiveFlight {
    /// Opens the recording at `sink` with the mission's world and `plan`, the
    /// compiled plan the executor flies (its samples and gates, on `plan_time`:
    /// the same artifact, not scheduled again), ready for samples.
    pub fn start(
        mission: &Mission,
        plan: &CompiledPlan,
        sink: &Sink,
        options: RecorderOptions,
    ) -> Result<Self, RecordError> {
        prepare(sink)?;
        let scene = super::plan::drones_scene(mission, &plan.drones, &plan.execution);
        let scene_index = plan
            .drones
            .iter()
            .map(|d| {
                scene
                    .drones
                    .iter()
                    .position(|s| s.id == d.id)
                    .unwrap_or(usize::MAX)
            })
            .collect();
        let axis = TimeAxis {
            timeline: swarmctl_viz::PLAN_TIMELINE,
            offset_s: 0.0,
        };
        let recorder = Recorder::start(sink, &scene, &[axis], options)?;
        let tap = Arc::new(Tap {
            handle: recorder.handle(),
            scene_index,
            plan_started: AtomicBool::new(false),
        });
        Ok(Self { recorder, tap })
    }

    /// What to put in `FlyOptions::observer`.
    pub fn observer(&self) -> Arc<dyn FlightObserver> {
        self.tap.clone()
    }

    /// Finishes the recording once the flight is over: everything queued is
    /// logged and the stream flushed. `log` supplies the plan's start on the flight
    /// timeline if the live event was missed, each drone's lateness and (under an
    /// ellipsoid) the summary's minimum scaled separation, known only now.
    pub fn finish(self, log: &FlightLog) -> Result<RecorderStats, RecordError> {
        if !self.tap.plan_started.load(Ordering::Relaxed)
            && let Some(t_s) = super::flight_plan_offset_s(log)
        {
            self.tap.handle.plan_start_blocking(t_s)?;
        }
        if let Some((t_s, text)) = super::scaled_summary_event(log) {
            self.tap.handle.event_blocking(t_s, None, &text)?;
        }
        for (drone, series) in super::lateness_series(log) {
            self.tap.handle.lateness_blocking(drone, series)?;
        }
        Ok(self.recorder.finish()?)
    }
}
