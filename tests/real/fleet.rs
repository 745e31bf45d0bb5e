//! A swarm of firmware processes on loopback and what every real-firmware flight
//! shares: the mission with each drone's endpoint, flying it, and reading the
//! outcome against the simulators' truth.

use crate::truth::{self, Figures, Track, TruthSample};
use mavlink::dialects::common::MavMessage;
use std::process::Child;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use swarmctl::fly::{self, FlightLog};
use swarmctl::link::frames;
use swarmctl::mission::{Autopilot, Geodetic, Mission};
use swarmctl::plan::{self, DiscretePlan};

/// One firmware process in its own working directory; killed when dropped.
pub struct Process {
    pub child: Child,
    pub _dir: tempfile::TempDir,
}

impl Drop for Process {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The vehicles of one flight: their processes (stopped when the fleet is
/// dropped), how swarmctl reaches each, and each one's true track.
pub struct Fleet {
    pub processes: Vec<Process>,
    pub links: Vec<fly::VehicleLink>,
    pub tracks: Vec<Track>,
    /// Whether each vehicle ever said it was armed, on its truth link.
    pub armed_seen: Vec<Arc<std::sync::atomic::AtomicBool>>,
    /// When the flight began (set by [`fly`]): truth instants are reported as
    /// seconds from it, the clock of the flight log's events.
    pub flown_at: std::sync::OnceLock<Instant>,
}

/// Where and how one firmware reports its simulator's truth.
pub struct TruthSource {
    /// The address of instance n's truth link.
    pub address: fn(u16) -> String,
    /// The message carrying it.
    pub message_id: u32,
    /// The message as a truth sample (`None` for any other).
    pub sample: fn(&MavMessage, Instant) -> Option<TruthSample>,
}

impl Fleet {
    /// One instance per drone, booted by `boot(n, home)` at the home its pad has
    /// under the mission's geo origin, with a reader of its truth until `stop`.
    pub fn boot(
        mission: &Mission,
        boot: impl Fn(u16, &Geodetic) -> Process,
        truth: &TruthSource,
        stop: Instant,
    ) -> Self {
        let origin = mission.geo_origin.expect("geo origin");
        let mut fleet = Fleet {
            processes: Vec::new(),
            links: Vec::new(),
            tracks: Vec::new(),
            armed_seen: Vec::new(),
            flown_at: std::sync::OnceLock::new(),
        };
        for (n, (_, d)) in mission.drones().enumerate() {
            let n = u16::try_from(n).expect("a few drones");
            let home = frames::geodetic_at(&origin, mission.pad_ground_m(d));
            fleet.processes.push(boot(n, &home));
            let track: Track = Arc::new(Mutex::new(Vec::new()));
            fleet.tracks.push(track.clone());
            let armed_seen = Arc::new(std::sync::atomic::AtomicBool::new(false));
            fleet.armed_seen.push(armed_seen.clone());
            tokio::spawn(truth::read(
                (truth.address)(n),
                d.system_id.expect("system id"),
                truth.message_id,
                truth.sample,
                track,
                armed_seen,
                stop,
            ));
            fleet.links.push(fly::VehicleLink::mavlink(
                d.endpoint.clone().expect("endpoint"),
                d.system_id.expect("system id"),
            ));
        }
        fleet
    }
}

/// Only one fleet boots at a time: each is a swarm of firmware processes.
pub static ONE_AT_A_TIME: tokio::sync::Mutex<()> = tokio::sync::Mutex::const_new(());

/// The mission at `relative` (under the repository) for `autopilot`, each drone
/// given the endpoint and system id `endpoint(n)` returns for the n-th drone in
/// file order; and its plan.
pub fn mission(
    relative: &str,
    autopilot: Autopilot,
    endpoint: impl Fn(usize) -> (String, u8),
) -> (Mission, DiscretePlan) {
    mission_edited(relative, autopilot, endpoint, |yaml| yaml)
}

/// [`mission`], with its text changed by `edit` first.
pub fn mission_edited(
    relative: &str,
    autopilot: Autopilot,
    endpoint: impl Fn(usize) -> (String, u8),
    edit: impl Fn(String) -> String,
) -> (Mission, DiscretePlan) {
    let path = crate::support::repo_path(relative);
    let written = edit(std::fs::read_to_string(&path).expect("mission"));
    let file = swarmctl::mission::parse_yaml(&written).expect("mission parses");
    let mut yaml = written.clone();
    if !yaml.contains("link:") {
        yaml.push_str("link: { autopilot: px4 }\n");
    }
    yaml = yaml.replace("autopilot: px4", &format!("autopilot: {autopilot}"));
    let ids = file
        .groups
        .iter()
        .flat_map(|g| g.drones.iter().map(|d| d.id.clone()));
    for (n, id) in ids.enumerate() {
        let (address, system_id) = endpoint(n);
        let written = format!("{{ id: {id}, ");
        assert!(yaml.contains(&written), "{id} in the mission");
        yaml = yaml.replace(
            &written,
            &format!("{{ id: {id}, endpoint: \"{address}\", system_id: {system_id}, "),
        );
    }
    let mission = swarmctl::mission::from_yaml(&yaml, &path).expect("mission valid");
    let plan = plan::solve(&mission, &plan::PlanOptions::default())
        .expect("plans")
        .plan;
    (mission, plan)
}

/// Flies `mission` on `fleet`; `abort` turns true to abort as Ctrl-C does.
pub async fn fly(
    fleet: &Fleet,
    mission: &Mission,
    plan: &DiscretePlan,
    abort: tokio::sync::watch::Receiver<bool>,
    limit: Duration,
) -> FlightLog {
    let mut options = fly::FlyOptions::new(fleet.links.clone());
    options.ready_timeout = Duration::from_secs(120);
    let _ = fleet.flown_at.set(Instant::now());
    tokio::time::timeout(limit, fly::fly(mission, plan, &options, abort))
        .await
        .expect("flight within the test's time limit")
        .expect("flight starts")
}

/// Prints the summary, each drone's figures and the truth, keeps the flight log
/// (`<target tmp>/<name>.json`, for a look after a failure), and returns the truth.
pub fn report(
    name: &str,
    mission: &Mission,
    log: &FlightLog,
    fleet: &Fleet,
    started: Instant,
) -> Figures {
    let origin = mission.geo_origin.expect("geo origin");
    let kept = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}.json"));
    match serde_json::to_vec(log) {
        Ok(json) if std::fs::write(&kept, &json).is_ok() => {
            eprintln!("  flight log kept in {}", kept.display());
        }
        _ => eprintln!("  flight log not kept"),
    }
    for line in log.summary.lines() {
        eprintln!("{line}");
    }
    for e in &log.events {
        let who = e.drone.as_deref().unwrap_or("swarm");
        eprintln!("  event {:6.1} s {who}: {}", e.t_s, e.message);
    }
    for d in &log.drones {
        eprintln!(
            "  {} frame {} origin {:?} final {:?} tracking {:?} holds {}",
            d.id,
            d.frame,
            d.local_origin_enu_m,
            d.final_distance_to_goal_m,
            d.tracking_error,
            d.tracking_holds
        );
    }
    let figures = truth::figures(&origin, &fleet.tracks);
    let ids: Vec<&str> = log.drones.iter().map(|d| d.id.as_str()).collect();
    eprintln!(
        "  truth: min separation {:.3} m ({}–{}), top speed {:.2} m/s ({}), {} samples; test {:.0} s",
        figures.min_separation_m,
        ids[figures.closest_pair.0],
        ids[figures.closest_pair.1],
        figures.top_speed_mps,
        ids[figures.fastest],
        figures.samples,
        started.elapsed().as_secs_f64()
    );
    if let (Some(top), Some(flown_at)) = (figures.top_speed_sample, fleet.flown_at.get()) {
        let v = top.velocity_ned_mps;
        eprintln!(
            "  truth: top speed at {:.1} s of the flight, velocity NED ({:.2}, {:.2}, {:.2}) m/s",
            top.at.saturating_duration_since(*flown_at).as_secs_f64(),
            v[0],
            v[1],
            v[2]
        );
    }
    for (id, p) in ids.iter().zip(&figures.final_enu_m) {
        eprintln!(
            "  {id} ends at ENU ({:.2}, {:.2}, {:.2}) m (truth)",
            p[0], p[1], p[2]
        );
    }
    figures
}

/// How much faster than any vehicle truly flew a telemetry speed must be before
/// it is the estimate that moved, not the vehicle: the estimate's speed noise in
/// flight is a few tenths (PX4 SIH: telemetry 0.87–0.99 m/s against truth
/// 0.92–1.02 m/s on the wide formation change).
const ESTIMATE_RAN_AWAY_MPS: f64 = 0.5;

/// Why the flight says nothing of swarmctl, when a vehicle's estimator failed:
/// its telemetry reported a speed more than [`ESTIMATE_RAN_AWAY_MPS`] above the
/// top speed any vehicle had by truth. `None` when the estimates kept to the truth.
pub fn estimate_ran_away(log: &FlightLog, truth: &Figures) -> Option<String> {
    let s = &log.summary;
    (s.max_speed_mps > truth.top_speed_mps + ESTIMATE_RAN_AWAY_MPS).then(|| {
        format!(
            "an estimate ran away from the truth: telemetry {:.2} m/s ({}), truth at most {:.2} m/s",
            s.max_speed_mps,
            s.fastest
                .as_ref()
                .map_or("?".to_string(), |(id, t_s)| format!("{id} at {t_s:.1} s")),
            truth.top_speed_mps
        )
    })
}

/// What the truth of any flight must show, whatever its telemetry said:
/// separation and the speed limit (within its tolerance).
pub fn assert_truth_kept_separation_and_speed(mission: &Mission, truth: &Figures) {
    let limits = &mission.limits;
    assert!(
        truth.min_separation_m >= limits.safety_distance_m,
        "true separation {:.3} m < {} m",
        truth.min_separation_m,
        limits.safety_distance_m
    );
    let top_speed_mps = limits.max_speed_mps * (1.0 + fly::SPEED_TOLERANCE);
    assert!(
        truth.top_speed_mps <= top_speed_mps,
        "true speed {:.3} m/s > {top_speed_mps:.3} m/s",
        truth.top_speed_mps
    );
}

/// The guarantees every completed real-firmware flight must show: frames from GPS,
/// separation and speed from telemetry and truth, completion, every drone within
/// `arrival_m` of its goal, and plan execution within `max_stretch` × the planned
/// makespan.
pub fn assert_flight_kept_the_guarantees(
    mission: &Mission,
    log: &FlightLog,
    truth: &Figures,
    arrival_m: f64,
    max_stretch: f64,
) {
    let s = &log.summary;
    assert!(
        truth.samples > 100 * log.drones.len(),
        "truth was read ({} samples)",
        truth.samples
    );
    for d in &log.drones {
        assert_eq!(d.frame, fly::FrameFix::GpsOrigin, "{}", d.id);
    }
    assert!(s.safety_held, "telemetry separation {}", s.min_separation_m);
    assert!(s.speed_held, "telemetry speed {}", s.max_speed_mps);
    assert_truth_kept_separation_and_speed(mission, truth);
    assert!(s.completed, "completed");
    assert!(
        s.max_final_distance_to_goal_m <= arrival_m,
        "at the goals: {:.3} m > {arrival_m} m",
        s.max_final_distance_to_goal_m
    );
    let planned_s = s.planned_makespan_s;
    let executed_s = s.executed_makespan_s.expect("plan executed");
    assert!(
        executed_s <= max_stretch * planned_s,
        "plan execution {executed_s:.1} s > {max_stretch} × {planned_s:.1} s planned"
    );
}
