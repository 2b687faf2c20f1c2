//! Peak memory of a row: how far the process's resident size rose above
//! its size at the row's start. Linux's high-water mark gives the peak:
//! writing `5` to `/proc/self/clear_refs` resets `VmHWM` in
//! `/proc/self/status` to the current resident size `VmRSS` (Linux ≥ 4.0).
//! Other systems report no figure.

/// A peak-memory measurement from now on.
#[derive(Clone, Copy, Debug)]
pub struct PeakMemory {
    start_mib: Option<f64>,
}

impl PeakMemory {
    /// Resets the high-water mark and notes the resident size.
    pub fn start() -> Self {
        let reset = std::fs::write("/proc/self/clear_refs", "5").is_ok();
        Self {
            start_mib: reset.then(|| status_mib("VmRSS:")).flatten(),
        }
    }

    /// The peak resident size since [`PeakMemory::start`] above the
    /// resident size then [MiB]; `None` where the OS does not tell.
    pub fn rise_mib(&self) -> Option<f64> {
        Some((peak_mib()? - self.start_mib?).max(0.0))
    }
}

/// The process's peak resident size since the last reset [MiB].
pub fn peak_mib() -> Option<f64> {
    status_mib("VmHWM:")
}

fn status_mib(key: &str) -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[cfg(target_os = "linux")]
    fn peak_sees_an_allocation() {
        let m = PeakMemory::start();
        let before = peak_mib().expect("VmHWM on Linux");
        // 256 MiB, touched so it becomes resident (other tests run in the
        // same process, hence the wide margins).
        let block = vec![1u8; 256 << 20];
        std::hint::black_box(&block);
        let during = peak_mib().unwrap();
        drop(block);
        assert!(during - before > 250.0, "{before} -> {during}");
        // The rise outlives the block: it is a peak.
        assert!(m.rise_mib().unwrap() > 250.0, "{:?}", m.rise_mib());
        PeakMemory::start();
        let after = peak_mib().unwrap();
        assert!(after < during - 128.0, "reset: {during} -> {after}");
    }
}
