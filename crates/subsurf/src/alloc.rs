//! [`HugePageAlloc`]: the system allocator, asking Linux for transparent huge pages on large
//! blocks. A binary opts in with
//!
//! ```
//! #[global_allocator]
//! static GLOBAL: subsurf::alloc::HugePageAlloc = subsurf::alloc::HugePageAlloc;
//! # fn main() { let v = vec![0u8; 1 << 23]; assert_eq!(v.len(), 1 << 23); }
//! ```
//!
//! (the `subsurf` command-line tool does).
//!
//! # Why
//! Refining a mesh writes every byte of a few fresh buffers of tens to hundreds of MB that
//! the allocator takes from the kernel (`mmap`) and gives back when they are freed. Each
//! 4 KiB page is then faulted in on its first write: on `catmark_bishop` refined to level 6
//! that is ~100 k faults per call, and in a virtual machine they took about as long as the
//! refinement itself (`BENCHMARKS.md`: 45–60 % system time). Most Linux distributions set
//! transparent huge pages to `madvise` (`/sys/kernel/mm/transparent_hugepage/enabled`):
//! a region gets 2 MiB pages, 512 times fewer faults, only when asked for with
//! `madvise(MADV_HUGEPAGE)`. This allocator asks for it on every block of at least
//! [`HUGE_MIN`] bytes, right after allocating it and before anything is written to it.
//! Measured on `subsurf bench catmark_bishop.obj -l 6 --threads 1` (shared 2-core VM,
//! interleaved runs): page faults 723 k → 99 k per process of 7 repetitions; whole-process
//! wall time 0.81× (median of 5 pairs of 5-repetition processes), per-call median
//! ~0.41 s → ~0.25 s on a quiet machine. glibc's `GLIBC_TUNABLES=glibc.malloc.hugetlb=1` has
//! the same effect; this allocator makes it the default.
//!
//! Blocks that glibc serves from its heap rather than from a mapping of their own (after a
//! large block is freed, glibc raises that limit up to 32 MiB) are advised too, but their
//! pages may already be in use in 4 KiB pages: at level 5 of `catmark_bishop` faults fell
//! only from 660 k to 373 k (20 repetitions). Mapping large blocks here instead (aligned,
//! advised, `mremap` to grow) removed more of those at level 5 but measured 33 % more faults
//! and no gain at level 6, so it was left out.
//!
//! Memory use hardly changes: the buffers concerned are written in full, so a huge page is
//! rarely backed for a few bytes. Smaller blocks, other operating systems, and kernels
//! where huge pages are off (`never`) or always on behave exactly as with
//! [`std::alloc::System`] (the advice is then redundant or ignored).
//!
//! # Safety
//! Allocation, deallocation and reallocation are [`System`]'s, unchanged; the only addition
//! is an `madvise` call on whole 2 MiB-aligned pages inside a block that the allocator has
//! just returned (so mapped, and ours). `MADV_HUGEPAGE` changes how the kernel backs the
//! range, never its contents or its mapping; if the call fails (an old kernel, huge pages
//! disabled) the block is used as it is.

use std::alloc::{GlobalAlloc, Layout, System};

/// Blocks of at least this many bytes are advised (smaller ones could not hold a whole
/// aligned 2 MiB page after glibc's header, or hardly).
pub const HUGE_MIN: usize = 4 << 20;

/// The [`System`] allocator, with transparent huge pages requested on Linux for blocks of
/// at least [`HUGE_MIN`] bytes (see the [module documentation](self)).
#[derive(Clone, Copy, Debug, Default)]
pub struct HugePageAlloc;

/// Size of a transparent huge page (x86-64 and aarch64 with 4 KiB base pages); the advice
/// is given on whole aligned huge pages only.
#[cfg(target_os = "linux")]
const HUGE_PAGE: usize = 2 << 20;

/// Asks for huge pages on the 2 MiB-aligned part of `[ptr, ptr + size)`.
#[cfg(target_os = "linux")]
#[inline]
fn advise(ptr: *mut u8, size: usize) {
    if ptr.is_null() || size < HUGE_MIN {
        return;
    }
    let start = (ptr as usize).next_multiple_of(HUGE_PAGE);
    let end = (ptr as usize + size) & !(HUGE_PAGE - 1);
    if end > start {
        // SAFETY: `[start, end)` lies inside a live block just returned by `System` (so it
        // is mapped memory owned by the caller), and `start` is page aligned. The advice
        // does not change the contents or the validity of the memory; failure is ignored.
        unsafe {
            libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
#[inline]
fn advise(_ptr: *mut u8, _size: usize) {}

// SAFETY: every method forwards to `System` with the same arguments and returns its result;
// `advise` only gives the kernel a hint about memory inside the returned block.
unsafe impl GlobalAlloc for HugePageAlloc {
    #[inline]
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        advise(p, layout.size());
        p
    }

    #[inline]
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc_zeroed(layout);
        advise(p, layout.size());
        p
    }

    #[inline]
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }

    #[inline]
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = System.realloc(ptr, layout, new_size);
        if new_size > layout.size() {
            advise(p, new_size);
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Blocks of every size class come back usable, zeroed when asked, and keep their
    /// contents through reallocation, growing and shrinking across the threshold.
    #[test]
    fn behaves_as_the_system_allocator() {
        let a = HugePageAlloc;
        let sizes = [1usize, 4096, HUGE_MIN - 1, HUGE_MIN, 3 * HUGE_MIN + 12345];
        for align in [8usize, 16, 8192] {
            for size in sizes {
                for new_size in [2 * size, size / 2 + 1, HUGE_MIN / 3] {
                    let layout = Layout::from_size_align(size, align).unwrap();
                    unsafe {
                        let p = a.alloc_zeroed(layout);
                        assert!(!p.is_null());
                        assert_eq!(p as usize % align, 0);
                        let s = std::slice::from_raw_parts_mut(p, size);
                        assert!(s.iter().all(|&b| b == 0));
                        s.fill(7);
                        let q = a.realloc(p, layout, new_size);
                        assert!(!q.is_null());
                        assert_eq!(q as usize % align, 0);
                        let keep = size.min(new_size);
                        let s = std::slice::from_raw_parts_mut(q, new_size);
                        assert!(s[..keep].iter().all(|&b| b == 7));
                        s.fill(9);
                        a.dealloc(q, Layout::from_size_align(new_size, align).unwrap());
                    }
                }
            }
        }
    }
}
