//! `RefinePlan::apply_into` allocates nothing once its output and scratch buffers have their
//! sizes (its documented promise, which re-posing every frame relies on): checked with a
//! counting global allocator, on shapes whose plans have sparse rows, plain patches and
//! edge patches (boundaries, creases), Loop's ring patches and bilinear's face patches,
//! for positions and for a wider primvar.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use subsurf::io::read_obj;
use subsurf::mesh::Options;
use subsurf::refine::{PlanScratch, RefinePlan};

/// The system allocator, counting allocations.
struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to `System`; the counter has no effect on the memory.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        System.alloc(layout)
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Applies the plan twice into the same buffers and returns the allocations of the second.
fn second_apply_allocations<const D: usize>(plan: &RefinePlan, base: &[[f64; D]]) -> usize {
    let mut out = Vec::new();
    let mut scratch = PlanScratch::default();
    plan.apply_into(base, &mut out, &mut scratch);
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    plan.apply_into(base, &mut out, &mut scratch);
    ALLOCATIONS.load(Ordering::Relaxed) - before
}

#[test]
fn apply_into_does_not_allocate() {
    // One thread: nothing else in the process allocates while the second apply runs.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    use subsurf::Scheme;
    for (name, scheme) in [
        ("catmark_pawn", Scheme::CatmullClark),
        ("catmark_quadstrips", Scheme::CatmullClark),
        ("catmark_inf_crease1", Scheme::CatmullClark),
        ("loop_pole360", Scheme::Loop),
        ("loop_cube_creases1", Scheme::Loop),
        ("catmark_nonquads", Scheme::Bilinear),
    ] {
        let path = format!("{}/tests/shapes/osd/{name}.obj", env!("CARGO_MANIFEST_DIR"));
        let obj = read_obj(Path::new(&path)).unwrap();
        let options = obj.options.resolve(Options::default());
        let plan = RefinePlan::new(&obj.mesh, scheme, options, 4).unwrap();
        assert!(plan.num_patches() > 0, "{name}");
        let pos = obj.mesh.positions();
        let wide: Vec<[f64; 5]> = pos.iter().map(|p| [p[0], p[1], p[2], 1.0, 0.5]).collect();
        pool.install(|| {
            assert_eq!(second_apply_allocations(&plan, pos), 0, "{name}, positions");
            assert_eq!(
                second_apply_allocations(&plan, &wide),
                0,
                "{name}, 5 components"
            );
        });
    }
}
