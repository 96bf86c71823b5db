//! The binary's allocator: mimalloc for everything but large blocks, which are mapped from and
//! given back to the operating system at once.
//!
//! Why both: reading a model of 10^5 beams allocates and frees millions of small strings and
//! vectors, which mimalloc serves several times faster than the system allocator
//! (bench/README.md §3b). But mimalloc keeps the pages of freed blocks for reuse and gives them
//! back only after a delay, and the large vectors of one phase (the reader's, the static
//! step's, a factorisation) are rarely the size the next phase asks for: on the 10^5-beam strip
//! `modes` was resident at 1.25 times its heap. Blocks of [`LARGE`] bytes and more are few (a
//! vector of the model's size is one) and once freed they no longer count against the process.
//! The price is fresh, zeroed pages for each: `modes` on the 10^4-beam strip takes 0.34 s
//! instead of 0.27 s, for 57 MiB instead of 100–116 (bench/README.md §3b).
//!
//! Mappings up to [`POPULATE`] are filled at once (page faults one by one made `modes` at 10^5
//! beams 40 % slower); larger ones, often capacity reserved ahead and never touched, page by
//! page as they are touched. The small blocks' pages mimalloc gives back as soon as they are
//! free ([`purge_at_once`]) instead of a second later: with the large blocks out of its way that
//! costs no measurable time (30–40 % when mimalloc served them too), and a model's many small
//! temporaries (the reader's, the builder's) no longer stay resident beside the analysis.

use mimalloc::MiMalloc;
use std::alloc::{GlobalAlloc, Layout};

/// mimalloc's `mi_option_purge_delay` (its number in `mi_option_e` of mimalloc.h, versions 2
/// and 3; default 10 ms, 1000 ms in the 3.3 the mimalloc crate builds).
const PURGE_DELAY: libc::c_int = 15;

unsafe extern "C" {
    fn mi_option_get(option: libc::c_int) -> libc::c_long;
    fn mi_option_set(option: libc::c_int, value: libc::c_long);
}

/// Lets mimalloc give free pages back at once (its purge delay 0), unless the user set the
/// delay (`MIMALLOC_PURGE_DELAY`). Left as it is if the option does not read as one of its
/// defaults (10 or 1000 ms): another mimalloc version may number its options otherwise.
pub fn purge_at_once() {
    if std::env::var_os("MIMALLOC_PURGE_DELAY").is_some() {
        return;
    }
    // SAFETY: mimalloc's option calls take any option number and value.
    unsafe {
        if matches!(mi_option_get(PURGE_DELAY), 10 | 1000) {
            mi_option_set(PURGE_DELAY, 0);
        }
    }
}

/// Blocks of this many bytes or more are mapped directly (a quarter of a MiB: a vector of
/// 32,768 reals).
const LARGE: usize = 256 * 1024;

/// Mappings up to this size are filled at once (MAP_POPULATE: one system call instead of a
/// page fault per 4 KiB page), larger ones page by page as they are touched.
const POPULATE: usize = 8 << 20;

/// Alignments up to the page size come with every mapping.
const PAGE: usize = 4096;

/// mimalloc for small blocks, anonymous mappings for large ones.
pub struct Allocator;

/// Whether a block of this layout is mapped (decided from the layout alone, so that `dealloc`
/// and `realloc` find where a block came from).
fn mapped(size: usize, align: usize) -> bool {
    size >= LARGE && align <= PAGE
}

unsafe fn map(size: usize) -> *mut u8 {
    // SAFETY: an anonymous private mapping has no preconditions; failure is MAP_FAILED.
    let p = unsafe {
        libc::mmap(
            std::ptr::null_mut(),
            size,
            libc::PROT_READ | libc::PROT_WRITE,
            if size <= POPULATE {
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS | libc::MAP_POPULATE
            } else {
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS
            },
            -1,
            0,
        )
    };
    if p == libc::MAP_FAILED {
        std::ptr::null_mut()
    } else {
        p.cast()
    }
}

// SAFETY: every block is given back by the allocator that gave it: `mapped` of the block's
// layout, which the caller passes unchanged to `dealloc` and `realloc`, says which.
unsafe impl GlobalAlloc for Allocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if mapped(layout.size(), layout.align()) {
            unsafe { map(layout.size()) }
        } else {
            unsafe { MiMalloc.alloc(layout) }
        }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if mapped(layout.size(), layout.align()) {
            // anonymous mappings are zero-filled
            unsafe { map(layout.size()) }
        } else {
            unsafe { MiMalloc.alloc_zeroed(layout) }
        }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        if mapped(layout.size(), layout.align()) {
            unsafe { libc::munmap(ptr.cast(), layout.size()) };
        } else {
            unsafe { MiMalloc.dealloc(ptr, layout) }
        }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let align = layout.align();
        match (mapped(layout.size(), align), mapped(new_size, align)) {
            (false, false) => unsafe { MiMalloc.realloc(ptr, layout, new_size) },
            (true, true) => {
                // SAFETY: `ptr` is a mapping of `layout.size()` bytes made by `map`.
                let p = unsafe {
                    libc::mremap(ptr.cast(), layout.size(), new_size, libc::MREMAP_MAYMOVE)
                };
                if p == libc::MAP_FAILED {
                    std::ptr::null_mut()
                } else {
                    p.cast()
                }
            }
            _ => {
                // SAFETY: the new layout is valid (same alignment, the caller's size).
                let new_layout = unsafe { Layout::from_size_align_unchecked(new_size, align) };
                let q = unsafe { self.alloc(new_layout) };
                if !q.is_null() {
                    unsafe {
                        std::ptr::copy_nonoverlapping(ptr, q, layout.size().min(new_size));
                        self.dealloc(ptr, layout);
                    }
                }
                q
            }
        }
    }
}
