//! Heap allocations of an update, counted by this test binary's own allocator: a skipped
//! frame (a still camera once nothing changes) allocates nothing.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

use dynlod::camera_path::{frame_bounds, CameraPath};
use dynlod::lod::{Runtime, RuntimeOptions};
use dynlod::BuildOptions;

/// The system allocator, counting allocations and reallocations (every thread's).
struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Relaxed);
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

/// The bunny under a still camera: the cold start allocates (which shows the counter sees the
/// runtime's allocations), and once frames are skipped they allocate nothing.
#[test]
fn a_skipped_frame_allocates_nothing() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let m = dynlod::load_mesh(path, BuildOptions::default()).unwrap();
    let (centre, diag) = frame_bounds(&m.positions);
    let view = CameraPath::Orbit.view(30, 360, centre, diag, (1920, 1080));
    let mut rt = Runtime::new(m, RuntimeOptions::default());
    let (mut full, mut skipped) = (Vec::new(), Vec::new());
    for _ in 0..100 {
        let before = ALLOCATIONS.load(Relaxed);
        let s = rt.update(Some(&view));
        let n = ALLOCATIONS.load(Relaxed) - before;
        if s.skipped {
            skipped.push(n)
        } else {
            full.push(n)
        }
    }
    assert!(skipped.len() > 40, "{} frames skipped", skipped.len());
    assert!(full[0] > 1000, "the cold start allocated {} times", full[0]);
    assert!(skipped.iter().all(|&n| n == 0), "skipped frames allocated: {skipped:?}");
}
