//! The real firmware: several ArduCopter SITL instances (`../shared/sitl/ardupilot`,
//! ArduPilot's own EKF, position controller and physics) on loopback, each booted
//! at its own home on its pad, so each keeps its own local frame. swarmctl flies the
//! formation change on them and the simulator's truth (`SIM_STATE`, read on each
//! vehicle's second serial port) is measured apart from the telemetry swarmctl
//! steered by.
//!
//! `SWARMCTL_ARDUCOPTER` overrides where the binary is.

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use swarmctl::fly;
use swarmctl::link::frames;
use swarmctl::mission::{Geodetic, Mission};
use swarmctl::plan::{self, DiscretePlan};

/// ArduCopter's SITL serial ports: SERIAL0 at 5760 + 10·N, SERIAL1 at 5762 + 10·N.
const SERIAL0_BASE: u16 = 5760;
const SERIAL1_BASE: u16 = 5762;
/// The whole test, boot (about 40 s) to the last touchdown.
const TEST_LIMIT: Duration = Duration::from_secs(400);

fn arducopter_dir() -> PathBuf {
    std::env::var_os("SWARMCTL_ARDUCOPTER")
        .map(PathBuf::from)
        .and_then(|p| p.parent().map(PathBuf::from))
        .unwrap_or_else(|| crate::support::repo_root().join("../shared/sitl/ardupilot"))
}

/// One ArduCopter process in its own working directory; killed when dropped.
struct Vehicle {
    child: Child,
    _dir: tempfile::TempDir,
}

impl Drop for Vehicle {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Boots instance `n` (system id n + 1) at `home`.
fn boot(n: u16, home: &Geodetic) -> Vehicle {
    let dir = arducopter_dir();
    let binary = dir.join("arducopter");
    assert!(
        binary.is_file(),
        "ArduCopter SITL not found at {} (set SWARMCTL_ARDUCOPTER)",
        binary.display()
    );
    let work = tempfile::tempdir().expect("working directory");
    let child = Command::new(&binary)
        .current_dir(work.path())
        .args(["--model", "+", "--speedup", "1", "-I", &n.to_string()])
        .args(["--sysid", &(n + 1).to_string()])
        .arg("--home")
        .arg(format!(
            "{:.9},{:.9},{:.3},0",
            home.lat_deg, home.lon_deg, home.alt_m
        ))
        .arg("--defaults")
        .arg(dir.join("copter.parm"))
        .args(["--serial0", "tcp:0"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("ArduCopter starts");
    Vehicle { child, _dir: work }
}

/// One true state: when it arrived, latitude and longitude (degrees), altitude
/// (metres AMSL) and speed (m/s).
type TruthSample = (Instant, f64, f64, f64, f64);

/// Reads `SIM_STATE` at 20 Hz from instance `n`'s SERIAL1 until `stop`.
async fn read_truth(n: u16, samples: Arc<Mutex<Vec<TruthSample>>>, stop: Instant) {
    use mavlink::AsyncMavConnection;
    use mavlink::dialects::common::{COMMAND_LONG_DATA, MavCmd, MavMessage};
    let address = format!("tcpout:127.0.0.1:{}", SERIAL1_BASE + 10 * n);
    let connection = loop {
        match mavlink::connect_async::<MavMessage>(&address).await {
            Ok(c) => break c,
            Err(_) if Instant::now() < stop => tokio::time::sleep(Duration::from_secs(1)).await,
            Err(e) => panic!("no truth link to {address}: {e}"),
        }
    };
    let header = mavlink::MavHeader {
        system_id: 251,
        component_id: 190,
        sequence: 0,
    };
    let ask = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        target_system: (n + 1) as u8,
        target_component: 1,
        command: MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
        confirmation: 0,
        param1: 108.0, // SIM_STATE
        param2: 50_000.0,
        param3: 0.0,
        param4: 0.0,
        param5: 0.0,
        param6: 0.0,
        param7: 0.0,
    });
    let mut asked_at: Option<Instant> = None;
    while Instant::now() < stop {
        if asked_at.is_none_or(|t| t.elapsed() > Duration::from_secs(5)) {
            let _ = connection.send(&header, &ask).await;
            asked_at = Some(Instant::now());
        }
        let Ok(Ok((_, message))) =
            tokio::time::timeout(Duration::from_millis(500), connection.recv()).await
        else {
            continue;
        };
        if let MavMessage::SIM_STATE(s) = message {
            let speed = f64::from(s.vn.hypot(s.ve).hypot(s.vd));
            samples.lock().unwrap().push((
                Instant::now(),
                f64::from(s.lat_int) / 1e7,
                f64::from(s.lon_int) / 1e7,
                f64::from(s.alt),
                speed,
            ));
        }
    }
}

/// Metres east, north, up of `(lat, lon, alt)` from `origin`, on a local flat
/// earth with the WGS84 radii of curvature: written here, apart from swarmctl's
/// geodesy, so the check shares no code with what it checks.
fn enu_m(origin: &Geodetic, lat_deg: f64, lon_deg: f64, alt_m: f64) -> [f64; 3] {
    const A_M: f64 = 6_378_137.0;
    const E2: f64 = 6.694_379_990_14e-3;
    let lat0 = origin.lat_deg.to_radians();
    let w2 = 1.0 - E2 * lat0.sin().powi(2);
    let prime_m = A_M / w2.sqrt();
    let meridian_m = prime_m * (1.0 - E2) / w2;
    [
        (lon_deg - origin.lon_deg).to_radians() * prime_m * lat0.cos(),
        (lat_deg - origin.lat_deg).to_radians() * meridian_m,
        alt_m - origin.alt_m,
    ]
}

/// Smallest true distance between two vehicles, sampled every 50 ms from the first
/// to the last truth sample of all (each vehicle at its latest state), and the
/// highest true speed.
fn truth_figures(origin: &Geodetic, tracks: &[Vec<TruthSample>]) -> (f64, f64) {
    let start = tracks.iter().filter_map(|t| t.first()).map(|s| s.0).max();
    let end = tracks.iter().filter_map(|t| t.last()).map(|s| s.0).min();
    let (Some(start), Some(end)) = (start, end) else {
        return (f64::INFINITY, 0.0);
    };
    let mut min_m = f64::INFINITY;
    let mut t = start;
    let mut cursor = vec![0usize; tracks.len()];
    while t <= end {
        let at: Vec<[f64; 3]> = tracks
            .iter()
            .zip(&mut cursor)
            .map(|(track, k)| {
                while *k + 1 < track.len() && track[*k + 1].0 <= t {
                    *k += 1;
                }
                let s = track[*k];
                enu_m(origin, s.1, s.2, s.3)
            })
            .collect();
        for (i, a) in at.iter().enumerate() {
            for b in &at[i + 1..] {
                let d =
                    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
                min_m = min_m.min(d);
            }
        }
        t += Duration::from_millis(50);
    }
    let top_speed = tracks.iter().flatten().map(|s| s.4).fold(0.0, f64::max);
    (min_m, top_speed)
}

/// The formation change for ArduPilot, each drone on the endpoint of its instance.
fn mission_for_ardupilot() -> (Mission, DiscretePlan) {
    let path = crate::support::repo_path("missions/formation-change.yaml");
    let mut yaml = std::fs::read_to_string(&path).expect("mission");
    yaml = yaml.replace("autopilot: px4", "autopilot: ardupilot");
    for (n, id) in ["b1", "b2", "b3", "b4", "r1", "r2", "r3", "r4"]
        .iter()
        .enumerate()
    {
        let written = format!("{{ id: {id}, ");
        let with_endpoint = format!(
            "{{ id: {id}, endpoint: \"tcpout:127.0.0.1:{}\", system_id: {}, ",
            SERIAL0_BASE + 10 * n as u16,
            n + 1
        );
        assert!(yaml.contains(&written), "{id} in the mission");
        yaml = yaml.replace(&written, &with_endpoint);
    }
    let mission = swarmctl::mission::from_yaml(&yaml, &path).expect("mission valid");
    let plan = plan::solve(&mission, &plan::PlanOptions::default())
        .expect("plans")
        .plan;
    (mission, plan)
}

/// The 8-drone formation change on eight real ArduCopter SITL vehicles, each at its
/// own home: completed, safety held from telemetry and from the simulator's truth,
/// speed within the limit plus tolerance, every drone at its goal.
///
/// Ignored because it fails today, and says so: every vehicle's frame is placed
/// from its GPS origin within 1 cm, but ArduCopter strays up to 1.4 m from the
/// streamed setpoints (p95 about 1 m), tops 1.7 m/s against 1.0 m/s, and the truth
/// separation fell to 0.044 m (2026-12-02). Run it with
/// `cargo test -p swarmctl-harness --test flights real_ardupilot -- --ignored --nocapture`.
#[ignore = "fails today: ArduCopter tracking (p95 ~1 m) breaks separation; see the doc comment"]
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn formation_change_on_real_arducopter() {
    let (mission, plan) = mission_for_ardupilot();
    let origin = mission.geo_origin.expect("geo origin");
    let mut vehicles = Vec::new();
    let mut links = Vec::new();
    let mut truth = Vec::new();
    let stop = Instant::now() + TEST_LIMIT;
    for (n, (_, d)) in mission.drones().enumerate() {
        let pad = mission.pad_ground_m(d);
        let home = frames::geodetic_at(&origin, pad);
        vehicles.push(boot(n as u16, &home));
        let samples = Arc::new(Mutex::new(Vec::new()));
        truth.push(samples.clone());
        tokio::spawn(read_truth(n as u16, samples, stop));
        links.push(fly::VehicleLink {
            endpoint: d.endpoint.clone().expect("endpoint"),
            system_id: d.system_id.expect("system id"),
        });
    }
    // The TCP ports open a moment after the processes start (SERIAL2 is probed, so
    // the ports swarmctl and the truth reader use stay untouched).
    for n in 0..vehicles.len() as u16 {
        let port = SERIAL1_BASE + 1 + 10 * n;
        let deadline = Instant::now() + Duration::from_secs(30);
        while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                Instant::now() < deadline,
                "instance {n} never opened its ports"
            );
            tokio::time::sleep(Duration::from_millis(200)).await;
        }
    }
    let mut options = fly::FlyOptions::new(links);
    options.ready_timeout = Duration::from_secs(120);
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let log = tokio::time::timeout(TEST_LIMIT, fly::fly(&mission, &plan, &options, abort_rx))
        .await
        .expect("flight within the test's time limit")
        .expect("flight starts");
    let tracks: Vec<Vec<TruthSample>> = truth.iter().map(|t| t.lock().unwrap().clone()).collect();
    drop(vehicles);
    let s = &log.summary;
    for line in s.lines() {
        eprintln!("{line}");
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
    let (truth_min_m, truth_speed) = truth_figures(&origin, &tracks);
    eprintln!(
        "  truth                min separation {truth_min_m:.3} m, top speed {truth_speed:.2} m/s ({} samples)",
        tracks.iter().map(Vec::len).sum::<usize>()
    );
    assert!(tracks.iter().all(|t| t.len() > 100), "truth was read");
    for d in &log.drones {
        assert_eq!(d.frame, fly::placement::FrameFix::GpsOrigin, "{}", d.id);
    }
    let limits = &mission.limits;
    assert!(s.safety_held, "telemetry separation {}", s.min_separation_m);
    assert!(
        truth_min_m >= limits.safety_distance_m,
        "true separation {truth_min_m:.3} m < {} m",
        limits.safety_distance_m
    );
    assert!(s.speed_held, "telemetry speed {}", s.max_speed_mps);
    assert!(s.completed, "completed");
    assert!(s.max_final_distance_to_goal_m <= 0.2, "at the goals");
}
