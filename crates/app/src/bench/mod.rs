//! The benchmark workloads behind `oficina bench …`: generated inputs, the peers' drivers
//! and the measurements. The CLI parses options, calls these and prints the tables.

pub mod carve;
pub mod carve_mesh;
pub mod gcode;
pub mod motion;
pub mod offsets;
pub mod plot;
pub mod programs;
pub mod stitch;
pub mod stream;

use std::time::Instant;

/// Wall and CPU seconds (CPU: every thread of this process, from getrusage).
#[derive(Clone, Copy, Debug, Default)]
pub struct Cost {
    /// Wall seconds.
    pub wall: f64,
    /// CPU seconds, user + system.
    pub cpu: f64,
}

impl Cost {
    /// Both costs together.
    pub fn plus(self, o: Cost) -> Cost {
        Cost {
            wall: self.wall + o.wall,
            cpu: self.cpu + o.cpu,
        }
    }
}

/// Whose CPU time [`cpu_seconds`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CpuOf {
    /// This process, every thread.
    Process,
    /// The children this process has waited for.
    Children,
}

/// User + system CPU seconds used so far.
pub fn cpu_seconds(of: CpuOf) -> f64 {
    use nix::sys::resource::{getrusage, UsageWho};
    let who = match of {
        CpuOf::Process => UsageWho::RUSAGE_SELF,
        CpuOf::Children => UsageWho::RUSAGE_CHILDREN,
    };
    getrusage(who).map_or(0.0, |u| {
        let t = |v: nix::sys::time::TimeVal| v.tv_sec() as f64 + v.tv_usec() as f64 * 1e-6;
        t(u.user_time()) + t(u.system_time())
    })
}

/// This process's largest resident set so far, MB (getrusage's max RSS).
pub fn max_rss_mb() -> f64 {
    use nix::sys::resource::{getrusage, UsageWho};
    getrusage(UsageWho::RUSAGE_SELF).map_or(0.0, |u| u.max_rss() as f64 / 1024.0)
}

/// Runs `f` and says what it cost.
pub fn measure<T>(f: impl FnOnce() -> T) -> (T, Cost) {
    let (wall, cpu) = (Instant::now(), cpu_seconds(CpuOf::Process));
    let out = f();
    let cost = Cost {
        wall: wall.elapsed().as_secs_f64(),
        cpu: cpu_seconds(CpuOf::Process) - cpu,
    };
    (out, cost)
}

/// The peak resident memory of this process (Linux's VmHWM) in kB, from /proc/self/status;
/// `None` where there is no such file. The kernel keeps the high-water mark, so it is the
/// whole benchmark's.
pub fn peak_memory_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let l = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    l.split_whitespace().nth(1)?.parse().ok()
}

/// `given`, else the repository's file at `relative` (from the working directory when it is
/// the checkout, else from this crate's source).
pub fn repo_file(given: Option<&std::path::Path>, relative: &str) -> std::path::PathBuf {
    given.map(std::path::Path::to_path_buf).unwrap_or_else(|| {
        let local = std::path::PathBuf::from(relative);
        if local.exists() {
            local
        } else {
            std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("../..")
                .join(relative)
        }
    })
}

/// The 1-minute load average, to say how busy the machine was.
pub fn load_average() -> Option<String> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    text.split_whitespace().next().map(str::to_string)
}

/// Why a benchmark stopped: over its memory budget (the CLI names the options that change
/// it) or anything else, said in words.
#[derive(Debug)]
pub enum BenchError {
    /// Over the memory budget: what would not fit.
    OverMemory(String),
    /// Anything else, in words.
    Failed(String),
}

impl std::fmt::Display for BenchError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BenchError::OverMemory(s) | BenchError::Failed(s) => f.write_str(s),
        }
    }
}

impl std::error::Error for BenchError {}

/// A peer's interpreter that would not start, named with its script.
fn cannot_run(python: &std::path::Path, script: &std::path::Path, e: std::io::Error) -> BenchError {
    failed(format!(
        "cannot run {} {}: {e}",
        python.display(),
        script.display()
    ))
}

fn failed(e: impl std::fmt::Display) -> BenchError {
    BenchError::Failed(e.to_string())
}
