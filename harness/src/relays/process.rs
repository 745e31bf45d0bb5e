//! One `swarmctl relay --sitl` child: started with its share of the drones,
//! stopped with SIGTERM, and read: what it wrote to its `--report` file, and
//! its CPU time and peak memory as the kernel counted them when it exited.

use crate::HarnessError;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use swarmctl_sitl::Flavour;

/// A relay stops within this long of SIGTERM, or is killed.
const STOP_TIMEOUT: Duration = Duration::from_secs(30);

/// What one relay carried and cost.
#[derive(Debug, Default, serde::Deserialize)]
pub struct RelayReport {
    /// The relay's name.
    pub relay: String,
    /// Drones it served.
    pub drones: usize,
    /// Setpoint intervals as its vehicles received them, milliseconds.
    pub setpoint_interval_ms: Option<RelayIntervals>,
    /// CPU time (user + system) over the process's lifetime, seconds.
    #[serde(skip)]
    pub cpu_s: Option<f64>,
    /// Peak resident memory of the process, bytes.
    #[serde(skip)]
    pub peak_rss_bytes: Option<u64>,
}

/// Setpoint intervals at one relay's vehicles, milliseconds.
#[derive(Debug, Default, serde::Deserialize)]
pub struct RelayIntervals {
    /// Intervals measured.
    pub count: u64,
    /// Median.
    pub p50_ms: f64,
    /// 99th percentile.
    pub p99_ms: f64,
    /// Longest.
    pub max_ms: f64,
}

/// A running relay process.
pub(super) struct RelayProcess {
    child: Child,
    report: PathBuf,
}

impl RelayProcess {
    /// Starts relay `k` (named `r{k+1}`) of `mission` for `drones`, on bundled
    /// vehicles imitating `flavour`, connecting to the controller at `port`.
    pub(super) fn start(
        swarmctl: &Path,
        mission: &Path,
        dir: &Path,
        k: usize,
        drones: &[String],
        port: u16,
        flavour: Flavour,
    ) -> Result<RelayProcess, HarnessError> {
        let report = dir.join(format!("relay-{k}.json"));
        let autopilot = match flavour {
            Flavour::ArduPilot => "ardupilot",
            Flavour::Px4 => "px4",
        };
        let child = Command::new(swarmctl)
            .arg("relay")
            .arg(mission)
            .args([
                "--name",
                &format!("r{}", k + 1),
                "--sitl",
                "--autopilot",
                autopilot,
            ])
            .args(["--drones", &drones.join(",")])
            .args(["--connect", &format!("tcp/127.0.0.1:{port}")])
            .arg("--report")
            .arg(&report)
            .stdout(Stdio::null())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|source| HarnessError::Io {
                what: format!("cannot start a relay process ({})", swarmctl.display()),
                source,
            })?;
        Ok(RelayProcess { child, report })
    }

    /// SIGTERM, wait (bounded), and read what the relay reported and used.
    pub(super) fn stop(mut self) -> Result<RelayReport, HarnessError> {
        let pid = self.child.id() as libc::pid_t;
        // SAFETY: kill(2) on our own child's pid, not yet reaped.
        unsafe {
            libc::kill(pid, libc::SIGTERM);
        }
        let deadline = Instant::now() + STOP_TIMEOUT;
        let usage = loop {
            match reap(pid) {
                Ok(Some(usage)) => break usage,
                Ok(None) if Instant::now() <= deadline => {
                    std::thread::sleep(Duration::from_millis(50));
                }
                Ok(None) => {
                    let _ = self.child.kill();
                    let _ = self.child.wait();
                    return Err(HarnessError::RelayDidNotStop {
                        timeout: STOP_TIMEOUT,
                    });
                }
                Err(source) => {
                    return Err(HarnessError::Io {
                        what: "waiting for a relay process".into(),
                        source,
                    });
                }
            }
        };
        let text = std::fs::read_to_string(&self.report).map_err(|source| HarnessError::Io {
            what: format!("the relay wrote no report to {}", self.report.display()),
            source,
        })?;
        let mut report: RelayReport =
            serde_json::from_str(&text).map_err(|source| HarnessError::RelayReport {
                path: self.report.clone(),
                source,
            })?;
        report.cpu_s = Some(usage.cpu_s);
        report.peak_rss_bytes = Some(usage.peak_rss_bytes);
        Ok(report)
    }
}

impl Drop for RelayProcess {
    fn drop(&mut self) {
        // Reaped already (stopped): try_wait fails, and nothing is left to kill.
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// What an exited child used over its lifetime, as the kernel counted it.
#[derive(Debug, Clone, Copy)]
struct Usage {
    /// User + system CPU time, seconds.
    cpu_s: f64,
    /// Peak resident memory, bytes.
    peak_rss_bytes: u64,
}

/// Reaps child `pid` if it has exited, with what it used; `None` while it runs.
fn reap(pid: libc::pid_t) -> std::io::Result<Option<Usage>> {
    let mut status = 0;
    // SAFETY: `rusage` is plain integers, so all zeroes is a valid value.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: wait4 on our own child's pid, with pointers to live, writable
    // values that it only writes into.
    let reaped = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
    match reaped {
        0 => Ok(None),
        -1 => Err(std::io::Error::last_os_error()),
        _ => {
            let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
            let cpu_s = seconds(usage.ru_utime) + seconds(usage.ru_stime);
            // Linux gives the peak resident set in kibibytes.
            let peak_rss_bytes = u64::try_from(usage.ru_maxrss).unwrap_or(0) * 1024;
            Ok(Some(Usage {
                cpu_s,
                peak_rss_bytes,
            }))
        }
    }
}
