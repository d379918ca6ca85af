//! What this process has used: processor time and memory, for the benchmarks' tables.

use std::time::Instant;

/// Peak resident memory of this process (bytes), from /proc; None where unavailable.
pub fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// User plus system processor time of this process so far (s).
pub fn cpu_time() -> f64 {
    // SAFETY: getrusage only writes into the struct we hand it.
    let usage = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_SELF, &mut usage);
        usage
    };
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    secs(usage.ru_utime) + secs(usage.ru_stime)
}

/// The machine's load average over the last minute, as /proc says it ("unknown" elsewhere):
/// how far the timings are from an idle machine.
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|l| l.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "unknown".into())
}

/// The best wall time of `repeat` runs of `f` (at least one) with that run's processor time,
/// and the last run's result: on a shared machine the wall time includes waiting for a core,
/// the processor time does not.
pub fn best_of<T>(repeat: usize, mut f: impl FnMut() -> T) -> (f64, f64, T) {
    let mut once = || {
        let (cpu, start) = (cpu_time(), Instant::now());
        let out = f();
        (start.elapsed().as_secs_f64(), cpu_time() - cpu, out)
    };
    let (mut wall, mut cpu, mut out) = once();
    for _ in 1..repeat {
        let (w, c, o) = once();
        if w < wall {
            (wall, cpu) = (w, c);
        }
        out = o;
    }
    (wall, cpu, out)
}
