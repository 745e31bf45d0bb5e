//! From a TPG to times: straight rest-to-rest runs, an STN over their start times, and
//! the earliest schedule with latest times and slack.
//!
//! Each drone moves in *segments*: straight runs that start and end at rest (see
//! [`Profile`]). Every event inside a segment is passed at a fixed offset from the
//! segment's start, so the STN's timepoints are the segment starts, and a type-2 edge
//! `a → b` becomes a lower bound between the segment in which `a` is reached and the one
//! in which `b` is left. Segments break at the start, the goal, every turn and every
//! wait of the discrete plan. Because runs are rigid, a run that is constrained late and
//! constrains others early can close a cycle among runs; such runs are split at their
//! constrained `Enter` markers (the drone stops there instead) until no cycle is left.
//! Once every constrained marker is a stop, a remaining cycle is a cycle of the TPG
//! itself (a rotation), reported as [`ScheduleError::CyclicPlan`].

use super::ScheduleError;
use super::decision_lead::{DecisionLead, RunPoint};
use super::stn::Stn;
use super::tpg::Tpg;
use crate::profile::{Kinematics, Profile};
use serde::{Deserialize, Serialize};

/// One straight rest-to-rest run of one drone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// Index of the event at which the run starts (the drone is at rest there).
    pub first_event: u32,
    /// Index of the event at which the run ends (at rest again).
    pub last_event: u32,
    /// Where the run starts, ENU metres.
    pub from_m: [f64; 3],
    /// Where it ends, ENU metres.
    pub to_m: [f64; 3],
    /// Earliest start (the schedule's choice).
    pub start_s: f64,
    /// Latest start that keeps the makespan.
    pub latest_start_s: f64,
    /// The speed along the run, from `from_m` to `to_m`.
    pub profile: Profile,
}

impl Segment {
    /// When the run ends, at rest at `to_m`.
    pub fn end_s(&self) -> f64 {
        self.start_s + self.profile.duration_s()
    }
}

/// The times of one event in the schedule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EventTime {
    /// When the drone reaches the event's position.
    pub reach_s: f64,
    /// When it moves on past it (later than `reach_s` only where it stops and waits).
    pub leave_s: f64,
    /// How long leaving may be delayed without moving the makespan.
    pub slack_s: f64,
    /// The drone is at rest here.
    pub rest: bool,
}

/// One drone's timed motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DroneSchedule {
    /// The drone's id in the mission.
    pub id: String,
    /// Start voxel centre, ENU metres.
    pub start_m: [f64; 3],
    /// Goal voxel centre, ENU metres.
    pub goal_m: [f64; 3],
    /// Its runs in time order; it rests at `start_m` before the first.
    pub segments: Vec<Segment>,
    /// One entry per TPG event of the drone, same order.
    pub events: Vec<EventTime>,
}

/// The earliest schedule of a TPG: minimal makespan for its STN.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Schedule {
    /// When the last drone comes to rest at its goal, seconds.
    pub makespan_s: f64,
    /// Speed limit the runs obey, m/s (the mission's).
    pub max_speed_mps: f64,
    /// Acceleration limit the runs obey, m/s² (the mission's).
    pub max_accel_mps2: f64,
    /// Jerk limit the runs obey, m/s³ (the mission's).
    pub max_jerk_mps3: f64,
    /// Every drone, in plan order.
    pub drones: Vec<DroneSchedule>,
    /// The network that was solved: timepoint 0 is the origin, 1 the end of the mission,
    /// then one per segment in drone order.
    pub stn: Stn,
}

/// Where an event sits: (global segment index, offset from that segment's start).
type Anchor = (u32, f64);

/// Solves the TPG: earliest schedule, makespan, latest times and slack.
///
/// Fails with [`ScheduleError::CyclicPlan`] if the plan's precedences are cyclic.
pub fn solve(tpg: &Tpg) -> Result<Schedule, ScheduleError> {
    let limits = tpg.kinematics();
    let mut rest: Vec<Vec<bool>> = tpg
        .drones
        .iter()
        .map(|d| d.events.iter().map(|e| e.rest).collect())
        .collect();
    let mut constrained: Vec<Vec<bool>> = rest.iter().map(|r| vec![false; r.len()]).collect();
    for e in &tpg.cross_edges {
        constrained[e.to.drone as usize][e.to.index as usize] = true;
    }
    loop {
        let layout = Layout::new(tpg, &rest, limits);
        let stn = layout.stn(tpg);
        match stn.topological_order() {
            Ok(order) => return Ok(layout.schedule(tpg, stn, &order, &rest)),
            Err(cycle) => {
                // First split only where an edge inside a cycle enters a run mid-way;
                // if that is not possible, every constrained marker of the cyclic runs.
                let targeted = layout.split_cycle_entries(tpg, &cycle.components, &mut rest);
                let mut split_any = targeted;
                let fallback = if targeted {
                    &[][..]
                } else {
                    &cycle.components[..]
                };
                for component in fallback {
                    for &tp in component.iter().filter(|&&tp| tp >= FIRST_SEGMENT) {
                        let (drone, seg) = layout.owner[tp as usize];
                        let (first, last) = layout.bounds[drone as usize][seg as usize];
                        for i in first + 1..last {
                            if constrained[drone as usize][i as usize]
                                && !rest[drone as usize][i as usize]
                            {
                                rest[drone as usize][i as usize] = true;
                                split_any = true;
                            }
                        }
                    }
                }
                if !split_any {
                    let mut drones: Vec<String> = cycle
                        .components
                        .iter()
                        .flatten()
                        .filter(|&&tp| tp >= FIRST_SEGMENT)
                        .map(|&tp| tpg.drones[layout.owner[tp as usize].0 as usize].id.clone())
                        .collect();
                    drones.sort();
                    drones.dedup();
                    return Err(ScheduleError::CyclicPlan { drones });
                }
            }
        }
    }
}

/// Timepoints reserved before the segments.
const ORIGIN: u32 = 0;
const END: u32 = 1;
const FIRST_SEGMENT: u32 = 2;

/// The segments of every drone for one choice of rest events.
struct Layout {
    /// Per drone, per segment: (first event, last event).
    bounds: Vec<Vec<(u32, u32)>>,
    profiles: Vec<Vec<Profile>>,
    /// Timepoint of each drone's first segment.
    base: Vec<u32>,
    /// Timepoint → (drone, segment); the first `FIRST_SEGMENT` entries are placeholders.
    owner: Vec<(u32, u32)>,
    /// Per drone, per event: the segment index it belongs to (its leave segment, or the
    /// last segment for the final event).
    segment_of: Vec<Vec<u32>>,
}

impl Layout {
    fn new(tpg: &Tpg, rest: &[Vec<bool>], limits: Kinematics) -> Self {
        let mut bounds = Vec::with_capacity(tpg.drones.len());
        let mut profiles = Vec::with_capacity(tpg.drones.len());
        let mut base = Vec::with_capacity(tpg.drones.len());
        let mut owner = vec![(u32::MAX, u32::MAX); FIRST_SEGMENT as usize];
        let mut segment_of = Vec::with_capacity(tpg.drones.len());
        for (d, drone) in tpg.drones.iter().enumerate() {
            base.push(owner.len() as u32);
            let mut b = Vec::new();
            let mut p = Vec::new();
            let mut of = vec![0u32; drone.events.len()];
            let mut first = 0u32;
            for i in 1..drone.events.len() {
                of[i - 1] = b.len() as u32;
                if rest[d][i] {
                    let length_m =
                        drone.events[i].distance_m - drone.events[first as usize].distance_m;
                    owner.push((d as u32, b.len() as u32));
                    b.push((first, i as u32));
                    p.push(Profile::new(length_m, limits));
                    first = i as u32;
                }
            }
            if let Some(last) = of.last_mut() {
                *last = b.len().saturating_sub(1) as u32;
            }
            bounds.push(b);
            profiles.push(p);
            segment_of.push(of);
        }
        Self {
            bounds,
            profiles,
            base,
            owner,
            segment_of,
        }
    }

    /// Makes a stop of every `Enter` marker whose type-2 edge joins two runs of one
    /// strongly connected component. Returns whether anything changed.
    fn split_cycle_entries(
        &self,
        tpg: &Tpg,
        components: &[Vec<u32>],
        rest: &mut [Vec<bool>],
    ) -> bool {
        let mut component = vec![u32::MAX; self.owner.len()];
        for (c, members) in components.iter().enumerate() {
            for &tp in members {
                component[tp as usize] = c as u32;
            }
        }
        let mut split_any = false;
        for e in &tpg.cross_edges {
            let (from_tp, _) = self.reach(tpg, e.from.drone, e.from.index);
            let Some((to_tp, _)) = self.leave(tpg, e.to.drone, e.to.index) else {
                continue;
            };
            let c = component[to_tp as usize];
            let target = &mut rest[e.to.drone as usize][e.to.index as usize];
            if c != u32::MAX && component[from_tp as usize] == c && !*target {
                *target = true;
                split_any = true;
            }
        }
        split_any
    }

    fn timepoint(&self, drone: u32, seg: u32) -> u32 {
        self.base[drone as usize] + seg
    }

    /// Where the drone reaches event `i`: its start at time zero, any other event at
    /// its offset in the segment containing it, or at the end of the segment it ends.
    ///
    /// The start is where the drone rests from the outset, however late its first
    /// run begins. A stage's hold edge may start from it (a drone that holds the
    /// formation without having moved, such as a spare above its pad); anchored at
    /// the start of its first run instead, the hold edge from that drone to itself
    /// was a positive cycle, and for a drone that never moves there is no run at all.
    fn reach(&self, tpg: &Tpg, drone: u32, i: u32) -> Anchor {
        if i == 0 {
            return (ORIGIN, 0.0);
        }
        let seg = self.segment_of[drone as usize][i as usize];
        let (first, last) = self.bounds[drone as usize][seg as usize];
        let profile = &self.profiles[drone as usize][seg as usize];
        if i == first && seg > 0 {
            // A rest event: reached at the end of the previous segment.
            let prev = &self.profiles[drone as usize][seg as usize - 1];
            return (self.timepoint(drone, seg - 1), prev.duration_s());
        }
        if i == last {
            return (self.timepoint(drone, seg), profile.duration_s());
        }
        (self.timepoint(drone, seg), self.offset(tpg, drone, seg, i))
    }

    /// Where the drone moves on past event `i`; `None` for a drone that never moves
    /// (it has no run to delay, so nothing it waits for constrains it).
    fn leave(&self, tpg: &Tpg, drone: u32, i: u32) -> Option<Anchor> {
        if self.bounds[drone as usize].is_empty() {
            return None;
        }
        let seg = self.segment_of[drone as usize][i as usize];
        Some((self.timepoint(drone, seg), self.offset(tpg, drone, seg, i)))
    }

    fn offset(&self, tpg: &Tpg, drone: u32, seg: u32, i: u32) -> f64 {
        let events = &tpg.drones[drone as usize].events;
        let (first, _) = self.bounds[drone as usize][seg as usize];
        let x = events[i as usize].distance_m - events[first as usize].distance_m;
        self.profiles[drone as usize][seg as usize].time_at_distance_s(x)
    }

    fn stn(&self, tpg: &Tpg) -> Stn {
        let mut stn = Stn::new(self.owner.len() as u32);
        let inf = f64::INFINITY;
        for (d, profiles) in self.profiles.iter().enumerate() {
            let d = d as u32;
            for (g, p) in profiles.iter().enumerate() {
                let tp = self.timepoint(d, g as u32);
                let prev = if g == 0 { ORIGIN } else { tp - 1 };
                let lower = if g == 0 {
                    0.0
                } else {
                    profiles[g - 1].duration_s()
                };
                stn.add(prev, tp, lower, inf);
                if g + 1 == profiles.len() {
                    stn.add(tp, END, p.duration_s(), inf);
                }
            }
        }
        stn.add(ORIGIN, END, 0.0, inf);
        let mut lead = DecisionLead::new(tpg.setpoint_period_s, tpg.kinematics());
        for e in &tpg.cross_edges {
            let (from_tp, from_off) = self.reach(tpg, e.from.drone, e.from.index);
            let Some((to_tp, to_off)) = self.leave(tpg, e.to.drone, e.to.index) else {
                continue;
            };
            // A hold is waited out at rest; a hand-over is flown through on time
            // only with the dependant's decision budgeted (see `decision_lead`).
            let gap_s = if e.delay_s > 0.0 || from_tp == ORIGIN {
                e.delay_s
            } else {
                lead.gap_s(
                    self.run_point(from_tp, from_off),
                    self.run_point(to_tp, to_off),
                )
            };
            stn.add(from_tp, to_tp, from_off - to_off + gap_s, inf);
        }
        stn
    }

    /// The run starting at timepoint `tp` (a segment's) and an offset in it.
    fn run_point(&self, tp: u32, offset_s: f64) -> RunPoint<'_> {
        let (drone, seg) = self.owner[tp as usize];
        RunPoint {
            profile: &self.profiles[drone as usize][seg as usize],
            offset_s,
        }
    }

    fn schedule(&self, tpg: &Tpg, stn: Stn, order: &[u32], rest: &[Vec<bool>]) -> Schedule {
        let earliest = stn.earliest_in_order(order);
        let makespan_s = earliest[END as usize];
        let mut deadline = vec![f64::INFINITY; stn.timepoints as usize];
        deadline[END as usize] = makespan_s;
        let latest = stn.latest_dag(order, &deadline);
        let drones = tpg
            .drones
            .iter()
            .enumerate()
            .map(|(d, drone)| {
                let d32 = d as u32;
                let segments: Vec<Segment> = self.bounds[d]
                    .iter()
                    .zip(&self.profiles[d])
                    .enumerate()
                    .map(|(g, (&(first, last), profile))| {
                        let tp = self.timepoint(d32, g as u32) as usize;
                        Segment {
                            first_event: first,
                            last_event: last,
                            from_m: drone.events[first as usize].position_m,
                            to_m: drone.events[last as usize].position_m,
                            start_s: earliest[tp],
                            latest_start_s: latest[tp],
                            profile: *profile,
                        }
                    })
                    .collect();
                let n = drone.events.len() as u32;
                let events = (0..n)
                    .map(|i| {
                        let rest = rest[d][i as usize];
                        if segments.is_empty() {
                            return EventTime {
                                reach_s: 0.0,
                                leave_s: 0.0,
                                slack_s: f64::MAX,
                                rest,
                            };
                        }
                        let at = |(tp, off): Anchor| earliest[tp as usize] + off;
                        let slack = |(tp, _): Anchor| latest[tp as usize] - earliest[tp as usize];
                        let leave = if i + 1 == n {
                            self.reach(tpg, d32, i)
                        } else {
                            self.leave(tpg, d32, i).unwrap_or((ORIGIN, 0.0))
                        };
                        let reach_s = if i == 0 {
                            0.0
                        } else {
                            at(self.reach(tpg, d32, i))
                        };
                        EventTime {
                            reach_s,
                            leave_s: at(leave),
                            slack_s: slack(leave).max(0.0),
                            rest,
                        }
                    })
                    .collect();
                DroneSchedule {
                    id: drone.id.clone(),
                    start_m: drone.events[0].position_m,
                    goal_m: drone.events[n as usize - 1].position_m,
                    segments,
                    events,
                }
            })
            .collect();
        Schedule {
            makespan_s,
            max_speed_mps: tpg.max_speed_mps,
            max_accel_mps2: tpg.max_accel_mps2,
            max_jerk_mps3: tpg.max_jerk_mps3,
            drones,
            stn,
        }
    }
}
