//! Reproducible benchmark suites behind `swarmctl bench`.
//!
//! Each suite is a list of seeded instances; the report gives medians and maxima, so
//! a noisy shared machine shows as spread rather than as a wrong figure.

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
