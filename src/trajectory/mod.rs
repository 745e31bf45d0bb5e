//! Continuous trajectories from a [`Schedule`]: straight rest-to-rest runs with
//! S-curve speed profiles, so `|v| ≤ max_speed_mps`, `|a| ≤ max_accel_mps2` and
//! `|jerk| ≤ max_jerk_mps3` hold exactly, the drone stops at every corner, and it passes every TPG event's position
//! exactly at the scheduled time (which is what makes the precedences, and with them
//! the safety distance, hold in continuous time; see [`schedule`]).
//!
//! ```
//! use swarmctl::mission::from_yaml;
//! use swarmctl::plan::{DiscretePlan, DronePlan};
//! use swarmctl::world::Voxel;
//! let mission = from_yaml(
//!     "name: one\nworld: { dimensions: [3, 1, 1], voxel_size_m: 1.0, origin_m: [0.0, 0.0, 1.5] }\n\
//!      limits: { max_speed_mps: 1.0, max_accel_mps2: 1.0, safety_distance_m: 0.5 }\n\
//!      groups: [{ name: g, drones: [{ id: a, start: [0, 0, 0] }], goals: [[2, 0, 0]] }]\n",
//!     std::path::Path::new("one.yaml"),
//! ).unwrap();
//! let path = vec![Voxel::new(0, 0, 0), Voxel::new(1, 0, 0), Voxel::new(2, 0, 0)];
//! let plan = DiscretePlan {
//!     makespan_steps: 2,
//!     sum_of_costs_steps: 2,
//!     drones: vec![DronePlan { id: "a".into(), group: "g".into(), goal: path[2], path }],
//!     legs: Vec::new(),
//! };
//! let timed = swarmctl::trajectory::plan_trajectories(&mission, &plan).unwrap();
//! // 2 m straight at the default jerk limit of 2.5 m/s³: 1.4 s speeding up (0.4 s
//! // ramping the acceleration up, 0.6 s at 1 m/s², 0.4 s ramping it down), 0.6 s
//! // cruising, 1.4 s braking.
//! assert!((timed.makespan_s - 3.4).abs() < 1e-9);
//! let samples = timed.sample(20.0);
//! assert_eq!(samples[0].len(), 69);
//! let [t_s, x_m, y_m, z_m] = samples[0][68];
//! assert!((t_s - 3.4).abs() < 1e-9 && (x_m, y_m, z_m) == (2.0, 0.0, 1.5));
//! // Pad to pad: up 1.5 m from the ground first, down again at the end.
//! let flight = timed.pad_to_pad(mission.limits.kinematics());
//! assert_eq!(flight.drones[0].start_m, [0.0, 0.0, 0.0]);
//! assert_eq!(flight.drones[0].position_m(1e3), [2.0, 0.0, 0.0]);
//! ```

/// The speed profile of a run; it lives in [`crate::profile`], below both the
/// scheduler and this module, and is re-exported here because every run carries one.
pub use crate::profile::{Kinematics, Profile};

use crate::mission::Mission;
use crate::plan::DiscretePlan;
use crate::schedule::{self, Schedule, ScheduleError};
use serde::{Deserialize, Serialize};

/// One straight run: at rest at `from_m` until `start_s`, then along `profile` towards
/// `to_m`, at rest there from `start_s + profile.duration_s()`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Run {
    /// When the drone leaves `from_m`, seconds after the mission start.
    pub start_s: f64,
    /// Where the run starts, ENU metres.
    pub from_m: [f64; 3],
    /// Where it ends, ENU metres.
    pub to_m: [f64; 3],
    /// The speed along the run.
    pub profile: Profile,
}

impl Run {
    fn end_s(&self) -> f64 {
        self.start_s + self.profile.duration_s()
    }

    fn unit(&self) -> [f64; 3] {
        let l = self.profile.length_m;
        if l <= 0.0 {
            return [0.0; 3];
        }
        std::array::from_fn(|i| (self.to_m[i] - self.from_m[i]) / l)
    }

    fn position_m(&self, time_s: f64) -> [f64; 3] {
        let x = self.profile.distance_at_m(time_s - self.start_s);
        let u = self.unit();
        std::array::from_fn(|i| self.from_m[i] + u[i] * x)
    }

    fn velocity_mps(&self, time_s: f64) -> [f64; 3] {
        let v = self.profile.speed_at_mps(time_s - self.start_s);
        self.unit().map(|c| c * v)
    }
}

/// One drone's continuous motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DroneTrajectory {
    /// The drone's id in the mission.
    pub id: String,
    /// Where it rests before its first run, ENU metres.
    pub start_m: [f64; 3],
    /// Runs in time order, not overlapping.
    pub runs: Vec<Run>,
}

impl DroneTrajectory {
    /// The run in progress or last finished at `time_s`, if any has started.
    fn run_at(&self, time_s: f64) -> Option<&Run> {
        let k = self.runs.partition_point(|r| r.start_s <= time_s);
        k.checked_sub(1).map(|k| &self.runs[k])
    }

    /// Position at `time_s`, ENU metres (at the start before time zero, at the goal after).
    pub fn position_m(&self, time_s: f64) -> [f64; 3] {
        match self.run_at(time_s) {
            None => self.start_m,
            Some(r) => r.position_m(time_s),
        }
    }

    /// Velocity at `time_s`, ENU m/s: the feed-forward to stream with the position.
    pub fn velocity_mps(&self, time_s: f64) -> [f64; 3] {
        match self.run_at(time_s) {
            Some(r) if time_s < r.end_s() => r.velocity_mps(time_s),
            _ => [0.0; 3],
        }
    }

    /// When the drone comes to rest at its goal for good.
    pub fn arrival_s(&self) -> f64 {
        self.runs.last().map_or(0.0, Run::end_s)
    }
}

/// Every drone's trajectory, in plan order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trajectories {
    /// When the last drone comes to rest at its goal, seconds.
    pub makespan_s: f64,
    /// Every drone, in plan order.
    pub drones: Vec<DroneTrajectory>,
}

impl Trajectories {
    /// Samples every drone at `t = k / rate_hz` for `k = 0..=ceil(makespan_s · rate_hz)`,
    /// as `[t_s, x_m, y_m, z_m]` (ENU). All drones share the sample times; the last
    /// sample is at or after the makespan, so every drone ends at rest at its goal.
    pub fn sample(&self, rate_hz: f64) -> Vec<Vec<[f64; 4]>> {
        let count = sample_count(self.makespan_s, rate_hz);
        self.drones
            .iter()
            .map(|d| sample_drone(d, rate_hz, count))
            .collect()
    }
}

impl Trajectories {
    /// The whole flight, ground to ground: every drone first climbs straight up from
    /// the ground below its start to it (all together, while nobody has left yet),
    /// then flies its trajectory delayed by the longest climb, and once it has come
    /// to rest for good descends straight to the ground below. Climb and descent are
    /// rest-to-rest runs within the limits, inside the column below a pad-layer cell
    /// the drone holds (see the separation argument in [`schedule`]), and are what
    /// the independent checker measures along with the rest.
    pub fn pad_to_pad(&self, limits: Kinematics) -> Trajectories {
        self.with_ground_ends(limits, true)
    }

    /// The rest of a flight from where the drones are, down to the ground: every
    /// drone flies its trajectory and, once at rest for good, descends straight to
    /// the ground below, as in [`Trajectories::pad_to_pad`] but with no climb
    /// first. A replan spliced in flight starts with every drone airborne and at
    /// rest; this is what the independent checker measures of it.
    pub fn to_ground(&self, limits: Kinematics) -> Trajectories {
        self.with_ground_ends(limits, false)
    }

    /// Each drone's runs with the descent to the ground after its last, and with
    /// `climb` the climb from the ground before its first (every run then delayed
    /// by the longest climb).
    fn with_ground_ends(&self, limits: Kinematics, climb: bool) -> Trajectories {
        let vertical = |from_m: [f64; 3], to_m: [f64; 3], start_s: f64| Run {
            start_s,
            from_m,
            to_m,
            profile: Profile::new((to_m[2] - from_m[2]).abs(), limits),
        };
        let ground = |p: [f64; 3]| [p[0], p[1], 0.0];
        let climb_s = if climb {
            self.drones
                .iter()
                .map(|d| {
                    vertical(ground(d.start_m), d.start_m, 0.0)
                        .profile
                        .duration_s()
                })
                .fold(0.0, f64::max)
        } else {
            0.0
        };
        let drones: Vec<DroneTrajectory> = self
            .drones
            .iter()
            .map(|d| {
                let end_m = d.runs.last().map_or(d.start_m, |r| r.to_m);
                let mut runs = Vec::with_capacity(d.runs.len() + 2);
                if climb {
                    runs.push(vertical(ground(d.start_m), d.start_m, 0.0));
                }
                runs.extend(d.runs.iter().map(|r| Run {
                    start_s: r.start_s + climb_s,
                    ..*r
                }));
                runs.push(vertical(end_m, ground(end_m), d.arrival_s() + climb_s));
                DroneTrajectory {
                    id: d.id.clone(),
                    start_m: if climb { ground(d.start_m) } else { d.start_m },
                    runs,
                }
            })
            .collect();
        Trajectories {
            makespan_s: drones
                .iter()
                .map(DroneTrajectory::arrival_s)
                .fold(0.0, f64::max),
            drones,
        }
    }
}

/// Number of samples covering `[0, makespan_s]` at `rate_hz`.
fn sample_count(makespan_s: f64, rate_hz: f64) -> usize {
    // Tolerance so that a makespan that is a whole number of periods gets no extra sample.
    (makespan_s * rate_hz - 1e-9).ceil().max(0.0) as usize + 1
}

/// Samples one drone, walking its runs forward instead of searching per sample.
fn sample_drone(drone: &DroneTrajectory, rate_hz: f64, count: usize) -> Vec<[f64; 4]> {
    let mut out = Vec::with_capacity(count);
    let mut next = 0;
    for k in 0..count {
        let t = k as f64 / rate_hz;
        while next < drone.runs.len() && drone.runs[next].start_s <= t {
            next += 1;
        }
        let p = match next.checked_sub(1) {
            None => drone.start_m,
            Some(r) => drone.runs[r].position_m(t),
        };
        out.push([t, p[0], p[1], p[2]]);
    }
    out
}

/// The trajectories that realise `schedule`.
pub fn from_schedule(schedule: &Schedule) -> Trajectories {
    let drones = schedule
        .drones
        .iter()
        .map(|d| DroneTrajectory {
            id: d.id.clone(),
            start_m: d.start_m,
            runs: d
                .segments
                .iter()
                .map(|s| Run {
                    start_s: s.start_s,
                    from_m: s.from_m,
                    to_m: s.to_m,
                    profile: s.profile,
                })
                .collect(),
        })
        .collect();
    Trajectories {
        makespan_s: schedule.makespan_s,
        drones,
    }
}

/// The whole post-processing in one call: TPG, schedule, trajectories.
pub fn plan_trajectories(
    mission: &Mission,
    plan: &DiscretePlan,
) -> Result<Trajectories, ScheduleError> {
    let tpg = schedule::build(mission, plan)?;
    let schedule = schedule::solve(&tpg)?;
    Ok(from_schedule(&schedule))
}
