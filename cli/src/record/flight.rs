//! A flight log (and optionally its mission and plan) replayed into a recording.

use super::{RecordError, Sink, mission_scene, plan_scene, prepare};
use swarmctl::compiled::CompiledPlan;
use swarmctl::fly::FlightLog;
use swarmctl::mission::Mission;
use swarmctl_viz::{
    Drone, FlightSample, Recorder, RecorderOptions, RecorderStats, Scene, TimeAxis,
};

/// How logs written before launch pads named the start of the plan clock.
const PLAN_STARTED_BEFORE_PADS: &str = "all drones at their start";

/// When plan execution began, seconds after the first arm command: where plan
/// time 0 falls on the flight's timeline. `None` if the plan never started.
pub fn flight_plan_offset_s(log: &FlightLog) -> Option<f64> {
    log.events
        .iter()
        .find(|e| {
            e.message == swarmctl::fly::PLAN_STARTED
                || e.message.starts_with(PLAN_STARTED_BEFORE_PADS)
        })
        .map(|e| e.t_s)
}

/// Under an ellipsoid, the summary's minimum scaled separation from telemetry as
/// an event `(flight time, text)`: at the closest approach when the log names
/// the pair, else at the flight's end. The recording's own scaled plot is
/// sampled more coarsely than the summary's measurement, so the summary's figure
/// is the one to read. `None` for a sphere or when nothing was measured.
pub fn scaled_summary_event(log: &FlightLog) -> Option<(f64, String)> {
    let summary = &log.summary;
    let scaled = summary.min_scaled_separation.filter(|s| s.is_finite())?;
    let verdict = if scaled >= 1.0 { "held" } else { "breached" };
    let (t_s, pair) = match &summary.closest_scaled_pair {
        Some((a, b, t_s)) => (*t_s, format!(", {a} and {b}")),
        None => (summary.duration_s, String::new()),
    };
    let text = format!(
        "summary: min scaled separation from telemetry {scaled:.3}{pair} \
         ({verdict}; separated at 1 or more)"
    );
    Some((t_s, text))
}

/// Each drone's lateness against the schedule, `(flight time, seconds late)` at
/// each event it reached, for drones that reached any.
pub fn lateness_series(log: &FlightLog) -> Vec<(&str, Vec<(f64, f64)>)> {
    log.drones
        .iter()
        .filter(|d| !d.lateness.is_empty())
        .map(|d| {
            let series = d
                .lateness
                .iter()
                .map(|e| (e.flight_s, e.lateness_s()))
                .collect();
            (d.id.as_str(), series)
        })
        .collect()
}

/// Records `log` to `sink`: the flown telemetry on `flight_time`, each drone's
/// lateness, the log's events (and, under an ellipsoid, the summary's minimum scaled separation),
/// and — when given — the mission's world and the plan, the plan on
/// `plan_time` and again on `flight_time` from the moment execution began.
/// Samples go through the same recorder thread a live flight would use, but
/// blocking, since nothing is flying.
pub fn record_flight(
    log: &FlightLog,
    mission: Option<&Mission>,
    plan: Option<&CompiledPlan>,
    sink: &Sink,
) -> Result<RecorderStats, RecordError> {
    prepare(sink)?;
    let mut scene = match (mission, plan) {
        (Some(m), Some(p)) => plan_scene(m, p),
        (Some(m), None) => mission_scene(m),
        (None, _) => Scene {
            name: log.mission.clone(),
            voxel_size_m: 1.0,
            safety_distance_m: log.summary.safety_distance_m,
            vertical_separation_m: log.summary.vertical_separation_m,
            groups: vec![swarmctl_viz::Group {
                name: "drones".into(),
                color_rgb: swarmctl_viz::Group::palette(0),
            }],
            ..Scene::default()
        },
    };
    // Samples name drones by index in the scene: make sure every logged drone is there.
    for d in &log.drones {
        if !scene.drones.iter().any(|s| s.id == d.id) {
            scene.drones.push(Drone {
                id: d.id.clone(),
                goal_m: d.goal_m,
                start_m: d.samples.first().map_or(d.goal_m, |s| [s[1], s[2], s[3]]),
                ..Drone::default()
            });
        }
    }
    let mut axes = vec![TimeAxis {
        timeline: swarmctl_viz::PLAN_TIMELINE,
        offset_s: 0.0,
    }];
    if let Some(offset_s) = flight_plan_offset_s(log) {
        axes.push(TimeAxis {
            timeline: swarmctl_viz::FLIGHT_TIMELINE,
            offset_s,
        });
    }
    let recorder = Recorder::start(sink, &scene, &axes, RecorderOptions::for_sink(sink))?;
    let handle = recorder.handle();
    let mut samples: Vec<FlightSample> = log
        .drones
        .iter()
        .filter_map(|d| {
            let index = scene.drones.iter().position(|s| s.id == d.id)?;
            Some(d.samples.iter().map(move |s| FlightSample {
                drone: index,
                t_s: s[0],
                position_m: [s[1], s[2], s[3]],
            }))
        })
        .flatten()
        .collect();
    // In time order, as a live flight delivers them (the separation series relies on it).
    samples.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    for sample in samples {
        handle.sample_blocking(sample)?;
    }
    for e in &log.events {
        handle.event_blocking(e.t_s, e.drone.as_deref(), &e.message)?;
    }
    if let Some((t_s, text)) = scaled_summary_event(log) {
        handle.event_blocking(t_s, None, &text)?;
    }
    for (drone, series) in lateness_series(log) {
        handle.lateness_blocking(drone, series)?;
    }
    drop(handle);
    Ok(recorder.finish()?)
}
