//! `swarmctl fly --via zenoh` through `swarmctl relay` processes on loopback:
//! the formation change flown by a controller and two relays, each a process of
//! its own with its own bundled vehicles, separation measured from the
//! simulators' truth (which the relays publish); and a relay killed mid-flight,
//! which must read as a link loss of exactly its drones.

use std::io::{BufRead, BufReader};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};
use swarmctl::fly::FlightLog;
use swarmctl_relay::truth::TruthWatch;
use swarmctl_relay::{KeySpace, ZenohEndpoints};

/// The formation change's drones, split between two relays.
const NORTH: &str = "b1,b2,r1,r2";
const SOUTH: &str = "b3,b4,r3,r4";
/// Every wait here is bounded: a whole flight takes under a minute.
const FLIGHT_LIMIT: Duration = Duration::from_secs(240);

fn binary() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_swarmctl"))
}

fn mission() -> PathBuf {
    crate::support::repo_root().join("missions/formation-change.yaml")
}

/// A loopback port nothing listens on right now.
fn free_port() -> u16 {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    listener.local_addr().unwrap().port()
}

/// A child process killed (and reaped) when dropped, whatever the test did.
struct Process {
    name: String,
    child: Child,
    lines: mpsc::Receiver<String>,
}

impl Process {
    /// Starts `args` with stdout and stderr read line by line (and echoed, so
    /// a failing test shows them).
    fn start(name: &str, args: &[&str]) -> Process {
        let mut child = Command::new(binary())
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let (tx, lines) = mpsc::channel();
        let stdout = child.stdout.take().unwrap();
        let stderr = child.stderr.take().unwrap();
        echo(name, stdout, tx.clone());
        echo(name, stderr, tx);
        Process {
            name: name.to_string(),
            child,
            lines,
        }
    }

    /// Waits (at most `within`) for a line containing `text`.
    fn expect_line(&self, text: &str, within: Duration) -> String {
        let deadline = Instant::now() + within;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) if line.contains(text) => return line,
                Ok(_) => {}
                Err(_) => panic!("{}: no line with {text:?} within {within:?}", self.name),
            }
        }
    }

    /// Waits (at most `within`) for the process to exit.
    fn wait(&mut self, within: Duration) -> ExitStatus {
        let deadline = Instant::now() + within;
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return status;
            }
            assert!(
                Instant::now() < deadline,
                "{} still running after {within:?}",
                self.name
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// SIGTERM, as a service manager stops a relay, then wait for it.
    fn terminate(&mut self) -> ExitStatus {
        // SAFETY: kill(2) on our own child's pid; no memory is involved.
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM);
        }
        self.wait(Duration::from_secs(20))
    }

    /// SIGKILL: the relay's machine or process dies without a word.
    fn kill_hard(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Process {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Echoes `stream`'s lines as `name: line` and sends them to `tx`.
fn echo(name: &str, stream: impl std::io::Read + Send + 'static, tx: mpsc::Sender<String>) {
    let name = name.to_string();
    std::thread::spawn(move || {
        for line in BufReader::new(stream).lines().map_while(Result::ok) {
            eprintln!("{name}: {line}");
            // The test may have stopped listening; the echo goes on.
            let _ = tx.send(line);
        }
    });
}

/// A relay serving `drones` on the bundled SITL, connecting to the controller at `port`.
fn relay(name: &str, drones: &str, port: u16, report: &Path) -> Process {
    let connect = format!("tcp/127.0.0.1:{port}");
    let p = Process::start(
        name,
        &[
            "relay",
            mission().to_str().unwrap(),
            "--name",
            name,
            "--drones",
            drones,
            "--sitl",
            "--connect",
            &connect,
            "--report",
            report.to_str().unwrap(),
        ],
    );
    p.expect_line("serving 4 drones", Duration::from_secs(30));
    p
}

/// The controller flying the formation change through the relays, listening at `port`.
fn controller(port: u16, log: &Path) -> Process {
    let listen = format!("tcp/127.0.0.1:{port}");
    Process::start(
        "controller",
        &[
            "fly",
            mission().to_str().unwrap(),
            "--via",
            "zenoh",
            "--zenoh-listen",
            &listen,
            "--plain",
            "--log",
            log.to_str().unwrap(),
        ],
    )
}

/// A truth watch on the controller's Zenoh endpoint (a session of the test's
/// own, routed to the relays by the controller).
async fn watch_truth(port: u16) -> (swarmctl_relay::zenoh::Session, TruthWatch) {
    // A client's session opens once a router (the controller) answers.
    let endpoints = ZenohEndpoints {
        role: swarmctl_relay::Role::Client,
        listen: Vec::new(),
        connect: vec![format!("tcp/127.0.0.1:{port}")],
    };
    let session = tokio::time::timeout(Duration::from_secs(30), endpoints.open())
        .await
        .expect("the controller's Zenoh endpoint answers")
        .unwrap();
    let watch = TruthWatch::start(&session, &KeySpace::new("formation-change"), None, 50.0)
        .await
        .unwrap();
    (session, watch)
}

/// A controller, a test's truth watch, and relays north and south, started in
/// that order on a fresh port; everything in `dir`.
struct Topology {
    dir: tempfile::TempDir,
    log: PathBuf,
    fly: Process,
    _session: swarmctl_relay::zenoh::Session,
    truth: TruthWatch,
    north: Process,
    south: Process,
}

impl Topology {
    async fn start() -> Topology {
        let dir = tempfile::tempdir().unwrap();
        let port = free_port();
        let log = dir.path().join("flight.json");
        let fly = controller(port, &log);
        let (_session, truth) = watch_truth(port).await;
        let north = relay("north", NORTH, port, &dir.path().join("north.json"));
        let south = relay("south", SOUTH, port, &dir.path().join("south.json"));
        Topology {
            dir,
            log,
            fly,
            _session,
            truth,
            north,
            south,
        }
    }
}

fn read_log(path: &Path) -> FlightLog {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The whole topology on loopback: controller and two relays in separate
/// processes. The flight completes, keeps the 0.4 m safety distance and the
/// 1 m/s speed limit in the simulators' truth, and the log names each drone's relay.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_formation_change_flies_through_two_relays() {
    let mut t = Topology::start().await;
    let status = tokio::task::block_in_place(|| t.fly.wait(FLIGHT_LIMIT));
    let truth = t.truth.report();
    assert!(t.north.terminate().success() && t.south.terminate().success());
    assert!(status.success(), "the flight did not complete: {status}");

    let log = read_log(&t.log);
    let s = &log.summary;
    assert!(s.completed && s.safety_held && s.speed_held, "{s:?}");
    for d in &log.drones {
        let relay = if NORTH.split(',').any(|n| n == d.id) {
            "north"
        } else {
            "south"
        };
        assert_eq!(d.endpoint, format!("zenoh relay {relay}"), "{}", d.id);
    }
    assert!(truth.comparisons > 100 && truth.vehicles == 8, "{truth:?}");
    assert!(truth.min_separation_m >= 0.4, "truth {truth:?}");
    assert!(truth.top_speed_mps <= 1.0 * 1.05, "truth {truth:?}");
    for relay in ["north", "south"] {
        let report: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(t.dir.path().join(format!("{relay}.json"))).unwrap(),
        )
        .unwrap();
        assert!(
            report["frames_to_vehicles"].as_u64().unwrap() > 1000,
            "{report}"
        );
        assert!(
            report["setpoint_interval_ms"]["count"].as_u64().unwrap() > 1000,
            "{report}"
        );
    }
}

/// Relay south dies without a word (SIGKILL) mid-flight: each of its drones is
/// reported lost at once with the relay named, the flight goes on for north's
/// drones (replanned around the silent ones, which the simulator keeps hovering
/// in the truth as their failsafe would), and nobody comes closer than the
/// safety distance.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_relay_killed_mid_flight_is_a_link_loss_of_its_drones() {
    let mut t = Topology::start().await;
    // The plan clock starts once every drone hovers over its pad; the first
    // status line comes a few seconds into plan execution.
    tokio::task::block_in_place(|| {
        t.fly
            .expect_line(" flying  progress", Duration::from_secs(90));
        std::thread::sleep(Duration::from_secs(6));
    });
    t.south.kill_hard();
    let status = tokio::task::block_in_place(|| t.fly.wait(FLIGHT_LIMIT));
    let truth = t.truth.report();
    assert!(t.north.terminate().success());
    let log = read_log(&t.log);
    for id in SOUTH.split(',') {
        assert!(
            log.events.iter().any(|e| e.drone.as_deref() == Some(id)
                && e.message.contains("link lost: relay south left")),
            "{id}'s loss names its relay: {:#?}",
            log.events
        );
    }
    for id in NORTH.split(',') {
        assert!(
            !log.events
                .iter()
                .any(|e| e.drone.as_deref() == Some(id) && e.message.contains("link lost")),
            "{id} kept its link"
        );
    }
    let s = &log.summary;
    assert!(s.safety_held, "{s:?}");
    let mut lost = s.lost.clone();
    lost.sort();
    assert_eq!(lost, ["b3", "b4", "r3", "r4"], "{s:?}");
    assert!(truth.min_separation_m >= 0.4, "truth {truth:?}");
    // The flight ends on its own (completed or not is the replanner's to say);
    // what matters is that it ended and said what happened.
    assert!(status.code().is_some(), "{status}");
}

/// Nobody serves the drones: `fly` says so before arming anything, naming the
/// drones, and exits 1; a relay that does not know its drones says how to tell it.
#[test]
fn missing_relays_and_unknown_shares_are_refused_with_the_fix() {
    let port = free_port();
    let out = Command::new(binary())
        .args([
            "fly",
            mission().to_str().unwrap(),
            "--via",
            "zenoh",
            "--relay-wait",
            "1",
        ])
        .args(["--zenoh-listen", &format!("tcp/127.0.0.1:{port}")])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("no relay serves 8 of the 8 drones after 1 s: b1, b2")
            && stderr.contains("no relay seen at all"),
        "{stderr}"
    );
    let out = Command::new(binary())
        .args([
            "relay",
            mission().to_str().unwrap(),
            "--name",
            "north",
            "--sitl",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(
            "no link.relays section, so relay north does not know its drones: give --drones"
        ),
        "{stderr}"
    );
}
