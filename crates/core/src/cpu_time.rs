//! CPU time consumed by this process (all threads), for timings that stay meaningful when other jobs share the
//! machine: on Linux the sum of `/proc/self/task/*/schedstat` run times (nanosecond resolution); elsewhere `None`.

use std::time::Duration;

/// Total CPU time of all the process's threads so far, if the platform reports it.
pub fn process_cpu_time() -> Option<Duration> {
    let tasks = std::fs::read_dir("/proc/self/task").ok()?;
    let mut ns: u64 = 0;
    for t in tasks.flatten() {
        let stat = std::fs::read_to_string(t.path().join("schedstat")).ok()?;
        ns += stat.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(Duration::from_nanos(ns))
}
