//! One solver run as a child process, bounded in time: its wall time, its peak
//! resident memory and how it ended.
//!
//! Every solver, swarmctl included, is measured the same way, as a whole process
//! from `exec` to exit: what a user waits for. Peak memory is the child's own
//! `ru_maxrss` from `wait4` (Linux), so it is the solver's, not this harness's.

use crate::HarnessError;
use std::fs::File;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How often a running child is looked at: the wall time's resolution.
const POLL: Duration = Duration::from_millis(5);

/// How a bounded run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exit {
    /// It exited by itself with this status code.
    Code(i32),
    /// A signal ended it (not ours).
    Signal(i32),
    /// It was still running at its limit and was killed.
    TimedOut,
}

/// What one run of a child cost.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChildRun {
    /// From spawning to its end (or to the kill at the limit), seconds.
    pub wall_s: f64,
    /// Its peak resident memory, bytes (`None` where the platform does not say).
    pub peak_rss_bytes: Option<u64>,
    /// How it ended.
    pub exit: Exit,
}

impl ChildRun {
    /// Whether it exited by itself with status 0.
    pub fn succeeded(&self) -> bool {
        self.exit == Exit::Code(0)
    }
}

/// Runs `command` with stdout and stderr to `log`, killing it at `limit`.
pub fn run_bounded(
    command: &mut Command,
    limit: Duration,
    log: &Path,
) -> Result<ChildRun, HarnessError> {
    let io = |what: String| move |source| HarnessError::Io { what, source };
    let out = File::create(log).map_err(io(format!("creating {}", log.display())))?;
    let err = out
        .try_clone()
        .map_err(io(format!("sharing {}", log.display())))?;
    let program = command.get_program().to_string_lossy().into_owned();
    let began = Instant::now();
    let child = command
        .stdin(Stdio::null())
        .stdout(out)
        .stderr(err)
        .spawn()
        .map_err(io(format!("starting {program}")))?;
    wait_bounded(child, began, limit).map_err(io(format!("waiting for {program}")))
}

/// Waits for `child` (spawned at `began`) until `limit`, then kills it; reaps it
/// with `wait4` to read its own peak memory.
#[cfg(target_os = "linux")]
fn wait_bounded(
    child: std::process::Child,
    began: Instant,
    limit: Duration,
) -> std::io::Result<ChildRun> {
    let pid = libc::pid_t::try_from(child.id()).map_err(std::io::Error::other)?;
    let mut timed_out = false;
    loop {
        let flags = if timed_out { 0 } else { libc::WNOHANG };
        let mut status: libc::c_int = 0;
        // SAFETY: `rusage` is plain integers, so all zeroes is a valid value.
        let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
        // SAFETY: `pid` is our own child, not yet reaped (std's `Child` never
        // waits unless asked, and it is not asked); both pointers are to live,
        // writable locals that wait4 only writes into.
        let reaped = unsafe { libc::wait4(pid, &mut status, flags, &mut usage) };
        if reaped == pid {
            let wall_s = began.elapsed().as_secs_f64();
            let exit = if timed_out {
                Exit::TimedOut
            } else if libc::WIFEXITED(status) {
                Exit::Code(libc::WEXITSTATUS(status))
            } else {
                Exit::Signal(libc::WTERMSIG(status))
            };
            // Linux gives ru_maxrss in kibibytes.
            let peak_rss_bytes = u64::try_from(usage.ru_maxrss).ok().map(|kib| kib * 1024);
            return Ok(ChildRun {
                wall_s,
                peak_rss_bytes,
                exit,
            });
        }
        if reaped < 0 {
            let error = std::io::Error::last_os_error();
            if error.kind() != std::io::ErrorKind::Interrupted {
                return Err(error);
            }
            continue;
        }
        if began.elapsed() >= limit {
            timed_out = true;
            // SAFETY: kill has no memory effects; `pid` is our unreaped child,
            // so the number cannot have been given to another process.
            unsafe { libc::kill(pid, libc::SIGKILL) };
            continue;
        }
        std::thread::sleep(POLL);
    }
}

/// Waits for `child` (spawned at `began`) until `limit`, then kills it; peak
/// memory is not known off Linux.
#[cfg(not(target_os = "linux"))]
fn wait_bounded(
    mut child: std::process::Child,
    began: Instant,
    limit: Duration,
) -> std::io::Result<ChildRun> {
    loop {
        if let Some(status) = child.try_wait()? {
            let exit = status.code().map_or(Exit::Signal(0), Exit::Code);
            return Ok(ChildRun {
                wall_s: began.elapsed().as_secs_f64(),
                peak_rss_bytes: None,
                exit,
            });
        }
        if began.elapsed() >= limit {
            child.kill()?;
            child.wait()?;
            return Ok(ChildRun {
                wall_s: began.elapsed().as_secs_f64(),
                peak_rss_bytes: None,
                exit: Exit::TimedOut,
            });
        }
        std::thread::sleep(POLL);
    }
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    #[test]
    fn a_run_reports_its_exit_code_and_its_own_memory() {
        let dir = tempfile::tempdir().expect("temp dir");
        let log = dir.path().join("log");
        // Python holding 64 MiB: the child's peak, not ours, must show it.
        let mut command = Command::new("python3");
        command.args([
            "-c",
            "b = bytearray(64 << 20); b[::4096] = b'x' * len(b[::4096]); raise SystemExit(3)",
        ]);
        let run = run_bounded(&mut command, Duration::from_secs(20), &log).expect("runs");
        assert_eq!(run.exit, Exit::Code(3));
        let peak = run.peak_rss_bytes.expect("Linux reports ru_maxrss");
        assert!(peak >= 64 << 20, "peak {peak} B below the 64 MiB it held");
    }

    #[test]
    fn a_run_past_its_limit_is_killed_and_says_so() {
        let dir = tempfile::tempdir().expect("temp dir");
        let mut command = Command::new("sleep");
        command.arg("30");
        let run = run_bounded(
            &mut command,
            Duration::from_millis(200),
            &dir.path().join("log"),
        )
        .expect("runs");
        assert_eq!(run.exit, Exit::TimedOut);
        assert!(!run.succeeded());
        assert!(
            run.wall_s < 10.0,
            "killed at the limit, not at the end: {} s",
            run.wall_s
        );
    }

    #[test]
    fn output_goes_to_the_log() {
        let dir = tempfile::tempdir().expect("temp dir");
        let log = dir.path().join("log");
        let mut command = Command::new("sh");
        command.args(["-c", "echo out; echo err >&2"]);
        let run = run_bounded(&mut command, Duration::from_secs(10), &log).expect("runs");
        assert!(run.succeeded());
        let text = std::fs::read_to_string(&log).expect("log");
        assert!(text.contains("out") && text.contains("err"), "{text:?}");
    }

    #[test]
    fn a_program_that_is_not_there_is_an_error_naming_it() {
        let dir = tempfile::tempdir().expect("temp dir");
        let mut command = Command::new("/no/such/solver");
        let error = run_bounded(
            &mut command,
            Duration::from_secs(1),
            &dir.path().join("log"),
        )
        .expect_err("cannot start");
        assert!(error.to_string().contains("/no/such/solver"), "{error}");
    }
}
