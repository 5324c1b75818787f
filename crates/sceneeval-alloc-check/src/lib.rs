//! Counting allocations, to check that kernels documented as allocation-free allocate nothing.
//!
//! [`CountingAllocator`] is the system allocator that also counts, per thread, the calls that
//! obtain memory (`alloc`, `alloc_zeroed`, `realloc`); [`allocations_during`] runs a closure
//! once to warm it up and returns how many allocations a second run made on this thread.
//! `tests/no_allocation.rs` uses them on `sceneeval-relations`' predicates on plain geometry
//! (every relation, on boxes and on meshes), their batch forms, `sceneeval-geom`'s exact
//! box and mesh distances, and the loop of a layout optimiser (objects moved in a scene,
//! relations asked by index, `sceneeval-plausibility`'s per-object checks), as the
//! `layout_optimizer` example runs it. Run with `cargo test -p sceneeval-alloc-check`.
//!
//! This package exists because a global allocator needs `unsafe impl GlobalAlloc`, which the
//! rest of the workspace forbids; it is not published.
//!
//! # Example
//! ```
//! use sceneeval_alloc_check::{CountingAllocator, allocations_during};
//!
//! #[global_allocator]
//! static ALLOCATOR: CountingAllocator = CountingAllocator;
//!
//! let data = vec![3.0_f64, 1.0, 2.0];
//! // Summing a slice allocates nothing; collecting into a new vector allocates once.
//! assert_eq!(allocations_during(|| data.iter().sum::<f64>()), 0);
//! assert_eq!(allocations_during(|| data.iter().map(|x| x * 2.0).collect::<Vec<_>>()), 1);
//! ```
//! Without `CountingAllocator` installed as the global allocator, every count is 0.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

/// The system allocator, counting per thread the calls that obtain memory. Install it with
/// `#[global_allocator]` in a test binary, then measure with [`allocations_during`].
#[derive(Debug, Clone, Copy, Default)]
pub struct CountingAllocator;

fn count() {
    // `try_with`: the thread's slot may already be gone while the thread exits.
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

// SAFETY: every method forwards to `System` with the caller's arguments unchanged; counting
// touches only a const-initialised thread-local `Cell`, which neither allocates nor panics.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: the caller upholds `GlobalAlloc::alloc`'s contract, forwarded as is.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: as `alloc`.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: `ptr` was allocated by this allocator, i.e. by `System`, with `layout`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was allocated by this allocator, i.e. by `System`, with `layout`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// Runs `f` once to warm up (a first call may initialise lazily, e.g. register a `tracing`
/// callsite), then again, and returns how many allocations the second run made on this
/// thread. Allocations by other threads are not counted; 0 when [`CountingAllocator`] is not
/// the global allocator.
pub fn allocations_during<R>(mut f: impl FnMut() -> R) -> usize {
    std::hint::black_box(f());
    let before = ALLOCATIONS.with(Cell::get);
    std::hint::black_box(f());
    ALLOCATIONS.with(Cell::get) - before
}
