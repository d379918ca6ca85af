//! The process's peak resident memory over a stretch of work, where the kernel tells it
//! cheaply (Linux): its high-water mark of resident memory (`VmHWM` in `/proc/self/status`) is
//! reset by writing 5 to `/proc/self/clear_refs` before, and read after.
//!
//! It measures the whole process: what the work allocated and touched, and everything the
//! process already held resident (the photograph, the program, the caller's data), not the
//! work's own allocations alone. Work on other threads of the process at the same time counts
//! too.

/// Starts a measurement; false where the high-water mark cannot be reset (then
/// [`peak_bytes`] gives the peak since the process started, or nothing).
pub fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// The process's peak resident memory (bytes) since the last [`reset_peak`], where known.
pub fn peak_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line
        .trim_start_matches("VmHWM:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_peak_covers_what_was_touched() {
        if !reset_peak() {
            return; // not Linux, or /proc not writable: nothing to measure
        }
        let before = peak_bytes().expect("VmHWM readable where clear_refs is");
        // Touch 64 MB: the peak after holds it.
        let block = vec![1u8; 64 << 20];
        std::hint::black_box(&block);
        let after = peak_bytes().unwrap();
        assert!(after >= before + (60 << 20), "{before} -> {after}");
    }
}
