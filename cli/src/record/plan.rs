//! A compiled plan as a `viz::Scene`: voxel paths, trajectories and TPG waits.

use super::{RecordError, Sink, mission_scene, prepare};
use swarmctl::compiled::{CompiledDrone, CompiledPlan};
use swarmctl::mission::Mission;
use swarmctl::schedule::{EventKind, ExecutionPlan};
use swarmctl_viz::{Drone, PlanEvent, Scene, TimeAxis};

/// The point on the ground below an ENU position.
fn on_ground([x, y, _]: [f64; 3]) -> [f64; 3] {
    [x, y, 0.0]
}

/// A dwell shorter than this is sampling noise, not a wait worth reading about.
const MIN_WAIT_S: f64 = 1e-3;

/// The mission's world with the plan's drones: goals as assigned, paths, trajectories.
pub fn plan_scene(mission: &Mission, plan: &CompiledPlan) -> Scene {
    let mut scene = drones_scene(mission, &plan.drones, &plan.execution);
    scene.events.extend(leg_events(plan));
    scene.events.extend(scaled_check_event(plan));
    scene.events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    scene
}

/// The stage timeline: when the last drone comes to rest at the end of each leg
/// (takeoff done, each formation formed, everyone down on the pad layer).
fn leg_events(plan: &CompiledPlan) -> Vec<PlanEvent> {
    plan.legs
        .iter()
        .map(|leg| {
            let t_s = plan
                .execution
                .drones
                .iter()
                .filter_map(|d| {
                    d.events
                        .iter()
                        .rev()
                        .find(|e| e.step <= leg.end_step)
                        .map(|e| e.reach_s)
                })
                .fold(0.0, f64::max);
            let hold = if leg.hold_s > 0.0 {
                format!(", holding {} s", leg.hold_s)
            } else {
                String::new()
            };
            PlanEvent {
                t_s,
                drone: None,
                text: format!(
                    "leg {:?} done: every drone in place ({} steps, lower bound {}){hold}",
                    leg.name, leg.makespan_steps, leg.lower_bound_steps
                ),
            }
        })
        .collect()
}

/// Under an ellipsoid, the checker's guaranteed lower bound on the scaled
/// separation of setpoints, at the plan's start: the recording's scaled plot
/// shows the sampled drones against the ellipsoid, this is what the schedule
/// promises between samples (against the bounding cylinder grown by twice the
/// tracking error, hence a figure of its own). `None` for a sphere.
fn scaled_check_event(plan: &CompiledPlan) -> Option<PlanEvent> {
    let scaled = plan.check.scaled.as_ref()?;
    let verdict = if scaled.min_bound >= 1.0 {
        "held"
    } else {
        "breached"
    };
    Some(PlanEvent {
        t_s: 0.0,
        drone: None,
        text: format!(
            "checker: min scaled separation of setpoints ≥ {:.3} ({verdict}; separated at 1: \
             outside each other's cylinder of radius {:.3} m, half height {:.3} m)",
            scaled.min_bound, scaled.horizontal_m, scaled.vertical_m
        ),
    })
}

/// The mission's world with `drones` (paths, trajectories) and the TPG waits of `execution`.
pub(crate) fn drones_scene(
    mission: &Mission,
    drones: &[CompiledDrone],
    execution: &ExecutionPlan,
) -> Scene {
    let mut scene = mission_scene(mission);
    let center = |v| {
        let p = mission.airspace.center_m(v);
        [p.x, p.y, p.z]
    };
    let group_of = |name: &str| {
        scene
            .groups
            .iter()
            .position(|g| g.name == name)
            .unwrap_or(0)
    };
    scene.drones = drones
        .iter()
        .map(|d| {
            let mut path_m: Vec<[f64; 3]> = Vec::with_capacity(d.path.len());
            for v in &d.path {
                let p = center(*v);
                if path_m.last() != Some(&p) {
                    path_m.push(p);
                }
            }
            Drone {
                id: d.id.clone(),
                group: group_of(&d.group),
                // Pads are on the ground, below the pad layer the paths begin and end in.
                start_m: on_ground(d.path.first().map_or(center(d.goal), |v| center(*v))),
                goal_m: on_ground(center(d.goal)),
                path_m,
                trajectory: d.trajectory.clone(),
            }
        })
        .collect();
    scene.events = waits(execution);
    scene
}

/// TPG waits: a drone resting at a voxel centre before its path goes on, and the
/// drones whose progress it waits for (the cross-drone predecessors of what comes next).
pub(crate) fn waits(execution: &ExecutionPlan) -> Vec<PlanEvent> {
    let id = |drone: u32| {
        execution
            .drones
            .get(drone as usize)
            .map_or_else(|| format!("#{drone}"), |d| d.id.clone())
    };
    let mut events = Vec::new();
    for drone in &execution.drones {
        for (i, e) in drone.events.iter().enumerate() {
            let dwell_s = e.leave_s - e.reach_s;
            let rests = matches!(e.kind, EventKind::Start | EventKind::Arrive);
            // Also skips a NaN dwell.
            let waits = dwell_s.partial_cmp(&MIN_WAIT_S) == Some(std::cmp::Ordering::Greater);
            if !rests || i + 1 == drone.events.len() || !waits {
                continue;
            }
            let blockers: Vec<String> = drone.events[i + 1..]
                .iter()
                .take_while(|n| !matches!(n.kind, EventKind::Arrive))
                .flat_map(|n| n.after.iter().map(|a| id(a.drone)))
                .collect();
            let text = if blockers.is_empty() {
                format!("waits {dwell_s:.2} s at {}", e.voxel)
            } else {
                format!(
                    "waits {dwell_s:.2} s at {} for {}",
                    e.voxel,
                    blockers.join(", ")
                )
            };
            events.push(PlanEvent {
                t_s: e.reach_s,
                drone: Some(drone.id.clone()),
                text,
            });
        }
    }
    events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    events
}

/// Writes (or streams) the recording of a compiled plan on the `plan_time` timeline.
pub fn record_plan(mission: &Mission, plan: &CompiledPlan, sink: &Sink) -> Result<(), RecordError> {
    prepare(sink)?;
    let axis = TimeAxis {
        timeline: swarmctl_viz::PLAN_TIMELINE,
        offset_s: 0.0,
    };
    swarmctl_viz::write_scene(&plan_scene(mission, plan), sink, &[axis])?;
    Ok(())
}
