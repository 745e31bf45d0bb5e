//! The truth watcher: a thread of its own that samples the simulator's true
//! positions and the process's resources while the flight runs.

use super::PEAK_WINDOW_S;
use crate::resources;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use swarmctl::world::Separation;
use swarmctl_sitl::{Swarm, truth};

/// How often the watcher samples true positions.
const TRUTH_PERIOD: Duration = Duration::from_millis(20);
/// How often it samples memory, open files and CPU.
const RESOURCE_PERIOD: Duration = Duration::from_secs(1);

/// What the watcher saw.
pub(super) struct Watched {
    /// Smallest true distance between two airborne vehicles, metres.
    pub min_separation_m: f64,
    /// Under an ellipsoid, the smallest true scaled separation of two airborne
    /// vehicles (separated at 1 or more).
    pub min_scaled_separation: Option<f64>,
    /// Highest resident memory sampled, bytes.
    pub max_rss_bytes: u64,
    /// Most open file descriptors sampled.
    pub max_fds: usize,
    /// The watcher's own CPU, seconds (0 where unknown).
    pub own_cpu_s: f64,
    /// Busiest [`PEAK_WINDOW_S`] s of the whole process, CPU s per wall s.
    pub peak_total_share: f64,
    /// Busiest [`PEAK_WINDOW_S`] s of the controller, CPU s per wall s.
    pub peak_controller_share: f64,
}

/// One resource sample: (wall s, process CPU s, SITL CPU s, watcher CPU s).
type CpuSample = [f64; 4];

/// Until `done`: the smallest true distance between two airborne vehicles (every
/// [`TRUTH_PERIOD`]), and every [`RESOURCE_PERIOD`] memory, open files and CPU.
pub(super) fn watch(swarm: &Swarm, ellipsoid: Option<Separation>, done: &AtomicBool) -> Watched {
    let own0 = resources::this_thread_cpu_s();
    let start = Instant::now();
    let mut min_m = f64::INFINITY;
    let mut min_scaled = ellipsoid.map(|_| f64::INFINITY);
    let mut max_rss_bytes = 0;
    let mut max_fds = 0;
    let mut samples: Vec<CpuSample> = Vec::new();
    let mut next_sample = start;
    let mut airborne: Vec<[f32; 3]> = Vec::with_capacity(swarm.len());
    while !done.load(Ordering::Relaxed) {
        truth::airborne_positions(swarm, &mut airborne);
        min_m = min_m.min(truth::min_separation_m(&airborne));
        if let (Some(e), Some(min)) = (&ellipsoid, &mut min_scaled) {
            *min = min.min(truth::min_scaled_separation(&airborne, |d| e.scaled(d)));
        }
        if Instant::now() >= next_sample {
            next_sample += RESOURCE_PERIOD;
            let usage = resources::process_resources();
            max_rss_bytes = max_rss_bytes.max(usage.rss_bytes);
            max_fds = max_fds.max(usage.open_fds);
            samples.extend(cpu_sample(start));
        }
        std::thread::sleep(TRUTH_PERIOD);
    }
    let (peak_total_share, peak_controller_share) = peak_shares(&samples);
    Watched {
        min_separation_m: min_m,
        min_scaled_separation: min_scaled,
        max_rss_bytes,
        max_fds,
        own_cpu_s: cpu_since_s(own0, resources::this_thread_cpu_s()),
        peak_total_share,
        peak_controller_share,
    }
}

/// CPU now, by thread kind; `None` where it cannot be read (not Linux), so
/// windows never mix known and unknown figures.
fn cpu_sample(start: Instant) -> Option<CpuSample> {
    Some([
        start.elapsed().as_secs_f64(),
        resources::process_cpu_s()?,
        resources::threads_named_cpu_s(super::SITL_THREAD)?,
        resources::this_thread_cpu_s()?,
    ])
}

/// The busiest [`PEAK_WINDOW_S`] stretch of the whole process and of the
/// controller (the process less the SITL and the watcher), CPU s per wall s.
fn peak_shares(samples: &[CpuSample]) -> (f64, f64) {
    let (mut peak_total_share, mut peak_controller_share) = (0.0f64, 0.0f64);
    for w in samples.windows(PEAK_WINDOW_S + 1) {
        let (a, b) = (w[0], w[PEAK_WINDOW_S]);
        let wall_s = b[0] - a[0];
        if wall_s > 0.0 {
            let total = b[1] - a[1];
            let controller = total - (b[2] - a[2]) - (b[3] - a[3]);
            peak_total_share = peak_total_share.max(total / wall_s);
            peak_controller_share = peak_controller_share.max(controller / wall_s);
        }
    }
    (peak_total_share, peak_controller_share)
}

/// CPU seconds between two readings; 0 where either is unknown (not Linux), as
/// the report's CPU rows promise.
pub(super) fn cpu_since_s(before: Option<f64>, after: Option<f64>) -> f64 {
    match (before, after) {
        (Some(before), Some(after)) => after - before,
        _ => 0.0,
    }
}
