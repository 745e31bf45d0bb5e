//! What this process uses right now: CPU time (the whole process, the calling
//! thread, each live thread by name), resident memory and open file descriptors.
//!
//! The one copy of these readers: the load benchmark, the soak, `swarmctl bench`
//! and the benchmarks (`fly_stream`, `fly_record`, `viz_recorder`) all measure the
//! same way. Linux only; elsewhere every reader returns `None`.
//!
//! - Process CPU: getrusage(`RUSAGE_SELF`), user + system, microseconds, every
//!   thread the process ever had (exited ones included).
//! - Thread CPU: `/proc/self/task/<tid>/stat` gives the thread's name and its
//!   user + system time in clock ticks (10 ms); where the kernel also keeps
//!   `schedstat`, its time on a CPU (the same accounting, in nanoseconds) is used
//!   instead, so a thread that ran for a few milliseconds does not read as zero.
//! - Memory: `VmRSS` and `VmHWM` of `/proc/self/status`.
//! - Descriptors: the entries of `/proc/self/fd`.

use std::path::Path;

/// Linux reports process times in USER_HZ ticks, fixed at 100 by the kernel ABI.
const USER_HZ: f64 = 100.0;
/// `/proc/self/status` gives memory in kibibytes.
const BYTES_PER_KIB: u64 = 1024;

/// User + system CPU time of the whole process (all threads, live and exited),
/// seconds.
pub fn process_cpu_s() -> Option<f64> {
    rusage_self_cpu_s()
}

#[cfg(target_os = "linux")]
fn rusage_self_cpu_s() -> Option<f64> {
    // SAFETY: `rusage` is plain integers, so all zeroes is a valid value.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: RUSAGE_SELF is a valid `who`, and the pointer is to a live, writable
    // rusage that getrusage only writes into.
    if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut usage) } != 0 {
        return None;
    }
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    Some(seconds(usage.ru_utime) + seconds(usage.ru_stime))
}

#[cfg(not(target_os = "linux"))]
fn rusage_self_cpu_s() -> Option<f64> {
    None
}

/// CPU time of the calling thread, seconds.
pub fn this_thread_cpu_s() -> Option<f64> {
    read_thread(Path::new("/proc/thread-self")).map(|(_, cpu_s)| cpu_s)
}

/// One live thread of this process and the CPU it has used.
#[derive(Debug, Clone, PartialEq)]
pub struct ThreadCpu {
    /// The kernel's thread id: tells apart threads that share a name, and the same
    /// thread across two readings.
    pub tid: u32,
    /// The thread's name as the kernel keeps it (at most 15 bytes).
    pub name: String,
    /// User + system CPU time since the thread started, seconds.
    pub cpu_s: f64,
}

/// Every live thread of this process with its CPU time (threads that have exited
/// are gone from the list; [`process_cpu_s`] still counts them).
pub fn threads_cpu() -> Option<Vec<ThreadCpu>> {
    let tasks = std::fs::read_dir("/proc/self/task").ok()?;
    let threads = tasks
        .flatten()
        .filter_map(|task| {
            let tid = task.file_name().to_str()?.parse().ok()?;
            let (name, cpu_s) = read_thread(&task.path())?;
            Some(ThreadCpu {
                tid,
                name: name.to_string(),
                cpu_s,
            })
        })
        .collect();
    Some(threads)
}

/// CPU time of this process's live threads named `name`, seconds (0 when none is
/// alive).
pub fn threads_named_cpu_s(name: &str) -> Option<f64> {
    let threads = threads_cpu()?;
    Some(
        threads
            .iter()
            .filter(|t| t.name == name)
            .map(|t| t.cpu_s)
            .sum(),
    )
}

/// The name and CPU seconds of the thread whose `/proc` directory is `dir`.
fn read_thread(dir: &Path) -> Option<(String, f64)> {
    let stat = std::fs::read_to_string(dir.join("stat")).ok()?;
    let (name, ticks_cpu_s) = parse_stat(&stat)?;
    let cpu_s = std::fs::read_to_string(dir.join("schedstat"))
        .ok()
        .as_deref()
        .and_then(parse_schedstat)
        .unwrap_or(ticks_cpu_s);
    Some((name.to_string(), cpu_s))
}

/// The name and utime + stime (seconds) of a `/proc/.../stat` line. The name is
/// in parentheses and may itself hold spaces and parentheses, so it runs to the
/// last `)`.
fn parse_stat(stat: &str) -> Option<(&str, f64)> {
    let open = stat.find('(')?;
    let close = stat.rfind(')')?;
    let name = stat.get(open + 1..close)?;
    let fields: Vec<&str> = stat.get(close + 1..)?.split_whitespace().collect();
    // After the name: state is field 0, utime field 11, stime field 12.
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    Some((name, (utime + stime) / USER_HZ))
}

/// Time on a CPU (seconds) from a `/proc/.../schedstat` line: nanoseconds run,
/// nanoseconds waited, time slices.
fn parse_schedstat(schedstat: &str) -> Option<f64> {
    let ns: f64 = schedstat.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// Resident memory now (`VmRSS`), bytes.
pub fn rss_bytes() -> Option<u64> {
    status_kib("VmRSS:").map(|kib| kib * BYTES_PER_KIB)
}

/// The most resident memory the process has had (`VmHWM`), bytes.
pub fn peak_rss_bytes() -> Option<u64> {
    status_kib("VmHWM:").map(|kib| kib * BYTES_PER_KIB)
}

/// A `/proc/self/status` field given in kB.
fn status_kib(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Open file descriptors (entries of `/proc/self/fd`, the one reading them
/// included).
pub fn open_fds() -> Option<usize> {
    std::fs::read_dir("/proc/self/fd").ok().map(Iterator::count)
}

/// What the process holds right now, for comparing one flight with the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ProcessResources {
    /// Resident memory (Linux `VmRSS`), bytes; 0 where unknown.
    pub rss_bytes: u64,
    /// Open file descriptors (entries of `/proc/self/fd`); 0 where unknown.
    pub open_fds: usize,
}

/// Resident memory and open file descriptors of this process, each 0 where it
/// cannot be read (not Linux): a soak compares snapshots, and equal zeros compare
/// as "no growth" rather than stopping the run.
pub fn process_resources() -> ProcessResources {
    ProcessResources {
        rss_bytes: rss_bytes().unwrap_or(0),
        open_fds: open_fds().unwrap_or(0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_lines_parse_with_spaces_and_parentheses_in_names() {
        let line = "123 (a (b) c) S 1 2 3 4 5 6 7 8 9 10 250 50 0 0";
        assert_eq!(parse_stat(line), Some(("a (b) c", 3.0)));
    }

    #[test]
    fn schedstat_gives_nanoseconds_on_a_cpu() {
        assert_eq!(parse_schedstat("1500000000 20 3\n"), Some(1.5));
        assert_eq!(parse_schedstat(""), None);
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn this_process_reads_on_linux() {
        let named = "resources-test";
        let spin = std::thread::Builder::new()
            .name(named.into())
            .spawn(move || {
                let started = std::time::Instant::now();
                while started.elapsed() < std::time::Duration::from_millis(30) {}
                let threads = threads_cpu().unwrap();
                let own = this_thread_cpu_s().unwrap();
                (threads, own)
            })
            .unwrap();
        let (threads, own_cpu_s) = spin.join().unwrap();
        let mine: Vec<&ThreadCpu> = threads.iter().filter(|t| t.name == named).collect();
        assert_eq!(mine.len(), 1, "{threads:?}");
        assert!(mine[0].cpu_s > 0.0 && own_cpu_s >= mine[0].cpu_s);
        assert!(process_cpu_s().unwrap() >= mine[0].cpu_s);
        let rss = rss_bytes().unwrap();
        assert!(rss > 0 && peak_rss_bytes().unwrap() >= rss);
        assert!(open_fds().unwrap() >= 3);
    }
}
