//! A process-wide count of the rays traced (closest-hit and occlusion
//! queries alike), for throughput figures in rays/s (`penumbra bench`,
//! bake reports).
//!
//! Each thread counts in a thread-local cell and adds to the global total
//! every [`FLUSH`] rays, so counting costs one thread-local increment per
//! ray; [`rays_traced`] therefore lags by less than `FLUSH` rays per thread.

use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

/// Rays a thread counts before adding them to the global total.
const FLUSH: u64 = 256;

static TOTAL: AtomicU64 = AtomicU64::new(0);

thread_local! {
    static LOCAL: Cell<u64> = const { Cell::new(0) };
}

/// Counts one ray.
#[inline]
pub fn count_ray() {
    count_rays(1);
}

/// Counts `n` rays.
#[inline]
pub fn count_rays(n: u64) {
    LOCAL.with(|c| {
        let m = c.get() + n;
        if m >= FLUSH {
            TOTAL.fetch_add(m, Ordering::Relaxed);
            c.set(0);
        } else {
            c.set(m);
        }
    });
}

/// Rays traced by the whole process so far (to within `FLUSH` per thread).
pub fn rays_traced() -> u64 {
    TOTAL.load(Ordering::Relaxed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_in_batches() {
        let before = rays_traced();
        std::thread::spawn(|| {
            for _ in 0..10 * FLUSH {
                count_ray();
            }
        })
        .join()
        .unwrap();
        // Other tests may trace rays concurrently: at least ours arrived.
        assert!(rays_traced() - before >= 10 * FLUSH);
    }
}
