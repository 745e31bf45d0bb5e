//! Reproducible benchmark suites behind `swarmctl bench`.
//!
//! Each suite is a list of seeded instances; the report gives medians and maxima, so
//! a noisy shared machine shows as spread rather than as a wrong figure.

pub mod bundled_sitl;
pub mod fault_matrix;
pub mod load;
mod plan_suite;

pub use load::{LoadOptions, LoadReport, run_load};
pub use plan_suite::{PlanSuite, PlanSuiteReport, run_plan_suite};

/// Median of a non-empty slice (the mean of the middle two for even lengths).
pub fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => sorted[n / 2],
        _ => (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0,
    }
}

/// The process's peak resident memory in bytes (Linux `VmHWM`), if known.
pub fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// What the process holds right now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ProcessResources {
    /// Resident memory (Linux `VmRSS`), bytes; 0 where unknown.
    pub rss_bytes: u64,
    /// Open file descriptors (entries of `/proc/self/fd`); 0 where unknown.
    pub open_fds: usize,
}

/// Resident memory and open file descriptors of this process (Linux).
pub fn process_resources() -> ProcessResources {
    let rss_bytes = std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|status| {
            let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
            line.split_whitespace().nth(1)?.parse::<u64>().ok()
        })
        .map_or(0, |kib| kib * 1024);
    let open_fds = std::fs::read_dir("/proc/self/fd").map_or(0, |dir| dir.count());
    ProcessResources {
        rss_bytes,
        open_fds,
    }
}

/// Smallest distance between two airborne vehicles of a bundled-SITL swarm right
/// now, from the simulator's true positions (∞ with fewer than two in the air).
/// `airborne` is a reused buffer; afterwards it holds the airborne positions (NED).
pub fn true_min_separation_m(swarm: &swarmctl_sitl::Swarm, airborne: &mut Vec<[f32; 3]>) -> f64 {
    /// Below this height a vehicle is on the ground.
    const AIRBORNE_M: f32 = 0.1;
    airborne.clear();
    airborne.extend(
        (0..swarm.len())
            .map(|i| swarm.snapshot(i).position_ned_m)
            .filter(|p| -p[2] > AIRBORNE_M),
    );
    let mut min_d2 = f32::INFINITY;
    for (k, a) in airborne.iter().enumerate() {
        for b in &airborne[k + 1..] {
            let d2 = (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2);
            min_d2 = min_d2.min(d2);
        }
    }
    f64::from(min_d2.sqrt())
}
