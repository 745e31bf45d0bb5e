//! The flight loop: one tick per setpoint period streams every drone's setpoint,
//! folds in telemetry, opens TPG gates, watches separation and link health, and
//! moves each drone through its phases (take off, fly the plan, land).

use super::command::CommandInbox;
use super::contingency;
use super::drone::{DroneRun, SwarmTick};
use super::gate::Progress;
use super::log::LogEvent;
use super::observer::FlightObserver;
use super::phase::Phase;
use super::replan::Replanner;
use super::settings::LoopSettings;
use super::tap::Tap;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A stuck plan (see `contingency::plan_stuck`) must stay stuck this long before
/// the flight ends, so a drone that is merely slow to settle is not mistaken for it.
const STUCK_CONFIRM: Duration = Duration::from_secs(3);
/// Takeoff of the whole swarm must finish within this long after arming.
const TAKEOFF_TIMEOUT_S: f64 = 60.0;

/// What the loop measured.
#[derive(Debug, Default)]
pub struct Outcome {
    /// Every drone reached its goal before landing started.
    pub completed: bool,
    /// Plan clock when every drone was at its goal, seconds (`None` if never).
    pub executed_makespan_s: Option<f64>,
    /// Smallest telemetry separation over the whole flight, metres (∞ if none).
    pub min_separation_m: f64,
    /// The two drones that came closest, and when (seconds since the first arm).
    pub closest_pair: Option<(String, String, f64)>,
    /// Under an ellipsoidal separation, the smallest scaled telemetry separation
    /// over the whole flight (separated when at least 1; ∞ if none or a sphere).
    pub min_scaled_separation: f64,
    /// The two drones behind `min_scaled_separation`, and when.
    pub closest_scaled_pair: Option<(String, String, f64)>,
    /// Highest telemetry speed over the whole flight, metres per second.
    pub max_speed_mps: f64,
    /// The drone that flew fastest, and when (seconds since the first arm).
    pub fastest: Option<(String, f64)>,
    /// Everything notable, in order, for the flight log.
    pub events: Vec<LogEvent>,
    /// Every replan tried (see `fly::replan`).
    pub replans: Vec<super::log::ReplanRecord>,
}

/// The loop's swarm-wide state between ticks.
struct Flight<'a> {
    drones: &'a mut [DroneRun],
    settings: LoopSettings,
    out: Outcome,
    /// When plan execution started (every drone at its start).
    execution_t0: Option<Instant>,
    /// When the plan being flown started: `execution_t0`, or the last splice.
    plan_t0: Option<Instant>,
    /// Replans the rest of the flight when drones leave it.
    replanner: Replanner,
    /// Abort, timeout or a failure before the plan: every drone holds, then lands.
    aborting: bool,
    landing_started: bool,
    /// Since when `contingency::plan_stuck` has held.
    stuck_since: Option<Instant>,
}

/// Runs the flight from armed-on-the-ground to landed (or to every drone given up).
/// Command results for the drones arrive in `inbox`.
pub async fn run(
    drones: &mut [DroneRun],
    settings: LoopSettings,
    armed_at: Instant,
    mut abort: tokio::sync::watch::Receiver<bool>,
    observers: &[Arc<dyn FlightObserver>],
    mut inbox: CommandInbox,
    replanner: Replanner,
) -> Outcome {
    let dt_s = 1.0 / settings.setpoint_rate_hz;
    let mut tick = tokio::time::interval(Duration::from_secs_f64(dt_s));
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut tap = Tap::new(drones.len());
    let mut flight = Flight::new(drones, settings, replanner);
    loop {
        tick.tick().await;
        let now = Instant::now();
        let since_arm_s = now.duration_since(armed_at).as_secs_f64();
        let abort_requested = *abort.borrow_and_update();
        flight.check_abort(abort_requested, now, since_arm_s);
        for d in flight.drones.iter_mut() {
            d.read_telemetry(&flight.settings, now, since_arm_s, &mut flight.out.events);
        }
        let t_exec_s = flight
            .execution_t0
            .map(|t0| now.duration_since(t0).as_secs_f64());
        if let Some(t0) = flight.plan_t0 {
            flight.contingencies(now.duration_since(t0).as_secs_f64(), now, since_arm_s);
        }
        // A splice above restarts the plan clock.
        if let Some(t0) = flight.plan_t0 {
            // Gates first (from everyone's progress), then commanded motion.
            flight.step_plan(now.duration_since(t0).as_secs_f64(), dt_s, now, since_arm_s);
        }
        flight.deliver(&mut inbox);
        for d in flight.drones.iter_mut() {
            d.advance(&flight.settings, now, since_arm_s, &mut flight.out.events);
        }
        for d in flight.drones.iter() {
            d.stream_setpoint().await;
        }
        flight.measure(since_arm_s);
        for d in flight.drones.iter_mut() {
            d.sample_tracking(now);
        }
        flight.start_plan_clock(now, since_arm_s);
        flight.end_plan(now, t_exec_s, since_arm_s);
        // Also before the plan ends: a drone a replan left out lands on its own.
        flight.start_landings(since_arm_s);
        if !observers.is_empty() {
            tap.forward(observers, flight.drones, armed_at, &flight.out.events);
        }
        let min_separation_m = flight.out.min_separation_m;
        let min_scaled = flight
            .settings
            .ellipsoid
            .map(|_| flight.out.min_scaled_separation);
        Tap::status(
            observers,
            flight.drones,
            since_arm_s,
            t_exec_s,
            min_separation_m,
            min_scaled,
        );
        if flight.finished() {
            break;
        }
    }
    flight.out.replans = std::mem::take(&mut flight.replanner.records);
    flight.out
}

impl<'a> Flight<'a> {
    fn new(drones: &'a mut [DroneRun], settings: LoopSettings, replanner: Replanner) -> Self {
        Self {
            drones,
            settings,
            out: Outcome {
                min_separation_m: f64::INFINITY,
                min_scaled_separation: f64::INFINITY,
                ..Outcome::default()
            },
            execution_t0: None,
            plan_t0: None,
            replanner,
            aborting: false,
            landing_started: false,
            stuck_since: None,
        }
    }

    fn event(&mut self, since_arm_s: f64, message: &str) {
        self.out
            .events
            .push(LogEvent::new(since_arm_s, None, message));
    }

    /// Starts aborting on request, on the execution timeout, on a drone failing
    /// before the plan started, or when takeoff takes too long.
    fn check_abort(&mut self, abort_requested: bool, now: Instant, since_arm_s: f64) {
        if self.aborting {
            return;
        }
        if abort_requested {
            self.aborting = true;
            self.event(
                since_arm_s,
                "abort requested: every drone holds, then lands",
            );
            return;
        }
        let Some(t0) = self.plan_t0 else {
            if let Some(d) = self
                .drones
                .iter()
                .find(|d| matches!(d.phase(), Phase::Failed(_)))
            {
                let why = format!(
                    "{} failed before the plan started: holding, then landing",
                    d.id()
                );
                self.aborting = true;
                self.event(since_arm_s, &why);
            } else if let Some(start) = self.settings.plan_start
                && now > start
                && !self.all_at_start()
            {
                let why = format!(
                    "not above their pads at the start instant: {}; holding, then landing",
                    self.not_at_start().join(", ")
                );
                self.aborting = true;
                self.event(since_arm_s, &why);
            } else if since_arm_s > TAKEOFF_TIMEOUT_S && !self.all_at_start() {
                // Name who kept the swarm waiting, and in which phase.
                let why = format!(
                    "takeoff timed out after {TAKEOFF_TIMEOUT_S:.0} s, not above their pads: {}; holding, then landing",
                    self.not_at_start().join(", ")
                );
                self.aborting = true;
                self.event(since_arm_s, &why);
            }
            return;
        };
        if now.duration_since(t0).as_secs_f64() > self.settings.execution_timeout_s {
            self.aborting = true;
            self.event(
                since_arm_s,
                "plan execution timed out: holding, then landing",
            );
        }
    }

    /// Lost drones, retirements, released events and replans, at `t_s` on the
    /// plan clock.
    fn contingencies(&mut self, t_s: f64, now: Instant, since_arm_s: f64) {
        let clearance = self.clearance();
        let events = &mut self.out.events;
        contingency::track_lost(self.drones, self.settings.lost_after_s, since_arm_s, events);
        if !self.landing_started {
            contingency::detect_retirement(self.drones, &self.settings, since_arm_s, events);
        }
        contingency::advance_retirements(self.drones, clearance, since_arm_s, events);
        contingency::release_landed(self.drones, self.settings.ground_clear, since_arm_s, events);
        if self.aborting || self.landing_started {
            self.replanner.abandon(since_arm_s, events);
        } else if let Some(spliced) = self.replanner.tick(self.drones, t_s, since_arm_s, events) {
            self.plan_t0 = Some(now);
            self.settings.execution_timeout_s = self.settings.timeout_factor * spliced.makespan_s
                + super::settings::TIMEOUT_MARGIN_S;
        }
    }

    /// Observed progress, gates and commanded motion of every flying drone.
    fn step_plan(&mut self, t_s: f64, dt_s: f64, now: Instant, since_arm_s: f64) {
        for d in self.drones.iter_mut() {
            d.observe_progress(t_s, &self.settings, now, since_arm_s);
        }
        let progress: Vec<Progress> = self.drones.iter().map(|d| d.progress().clone()).collect();
        let d_m = self.settings.safety_distance_m;
        let frozen = self.replanner.busy();
        let paused: Vec<bool> = (0..self.drones.len())
            .map(|i| frozen || contingency::paused_for(self.drones, i, d_m))
            .collect();
        for (d, swarm_paused) in self.drones.iter_mut().zip(paused) {
            let tick = SwarmTick {
                t_s,
                dt_s,
                aborting: self.aborting,
                swarm_paused,
            };
            d.step_plan(&self.settings, tick, &progress);
        }
    }

    /// Hands every command result that arrived since the last tick to its drone.
    fn deliver(&mut self, inbox: &mut CommandInbox) {
        for (i, command, result) in inbox.drain() {
            if let Some(d) = self.drones.get_mut(i) {
                d.deliver(command, result);
            }
        }
    }

    /// Every drone above its pad, ready for the plan.
    fn all_at_start(&self) -> bool {
        self.drones
            .iter()
            .all(|d| matches!(d.phase(), Phase::AtStart))
    }

    /// The drones not above their pads yet, with their phase.
    fn not_at_start(&self) -> Vec<String> {
        self.drones
            .iter()
            .filter(|d| !matches!(d.phase(), Phase::AtStart))
            .map(|d| format!("{} ({})", d.id(), d.phase().name()))
            .collect()
    }

    /// Everyone at the start: the plan clock starts, then or at the start instant
    /// asked for (plan time 0 is that instant, so the first tick after it is at
    /// most a setpoint period into the plan).
    fn start_plan_clock(&mut self, now: Instant, since_arm_s: f64) {
        if self.execution_t0.is_some() || self.aborting || !self.all_at_start() {
            return;
        }
        let t0 = match self.settings.plan_start {
            Some(start) if now < start => return,
            Some(start) => start,
            None => now,
        };
        self.execution_t0 = Some(t0);
        self.plan_t0 = Some(t0);
        for d in self.drones.iter_mut() {
            d.start_plan();
        }
        self.event(since_arm_s, super::log::PLAN_STARTED);
    }

    /// Ends plan execution once everyone is at the goal (or down, retired), the
    /// plan is stuck, or an abort has everyone holding: every drone queues to land.
    fn end_plan(&mut self, now: Instant, t_exec_s: Option<f64>, since_arm_s: f64) {
        let at_goal = |d: &DroneRun| matches!(d.phase(), Phase::AtGoal);
        // A drone a replan left out is no longer in the plan to finish.
        let all_at_goal = self.drones.iter().any(at_goal)
            && self.drones.iter().all(|d| at_goal(d) || d.left_plan());
        // Retired drones that are down count as done: the others finished without them.
        let plan_done = self.drones.iter().any(at_goal)
            && self.drones.iter().all(|d| {
                at_goal(d) || d.left_plan() || (d.released() && matches!(d.phase(), Phase::Landed))
            });
        if all_at_goal && !self.landing_started {
            self.out.completed = true;
            self.out.executed_makespan_s = t_exec_s;
        }
        let all_holding = self
            .drones
            .iter()
            .all(|d| !matches!(d.phase(), Phase::Flying) || d.follower().at_rest());
        // Everyone holds during a replan: that is not stuck.
        let stuck_now = !self.replanner.busy() && contingency::plan_stuck(self.drones);
        self.stuck_since = match (self.stuck_since, stuck_now) {
            (_, false) => None,
            (None, true) => Some(now),
            (Some(t), true) => Some(t),
        };
        let stuck = self
            .stuck_since
            .is_some_and(|t| now.duration_since(t) > STUCK_CONFIRM);
        if stuck && !self.landing_started {
            self.event(
                since_arm_s,
                "the plan cannot finish without the missing drones: the others land where they are, each once its column is clear",
            );
        }
        // A replan under way decides what is left to fly first.
        let done = !self.replanner.busy() && (all_at_goal || plan_done || stuck);
        if !self.landing_started && (done || (self.aborting && all_holding)) {
            self.landing_started = true;
            for d in self.drones.iter_mut() {
                d.prepare_landing();
            }
        }
    }

    /// Lets each drone waiting to land descend once telemetry shows it at rest and
    /// nothing is below it (never on commanded motion alone: after an abort the
    /// vehicle may still be braking behind its setpoint); a drone
    /// whose column stays blocked by one that will never move is handed to its
    /// autopilot.
    fn start_landings(&mut self, since_arm_s: f64) {
        let clearance = self.clearance();
        for i in 0..self.drones.len() {
            if matches!(self.drones[i].phase(), Phase::AwaitLanding)
                && self.drones[i].at_rest()
                && contingency::column_blocker(self.drones, i, clearance).is_none()
            {
                self.drones[i].begin_landing();
            }
        }
        for i in contingency::stranded(self.drones, clearance) {
            let why = match contingency::column_blocker(self.drones, i, clearance) {
                Some(j) if matches!(self.drones[j].phase(), Phase::Lost { .. }) => format!(
                    "lost drone {} was last seen in its column (it may have fallen there)",
                    self.drones[j].id()
                ),
                Some(j) => format!("{} is below it", self.drones[j].id()),
                None => "its column is blocked".to_string(),
            };
            let d = &mut self.drones[i];
            self.out.events.push(LogEvent::new(
                since_arm_s,
                Some(d.id()),
                &format!("cannot land: {why}; left in the autopilot's position hold — take manual control"),
            ));
            d.hand_over();
        }
    }

    /// Separation and speed from telemetry, over the whole flight: from the first arm
    /// command to the last touchdown, on the ground and in the air (pads are apart by
    /// a voxel, so drones standing on theirs never come close; one landing on another
    /// would). A lost drone's last position is stale and is left out.
    fn measure(&mut self, since_arm_s: f64) {
        let drones = &*self.drones;
        let out = &mut self.out;
        let known: Vec<(usize, [f64; 3])> = drones
            .iter()
            .enumerate()
            .filter(|(_, d)| !matches!(d.phase(), Phase::Lost { .. }))
            .filter_map(|(i, d)| d.position_m().map(|p| (i, p)))
            .collect();
        for (k, (i, a)) in known.iter().enumerate() {
            for (j, b) in &known[k + 1..] {
                let pair = || {
                    Some((
                        drones[*i].id().to_string(),
                        drones[*j].id().to_string(),
                        since_arm_s,
                    ))
                };
                let sep = super::path::distance_m(*a, *b);
                if sep < out.min_separation_m {
                    out.min_separation_m = sep;
                    out.closest_pair = pair();
                }
                if let Some(ellipsoid) = &self.settings.ellipsoid {
                    let scaled = ellipsoid.scaled(std::array::from_fn(|c| a[c] - b[c]));
                    if scaled < out.min_scaled_separation {
                        out.min_scaled_separation = scaled;
                        out.closest_scaled_pair = pair();
                    }
                }
            }
        }
        for d in drones {
            if d.speed_mps() > out.max_speed_mps {
                out.max_speed_mps = d.speed_mps();
                out.fastest = Some((d.id().to_string(), since_arm_s));
            }
        }
    }

    /// How far apart horizontally a drone coming down keeps from those below it.
    fn clearance(&self) -> contingency::Clearance {
        contingency::Clearance::new(
            self.settings.safety_distance_m,
            self.settings.tracking_error_m,
        )
    }

    /// Landing has started and every drone is down, given up, or handed over.
    fn finished(&self) -> bool {
        self.landing_started
            && self.drones.iter().all(|d| {
                matches!(
                    d.phase(),
                    Phase::Landed | Phase::Failed(_) | Phase::Lost { .. }
                ) || d.handed_over()
            })
    }
}

#[cfg(test)]
mod tests {
    use super::super::command::{self, Command};
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::task::{Context, Poll, Waker};
    use std::time::Duration;

    /// More results than tokio's cooperative budget (128 polls per task per tick).
    const DRONES: usize = 250;

    /// Command results of 250 drones arriving in the same tick must all be seen in
    /// that tick: polling join handles inside tokio's cooperative budget once
    /// reported drones 129 onwards unfinished, failing drones whose command had
    /// succeeded. The second half checks that this test does run under the budget,
    /// so a drain that spent it would fail here.
    #[tokio::test(flavor = "current_thread")]
    async fn many_command_results_are_drained_in_one_tick() {
        let (sender, mut inbox) = command::channel();
        let finished = Arc::new(AtomicUsize::new(0));
        for drone in 0..DRONES {
            let finished = finished.clone();
            sender.spawn_future(drone, Command::EnterExternalControl, async move {
                finished.fetch_add(1, Ordering::SeqCst);
                Ok(())
            });
        }
        for _ in 0..200 {
            if finished.load(Ordering::SeqCst) == DRONES {
                break;
            }
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
        assert_eq!(finished.load(Ordering::SeqCst), DRONES, "tasks did not run");

        let done = inbox.drain();
        assert_eq!(done.len(), DRONES, "results seen in one tick");
        assert!(done.iter().all(|(_, _, r)| r.is_ok()));
        let mut drones: Vec<usize> = done.iter().map(|(i, _, _)| *i).collect();
        drones.sort_unstable();
        assert_eq!(drones, (0..DRONES).collect::<Vec<_>>());

        // Control: the same number of messages read with the budgeted `poll_recv`
        // stops short within this tick.
        let (tx, mut rx) = tokio::sync::mpsc::unbounded_channel::<usize>();
        for i in 0..DRONES {
            tx.send(i).expect("receiver alive");
        }
        let mut cx = Context::from_waker(Waker::noop());
        let mut budgeted = 0;
        while let Poll::Ready(Some(_)) = rx.poll_recv(&mut cx) {
            budgeted += 1;
        }
        assert!(
            budgeted < DRONES,
            "the cooperative budget is not in effect here ({budgeted} read), so this test proves nothing"
        );
    }

    /// A command task that ends without a result (here: it panics) still reports,
    /// so the drone waiting for it is not left waiting for ever.
    #[tokio::test(flavor = "current_thread")]
    async fn a_panicking_command_reports_task_ended() {
        let (sender, mut inbox) = command::channel();
        sender.spawn_future(3, Command::Land, async {
            if true {
                panic!("boom");
            }
            Ok(())
        });
        for _ in 0..200 {
            tokio::time::sleep(Duration::from_millis(5)).await;
            let done = inbox.drain();
            if let Some((drone, command, result)) = done.into_iter().next() {
                assert_eq!((drone, command), (3, Command::Land));
                assert!(matches!(result, Err(command::CommandError::TaskEnded)));
                return;
            }
        }
        panic!("no result from the panicking task");
    }
}
