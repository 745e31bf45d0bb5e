//! Cost of recording a flight: 100 drones reporting at 20 Hz, paced in real time,
//! fed to the flight `Recorder` writing an `.rrd` file.
//!
//! Reports the recorder thread's CPU time and the CPU of everything recording
//! adds to the process (recorder thread + rerun's batcher and file writer: the
//! process total minus the feeding thread), both as a share of one core over the
//! flight's wall time. Run with `cargo bench --bench viz_recorder`;
//! `VIZ_BENCH_SECONDS` (default 30) sets the flight length, `VIZ_BENCH_FLUSH_S`
//! the recorder's flush period (default: a file's, 5 s). This is the recorder
//! alone on synthetic telemetry; `benches/fly_record.rs` weighs it against a
//! real flight.

use std::time::{Duration, Instant};
use swarmctl_harness::resources;
use swarmctl_viz::{Drone, FlightSample, Group, Recorder, RecorderOptions, Scene, Sink};

const DRONES: usize = 100;
const RATE_HZ: f64 = 20.0;

/// What the benchmark could not do (open the temp dir, start or finish the recorder).
type BenchResult<T> = Result<T, Box<dyn std::error::Error>>;

/// User + system CPU of the whole process, seconds.
fn process_cpu_s() -> BenchResult<f64> {
    resources::process_cpu_s()
        .ok_or_else(|| "cannot read the process's CPU time (Linux only)".into())
}

/// User + system CPU of the calling (feeding) thread, seconds.
fn feeder_cpu_s() -> BenchResult<f64> {
    resources::this_thread_cpu_s()
        .ok_or_else(|| "cannot read the thread's CPU time (Linux only)".into())
}

fn scene() -> Scene {
    Scene {
        name: "bench-100".into(),
        voxel_size_m: 1.0,
        safety_distance_m: 0.25,
        groups: (0..5)
            .map(|i| Group {
                name: format!("g{i}"),
                color_rgb: Group::palette(i),
            })
            .collect(),
        drones: (0..DRONES)
            .map(|i| Drone {
                id: format!("d{i:03}"),
                group: i % 5,
                ..Drone::default()
            })
            .collect(),
        ..Scene::default()
    }
}

/// Drone `i` circles its own centre on a 10 x 10 grid.
fn position(i: usize, t_s: f64) -> [f64; 3] {
    let (cx, cy) = ((i % 10) as f64 * 2.0, (i / 10) as f64 * 2.0);
    let phase = t_s * 0.5 + i as f64;
    [
        cx + 0.5 * phase.cos(),
        cy + 0.5 * phase.sin(),
        2.0 + 0.1 * phase.sin(),
    ]
}

fn main() -> BenchResult<()> {
    let seconds: f64 = std::env::var("VIZ_BENCH_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(30.0);
    let dir = tempfile::tempdir()?;
    let path = dir.path().join("bench.rrd");
    let process_before = process_cpu_s()?;
    let feeder_before = feeder_cpu_s()?;
    let mut options = RecorderOptions::for_sink(&Sink::File(path.clone()));
    if let Some(flush_s) = std::env::var("VIZ_BENCH_FLUSH_S")
        .ok()
        .and_then(|s| s.parse().ok())
    {
        options.flush_period_s = flush_s;
    }
    println!("  flush period         {} s", options.flush_period_s);
    let recorder = Recorder::start(&Sink::File(path.clone()), &scene(), &[], options)?;
    let handle = recorder.handle();
    let started = Instant::now();
    let ticks = (seconds * RATE_HZ).round() as u64;
    let mut dropped = 0u64;
    let mut sending = Duration::ZERO;
    let mut batch = Vec::with_capacity(DRONES);
    for k in 0..ticks {
        let t_s = k as f64 / RATE_HZ;
        batch.clear();
        batch.extend((0..DRONES).map(|i| FlightSample {
            drone: i,
            t_s,
            position_m: position(i, t_s),
        }));
        // What the executor's side pays: the non-blocking hand-over alone.
        let sent = Instant::now();
        for &sample in &batch {
            if !handle.try_sample(sample) {
                dropped += 1;
            }
        }
        sending += sent.elapsed();
        let next = started + Duration::from_secs_f64((k + 1) as f64 / RATE_HZ);
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
    let flight_wall_s = started.elapsed().as_secs_f64();
    // The recorder thread's own CPU, read while it still runs (it ends at finish).
    let recorder_thread_s =
        resources::threads_named_cpu_s(swarmctl_viz::RECORDER_THREAD).unwrap_or(f64::NAN);
    drop(handle);
    let stats = recorder.finish()?;
    let total_wall_s = started.elapsed().as_secs_f64();
    let feeder_s = feeder_cpu_s()? - feeder_before;
    let recording_cpu_s = process_cpu_s()? - process_before - feeder_s;
    let size_mb = std::fs::metadata(&path).map_or(0.0, |m| m.len() as f64 / 1e6);
    println!(
        "viz_recorder: {DRONES} drones x {RATE_HZ} Hz for {flight_wall_s:.1} s (finish took {:.2} s)",
        total_wall_s - flight_wall_s
    );
    println!(
        "  samples logged       {} (dropped {}, {} at the sender)",
        stats.samples_logged, stats.samples_dropped, dropped
    );
    println!(
        "  recorder thread CPU  {:.3} s = {:.2}% of one core",
        recorder_thread_s,
        100.0 * recorder_thread_s / flight_wall_s
    );
    println!(
        "  all recording CPU    {recording_cpu_s:.3} s = {:.2}% of one core (recorder + rerun threads)",
        100.0 * recording_cpu_s / flight_wall_s
    );
    println!("  feeder thread CPU    {feeder_s:.3} s");
    println!(
        "  try_sample           {:.0} ns per sample (the sender's cost, wall time)",
        sending.as_secs_f64() * 1e9 / (ticks as f64 * DRONES as f64)
    );
    println!("  recording size       {size_mb:.1} MB");
    Ok(())
}
