//! How busy the machine was while the report measured: the CPU time every process used (`/proc/stat`) minus this
//! process's own (`/proc/self/stat`), as a share of the machine's cores over the run, and the load average before
//! and after. Timings taken while other work shares the cores are noisy; the page says so in its footnote.
//! Elsewhere than Linux the numbers are unknown and the footnote says that.

use std::time::Instant;

/// CPU time counters at the start of the run.
pub struct Usage {
    started: Instant,
    all_busy: Option<f64>,
    own: Option<f64>,
    load: Option<String>,
}

/// What the run saw.
pub struct UsageReport {
    pub seconds: f64,
    /// CPU-seconds used by other processes during the run.
    pub others_cpu: Option<f64>,
    pub cores: usize,
    pub load_before: Option<String>,
    pub load_after: Option<String>,
}

/// Clock ticks per second of `/proc` counters (USER_HZ, 100 on every Linux platform in use).
const TICKS: f64 = 100.0;

/// Busy CPU-seconds of the whole machine (every mode but idle and iowait).
fn machine_busy() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/stat").ok()?;
    let line = stat.lines().next()?.strip_prefix("cpu ")?;
    let v: Vec<f64> = line.split_whitespace().filter_map(|x| x.parse().ok()).collect();
    if v.len() < 5 {
        return None;
    }
    let total: f64 = v.iter().take(8).sum();
    Some((total - v[3] - v[4]) / TICKS)
}

/// CPU-seconds of this process (user + system, all threads).
fn own_cpu() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may contain spaces) in parentheses.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let utime: f64 = f.get(11)?.parse().ok()?;
    let stime: f64 = f.get(12)?.parse().ok()?;
    Some((utime + stime) / TICKS)
}

fn load_average() -> Option<String> {
    let s = std::fs::read_to_string("/proc/loadavg").ok()?;
    Some(s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
}

impl Usage {
    pub fn start() -> Usage {
        Usage { started: Instant::now(), all_busy: machine_busy(), own: own_cpu(), load: load_average() }
    }

    pub fn finish(self) -> UsageReport {
        let others = match (self.all_busy, machine_busy(), self.own, own_cpu()) {
            (Some(a0), Some(a1), Some(o0), Some(o1)) => Some(((a1 - a0) - (o1 - o0)).max(0.0)),
            _ => None,
        };
        UsageReport {
            seconds: self.started.elapsed().as_secs_f64(),
            others_cpu: others,
            cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            load_before: self.load,
            load_after: load_average(),
        }
    }
}

impl UsageReport {
    /// Share of the machine's cores other processes used during the run (0..1).
    pub fn others_share(&self) -> Option<f64> {
        self.others_cpu.map(|c| c / (self.seconds.max(1e-9) * self.cores as f64))
    }

    /// The footnote: the machine, how shared it was, and whether the timings can be trusted.
    pub fn describe(&self, threads: usize) -> String {
        let mut s = format!("Machine: {} core{}", self.cores, if self.cores == 1 { "" } else { "s" });
        if let (Some(a), Some(b)) = (&self.load_before, &self.load_after) {
            s += &format!(", load average {a} before and {b} after the run");
        }
        s += ". ";
        match self.others_share() {
            Some(share) if share > 0.10 => {
                s += &format!(
                    "Other processes used {:.0}% of the machine's CPU time during the run ({:.0} CPU-seconds while the \
                 report ran on {threads} thread{}): the timings are noisy and the speed ratios uncertain; regenerate \
                 on a quiet machine for numbers to quote.",
                    100.0 * share,
                    self.others_cpu.unwrap_or(0.0),
                    if threads == 1 { "" } else { "s" }
                )
            }
            Some(share) => {
                s += &format!(
                    "Other processes used {:.1}% of the machine's CPU time during the run: a quiet machine.",
                    100.0 * share
                )
            }
            None => s += "How much other processes used the machine is unknown here (no /proc).",
        }
        s
    }
}
