//! `Renderer::render_into` allocates nothing for a frame of the same size, triangles and
//! depths as the previous one (new positions every frame), with and without depth levels;
//! a change of depths re-sorts without growing its buffers. Checked with a counting global
//! allocator: its own test binary, because the allocator is global.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use bunraku::render::{RenderOptions, Renderer};
use common::Grid;

/// Counts the allocations of the threads that are counting. `GlobalAlloc`'s own
/// `alloc_zeroed` and `realloc` allocate through `alloc`, so counting there counts them all.
struct Counting;

thread_local! {
    /// This thread's count, while it counts.
    static COUNT: Cell<Option<usize>> = const { Cell::new(None) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // `try_with`: the thread-local may already be gone while a thread shuts down.
        let _ = COUNT.try_with(|c| c.set(c.get().map(|n| n + 1)));
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The number of allocations `f` makes on this thread.
fn allocations<R>(f: impl FnOnce() -> R) -> (usize, R) {
    COUNT.with(|c| c.set(Some(0)));
    let r = f();
    (COUNT.with(|c| c.take()).unwrap_or(0), r)
}

#[test]
fn frames_with_unchanged_triangles_and_depths_allocate_nothing() {
    // The counter works: building a vector does allocate.
    assert!(allocations(|| vec![1u8; 10]).0 >= 1);
    let rgba: Vec<u8> = (0..16 * 16).flat_map(|k| [k as u8, 255 - k as u8, 90, 255]).collect();
    let mut renderer = Renderer::new(&rgba, 16, 16).unwrap();
    let shape = Grid::new(10, 8).jitter(0.2, 5).shape();
    let uvs: Vec<[f32; 2]> =
        shape.vertices.iter().map(|p| [(p[0] / 10.0) as f32, (p[1] / 8.0) as f32]).collect();
    // A fold: the right half swung over the left, in front of it, in 3 depth levels.
    let pose = |f: usize| -> Vec<[f64; 2]> {
        let a = 2.6 + 0.01 * f as f64;
        shape
            .vertices
            .iter()
            .map(|p| {
                let (x, y) = (p[0] - 5.0, p[1]);
                let x = if x > 0.0 { x * a.cos() } else { x };
                [40.0 + 6.0 * x, 10.0 + 6.0 * y + 0.3 * f as f64]
            })
            .collect()
    };
    let depth: Vec<f64> = shape
        .triangles
        .iter()
        .map(|t| (t.iter().map(|&v| shape.vertices[v as usize][0]).sum::<f64>() / 10.0).floor())
        .collect();
    let (w, h) = (100u32, 80u32);
    let mut out = vec![0u8; (w * h * 4) as usize];
    for options in [RenderOptions::new(), RenderOptions::new().with_depth(depth.clone())] {
        renderer.render_into(&mut out, &pose(0), &shape.triangles, &uvs, w, h, &options).unwrap();
        for f in 1..4 {
            let positions = pose(f);
            let (n, r) = allocations(|| {
                renderer.render_into(&mut out, &positions, &shape.triangles, &uvs, w, h, &options)
            });
            r.unwrap();
            assert_eq!(
                n,
                0,
                "frame {f} ({} depth) allocated {n} times",
                if options.depth.is_some() { "with" } else { "without" }
            );
        }
    }
    // New depths (the same number of levels): re-sorted in the buffers already there.
    let other: Vec<f64> = depth.iter().map(|d| 2.0 - d).collect();
    let options = RenderOptions::new().with_depth(other);
    let positions = pose(5);
    let (n, r) =
        allocations(|| renderer.render_into(&mut out, &positions, &shape.triangles, &uvs, w, h, &options));
    r.unwrap();
    assert!(n <= 1, "re-sorting for new depths allocated {n} times (the edge list of each level)");
}
