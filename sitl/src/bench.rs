//! `--bench`: many vehicles in real time with an in-process ground station
//! receiving all their telemetry; reports CPU use (getrusage) and missed ticks.

use crate::config::VehicleConfig;
use crate::swarm::spawn;
use anyhow::Context;
use std::net::{IpAddr, SocketAddr};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// User plus system CPU time this process has used so far.
fn process_cpu_time() -> Duration {
    // SAFETY: getrusage only writes into the zero-initialised struct we pass.
    let usage = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_SELF, &mut usage);
        usage
    };
    let tv = |t: libc::timeval| Duration::new(t.tv_sec as u64, (t.tv_usec as u32) * 1000);
    tv(usage.ru_utime) + tv(usage.ru_stime)
}

/// Runs the benchmark for `seconds` and prints the figures.
pub async fn run(
    bind: IpAddr,
    mut configs: Vec<VehicleConfig>,
    physics_hz: f64,
    telemetry_hz: f64,
    seconds: f64,
) -> anyhow::Result<()> {
    let sink = tokio::net::UdpSocket::bind(SocketAddr::new(bind, 0))
        .await
        .context("bind the ground-station sink")?;
    let sink_port = sink.local_addr()?.port();
    let received = Arc::new(AtomicU64::new(0));
    let counter = received.clone();
    let sink_task = tokio::spawn(async move {
        let mut buffer = [0u8; 2048];
        while sink.recv_from(&mut buffer).await.is_ok() {
            counter.fetch_add(1, Ordering::Relaxed);
        }
    });
    for c in &mut configs {
        c.gcs_stream_port = Some(sink_port);
        c.port = 0;
    }
    let vehicles = configs.len();
    let swarm = spawn(bind, configs, physics_hz, telemetry_hz).await?;
    // Let sockets and schedules settle for a second before measuring.
    tokio::time::sleep(Duration::from_secs(1)).await;
    let ticks_before = swarm.tick_stats();
    let received_before = received.load(Ordering::Relaxed);
    let cpu_before = process_cpu_time();
    let wall_start = Instant::now();
    tokio::time::sleep(Duration::try_from_secs_f64(seconds).context("bad --bench duration")?).await;
    let wall = wall_start.elapsed();
    let cpu = process_cpu_time() - cpu_before;
    let ticks = swarm.tick_stats();
    let datagrams = received.load(Ordering::Relaxed) - received_before;
    swarm.shutdown().await;
    sink_task.abort();

    let expected_steps = wall.as_secs_f64() * physics_hz;
    let steps = ticks.steps - ticks_before.steps;
    println!(
        "benchmark: {vehicles} vehicles, physics {physics_hz} Hz, telemetry {telemetry_hz} Hz, {:.1} s",
        wall.as_secs_f64()
    );
    println!(
        "  cpu            {:.1} % of one core ({:.2} s cpu in {:.2} s wall)",
        100.0 * cpu.as_secs_f64() / wall.as_secs_f64(),
        cpu.as_secs_f64(),
        wall.as_secs_f64()
    );
    println!(
        "  physics steps  {steps} of {expected_steps:.0} expected ({:.2} %)",
        100.0 * steps as f64 / expected_steps
    );
    println!("  ticks          {}", ticks.ticks - ticks_before.ticks);
    println!(
        "  missed ticks   {} (steps late by >= 1 period, caught up)",
        ticks.missed_ticks - ticks_before.missed_ticks
    );
    println!(
        "  skipped steps  {}",
        ticks.skipped_steps - ticks_before.skipped_steps
    );
    println!(
        "  telemetry      {datagrams} datagrams received by the sink ({:.0}/s)",
        datagrams as f64 / wall.as_secs_f64()
    );
    Ok(())
}
