//! The BVH's arrays on transparent huge pages (2 MB) where the kernel
//! offers them on request (Linux's THP mode `madvise`, the usual default).
//! Random rays through a tree larger than the caches touch a different
//! 4 KB page at nearly every node and leaf, and each such page costs a
//! TLB miss (a page-table walk) on top of the cache miss; a 2 MB page
//! covers 512 times as much. Embree asks for huge pages for its BVH the
//! same way (`madvise(MADV_HUGEPAGE)` on its allocations). Measured on
//! the 1M-triangle bench sphere's random rays, one thread, the builds
//! with and without alternating (6 rounds, 2026-12-06): one at a time
//! 0.67–0.79 against 0.59–0.74 Mrays/s, interleaved 1.11–1.13 against
//! 0.77–1.04, packets 0.79–0.87 against 0.61–0.81.
//!
//! [`HugePageAllocator`] does the same for every large allocation of a
//! program that makes it its global allocator, as the `penumbra` command
//! does: obvhs's build allocates and frees arrays of tens of megabytes,
//! and the page faults of their first touches were a quarter of the
//! 1M-triangle build's CPU time on a virtual machine (`perf`, 2026-12-07).
//! With it the build's median fell from 0.93 to 0.87 s there (10 runs
//! alternating the builds), within that machine's noise; its system time
//! did not fall (the kernel zeroes the same bytes either way).
//!
//! `unsafe` for the `madvise` call (a hint about memory we own) and the
//! allocator's forwarding to the system's.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};

/// Arrays smaller than this stay where they are: they hold at most one
/// whole 2 MB page, and trees that small mostly live in the caches.
const HUGE_ABOVE_BYTES: usize = 4 << 20;

/// A huge page's size (x86-64 and AArch64 with 4 KB base pages).
const HUGE_PAGE: usize = 2 << 20;

/// An empty vector with room for `len` items whose whole 2 MB pages are
/// marked for huge pages before anything touches them (so that the page
/// faults of filling it get huge pages), when `len` items are large enough
/// to hold some. Filling it past `len` moves it to ordinary memory.
pub(super) fn with_capacity<T>(len: usize) -> Vec<T> {
    let mut items: Vec<T> = Vec::with_capacity(len);
    advised(items.as_mut_ptr().cast(), len * size_of::<T>());
    items
}

/// `items`, copied into a [`with_capacity`] allocation when large enough;
/// otherwise, or on other systems, `items` unchanged (for an array whose
/// length is not known before it is filled).
pub(super) fn on_huge_pages<T: Copy>(items: Vec<T>) -> Vec<T> {
    if size_of_val(&items[..]) < HUGE_ABOVE_BYTES || !cfg!(target_os = "linux") {
        return items;
    }
    let mut copy = with_capacity(items.len());
    copy.extend_from_slice(&items);
    copy
}

/// The system allocator, with the whole 2 MB pages of every allocation of
/// at least 4 MB marked for huge pages before it is handed out (a fresh
/// mapping is untouched until then, so its page faults get huge pages
/// where the kernel has them). Smaller allocations, and every free, go to
/// the system allocator unchanged. For a binary:
/// `#[global_allocator] static A: HugePageAllocator = HugePageAllocator;`.
#[derive(Clone, Copy, Debug, Default)]
pub struct HugePageAllocator;

// SAFETY: every call forwards to `System` with the caller's arguments and
// returns its result; the hint only changes how the kernel backs pages of
// a block `System` just handed out.
unsafe impl GlobalAlloc for HugePageAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract for `alloc`, passed on.
        advised(unsafe { System.alloc(layout) }, layout.size())
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as `alloc`.
        advised(unsafe { System.alloc_zeroed(layout) }, layout.size())
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System` through this allocator.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as `dealloc`, with the caller's `new_size`.
        advised(unsafe { System.realloc(ptr, layout, new_size) }, new_size)
    }
}

/// `block` (of `len` bytes, or null), its whole 2 MB pages marked for huge
/// pages when it is large enough to hold some worth having.
fn advised(block: *mut u8, len: usize) -> *mut u8 {
    if !block.is_null() && len >= HUGE_ABOVE_BYTES {
        advise_huge(block, len);
    }
    block
}

/// Marks the whole 2 MB pages within `len` bytes from `start` for huge
/// pages. A hint: where the kernel refuses it (THP off, an old kernel),
/// nothing changes.
fn advise_huge(start: *mut u8, len: usize) {
    #[cfg(target_os = "linux")]
    {
        let first = start.wrapping_add(start.align_offset(HUGE_PAGE));
        let end = (start as usize + len) & !(HUGE_PAGE - 1);
        let whole = end.saturating_sub(first as usize);
        if whole > 0 {
            // SAFETY: [first, first + whole) lies within the caller's
            // allocation of `len` bytes from `start`; MADV_HUGEPAGE only
            // changes how the kernel backs those pages, not their contents.
            unsafe { libc::madvise(first.cast(), whole, libc::MADV_HUGEPAGE) };
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (start, len);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The THP mode the kernel runs, e.g. `madvise` (the bracketed word
    /// of /sys/kernel/mm/transparent_hugepage/enabled), if it has THP.
    fn thp_mode() -> Option<String> {
        let s = std::fs::read_to_string("/sys/kernel/mm/transparent_hugepage/enabled").ok()?;
        let start = s.find('[')? + 1;
        let end = s[start..].find(']')? + start;
        Some(s[start..end].to_string())
    }

    /// Whether the mapping that holds `address` may be backed by huge
    /// pages (`THPeligible` in /proc/self/smaps).
    fn thp_eligible(address: usize) -> Option<bool> {
        let smaps = std::fs::read_to_string("/proc/self/smaps").ok()?;
        let mut inside = false;
        for line in smaps.lines() {
            let range = line.split_whitespace().next().unwrap_or("");
            if let Some((a, b)) = range.split_once('-')
                && let (Ok(a), Ok(b)) = (usize::from_str_radix(a, 16), usize::from_str_radix(b, 16))
            {
                inside = (a..b).contains(&address);
            } else if inside && let Some(v) = line.strip_prefix("THPeligible:") {
                return Some(v.trim() == "1");
            }
        }
        None
    }

    /// Copies keep every value, small arrays stay in place, and on a
    /// Linux kernel whose THP mode is `madvise` the copy of a large array,
    /// and a large array filled in place, lie in mappings marked for huge
    /// pages, which a plain allocation of the same size is not.
    #[test]
    fn large_arrays_are_marked_for_huge_pages() {
        let small: Vec<u32> = (0..1000).collect();
        let at = small.as_ptr();
        let small = on_huge_pages(small);
        assert_eq!(small.as_ptr(), at, "a small array is not copied");
        assert!(small.iter().copied().eq(0..1000));

        let n = 3 * HUGE_PAGE / size_of::<u32>();
        let large: Vec<u32> = (0..n as u32).collect();
        let large = on_huge_pages(large);
        assert!(large.iter().copied().eq(0..n as u32));
        if !cfg!(target_os = "linux") || thp_mode().as_deref() != Some("madvise") {
            eprintln!(
                "note: THP mode {:?}: the madvise hint is not observable",
                thp_mode()
            );
            return;
        }
        let inside = large.as_ptr() as usize + HUGE_PAGE;
        assert_eq!(thp_eligible(inside), Some(true), "the copy is marked");
        let mut filled: Vec<u32> = with_capacity(n);
        filled.extend(0..n as u32);
        let inside = filled.as_ptr() as usize + HUGE_PAGE;
        assert_eq!(
            thp_eligible(inside),
            Some(true),
            "an array filled in place is marked"
        );
        let plain: Vec<u32> = vec![1; n];
        let inside = plain.as_ptr() as usize + HUGE_PAGE;
        assert_eq!(thp_eligible(inside), Some(false), "a plain array is not");
    }

    /// The allocator's large blocks, fresh, zeroed or grown, hold what is
    /// written to them (or zeros) and, where the THP mode is `madvise`,
    /// lie in mappings marked for huge pages. The blocks are larger than
    /// glibc's largest mmap threshold (32 MB), so each is a mapping of its
    /// own, returned to the kernel when freed, and the other test's plain
    /// array cannot land on memory marked here.
    #[test]
    fn the_allocator_marks_large_blocks() {
        let alloc = HugePageAllocator;
        let size = 40 << 20;
        let layout = Layout::from_size_align(size, 64).unwrap();
        let markable = cfg!(target_os = "linux") && thp_mode().as_deref() == Some("madvise");
        let check_marked = |block: *mut u8, what: &str| {
            if markable {
                let inside = block as usize + 3 * HUGE_PAGE;
                assert_eq!(thp_eligible(inside), Some(true), "{what}");
            }
        };
        // SAFETY: non-zero sizes; each block is used within its size and
        // freed once with the layout it has.
        unsafe {
            let block = alloc.alloc(layout);
            assert!(!block.is_null());
            check_marked(block, "a fresh block is marked");
            let words = std::slice::from_raw_parts_mut(block.cast::<u32>(), size / 4);
            for (i, w) in words.iter_mut().enumerate() {
                *w = i as u32;
            }
            let grown = alloc.realloc(block, layout, size + (8 << 20));
            assert!(!grown.is_null());
            check_marked(grown, "a grown block is marked");
            let words = std::slice::from_raw_parts(grown.cast::<u32>(), size / 4);
            assert!(words.iter().copied().eq(0..(size / 4) as u32), "kept");
            let grown_layout = Layout::from_size_align(size + (8 << 20), 64).unwrap();
            alloc.dealloc(grown, grown_layout);

            let zeroed = alloc.alloc_zeroed(layout);
            assert!(!zeroed.is_null());
            check_marked(zeroed, "a zeroed block is marked");
            assert!(
                std::slice::from_raw_parts(zeroed, size)
                    .iter()
                    .all(|&b| b == 0)
            );
            alloc.dealloc(zeroed, layout);
        }
        if !markable {
            eprintln!(
                "note: THP mode {:?}: the madvise hint is not observable",
                thp_mode()
            );
        }
    }
}
