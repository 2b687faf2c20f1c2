//! Peak resident memory of the process per row, from Linux's high-water
//! mark: writing `5` to `/proc/self/clear_refs` resets `VmHWM` in
//! `/proc/self/status` to the current resident size (Linux ≥ 4.0). Other
//! systems report no figure.

/// Starts a new peak-memory measurement.
pub fn reset_peak() {
    // Unsupported systems keep the process-wide peak; `peak_mib` is then an
    // upper bound, which is still an honest figure.
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// The peak resident memory since the last [`reset_peak`] [MiB].
pub fn peak_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[cfg(target_os = "linux")]
    fn peak_sees_an_allocation() {
        reset_peak();
        let before = peak_mib().expect("VmHWM on Linux");
        // 256 MiB, touched so it becomes resident (other tests run in the
        // same process, hence the wide margins).
        let block = vec![1u8; 256 << 20];
        std::hint::black_box(&block);
        let during = peak_mib().unwrap();
        drop(block);
        assert!(during - before > 250.0, "{before} -> {during}");
        reset_peak();
        let after = peak_mib().unwrap();
        assert!(after < during - 128.0, "reset: {during} -> {after}");
    }
}
