//! Memory guards: the limit a job is held to (`--max-memory`, else the memory available),
//! the checks of estimates against it, the three-step guard of limit surfaces
//! ([`SurfaceGuard`]), and the allocator's settings per job (huge pages for large
//! refinements, freed memory kept for refinement and returned at once otherwise).

use std::borrow::Cow;
use std::sync::atomic::{AtomicI64, Ordering};

use subsurf::limit::{BuildError, LimitSurface};
use subsurf::mesh::{Options, PolyMesh};

/// The memory the system reports as available (Linux `/proc/meminfo` `MemAvailable`), or
/// `None` where that is not known (the job then runs without a cap).
pub fn available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// Lets the kernel back this process's memory with transparent huge pages from now on, or
/// stops it (Linux's `prctl(PR_SET_THP_DISABLE)`; nothing elsewhere).
///
/// The allocator (mimalloc) asks for huge pages on its arenas. They pay for the jobs that
/// write hundreds of MB of fresh buffers (refinement): one page fault per 2 MiB instead of
/// per 4 KiB. The other jobs allocate many small blocks (a limit surface's nodes and
/// configuration trees) spread over the arena, and each 2 MiB page touched is resident
/// whole, which raises their peak at no gain in speed (BENCHMARKS.md, "Allocator settings,
/// kept buffers and memory estimates"). A page faulted in huge stays huge, so they are off
/// from the start of the job ([`allocator_at_start`]) and refinement turns them
/// back on when it is large enough ([`for_refinement`]).
pub fn huge_pages(on: bool) {
    #[cfg(target_os = "linux")]
    // SAFETY: `PR_SET_THP_DISABLE` takes integer arguments only and changes a flag of the
    // process, no memory; a failure (an old kernel) leaves the setting as it was, which
    // costs only speed or memory.
    unsafe {
        libc::prctl(libc::PR_SET_THP_DISABLE, libc::c_ulong::from(!on), 0, 0, 0);
    }
    #[cfg(not(target_os = "linux"))]
    let _ = on;
}

/// Estimated job size (bytes) from which refinement runs on huge pages ([`for_refinement`]).
///
/// Each thread's partly used 2 MiB pages stay resident whole, which below about this size
/// puts the peak above OpenSubdiv's for the same refinement; from here on their speed is
/// worth more than that and the peak stays below OpenSubdiv's (the measurements are in
/// BENCHMARKS.md, "Allocator settings, kept buffers and memory estimates").
pub const HUGE_PAGES_FROM: u64 = 128 << 20;

/// mimalloc's `mi_option_purge_delay` (its `mimalloc.h`, the same index in its versions 2
/// and 3; the `libmimalloc-sys` bindings do not name it): how many milliseconds freed
/// memory stays committed, for reuse, before it is returned to the system (0: at once).
const MI_OPTION_PURGE_DELAY: libmimalloc_sys::mi_option_t = 15;

// `mimalloc.h` lists the purge delay between these two options, which the bindings name.
const _: () = assert!(
    MI_OPTION_PURGE_DELAY == libmimalloc_sys::mi_option_eager_commit_delay + 1
        && MI_OPTION_PURGE_DELAY + 1 == libmimalloc_sys::mi_option_use_numa_nodes
);

/// How long refinement keeps freed memory for reuse, in milliseconds, unless the
/// environment sets `MIMALLOC_PURGE_DELAY`: one second, well above mimalloc 2's own
/// default.
///
/// A `bench` repetition, or a level of a large refinement, frees its buffers a little
/// before the next one needs as many again. With the allocator's default delay they are
/// mostly returned and faulted in again, which slows refinement at no saving in peak
/// memory (BENCHMARKS.md, "Allocator settings, kept buffers and memory estimates").
pub const REFINEMENT_PURGE_DELAY_MS: i64 = 1000;

/// The allocator's purge delay for refinement, which [`for_refinement`] sets:
/// [`REFINEMENT_PURGE_DELAY_MS`], or the `MIMALLOC_PURGE_DELAY` of the environment;
/// [`UNCHANGED`] until [`allocator_at_start`] runs.
static KEPT_PURGE_DELAY: AtomicI64 = AtomicI64::new(UNCHANGED);

/// [`KEPT_PURGE_DELAY`] before [`allocator_at_start`]: the option was never changed.
const UNCHANGED: i64 = i64::MIN;

/// Whether the allocator keeps freed memory for reuse (mimalloc's purge delay at
/// [`KEPT_PURGE_DELAY`]) or returns it to the system at once (a delay of 0).
///
/// Refinement frees each level's buffers and allocates the next, larger, ones: kept
/// memory is reused without faulting pages in again. The other jobs allocate as they
/// build (a limit surface, a tessellation's arrays) and then work in place: there the
/// memory kept only adds to the peak, the blocks of every growing array and the parser's
/// buffers staying resident after they are freed (BENCHMARKS.md, "Allocator settings,
/// kept buffers and memory estimates").
pub fn keep_freed_memory(keep: bool) {
    let delay = match KEPT_PURGE_DELAY.load(Ordering::Relaxed) {
        UNCHANGED => return,
        _ if !keep => 0,
        kept => kept,
    };
    // SAFETY: setting an option of the allocator is one store into its table of options,
    // allowed at any time and from any thread (mimalloc reads them as it purges).
    unsafe { libmimalloc_sys::mi_option_set(MI_OPTION_PURGE_DELAY, delay as _) }
}

/// Returns the memory freed so far to the system now, whatever the purge delay
/// ([`keep_freed_memory`]; mimalloc's `mi_collect(true)`, which also purges the memory
/// other threads freed).
///
/// For a job that builds something, frees the build's temporaries and then allocates its
/// working buffers once (a re-posing plan, then the re-posed points): kept, the freed
/// blocks may not be where the buffers go, and the buffers' fresh pages add to them.
/// Returning them first lowers the peak at the same speed, as a re-posing with kept
/// buffers allocates nothing (BENCHMARKS.md, "Allocator settings, kept buffers and memory
/// estimates").
pub fn return_freed_memory() {
    // SAFETY: a collection takes no arguments and touches only the allocator's own state;
    // it is allowed from any thread at any time.
    unsafe { libmimalloc_sys::mi_collect(true) }
}

/// Prepares the allocator for a refinement estimated to need `estimate` bytes: freed
/// memory kept for reuse ([`keep_freed_memory`]), and huge pages ([`huge_pages`]) if
/// `estimate` is at least [`HUGE_PAGES_FROM`] (below it they stay off).
pub fn for_refinement(estimate: u64) {
    keep_freed_memory(true);
    if estimate >= HUGE_PAGES_FROM {
        huge_pages(true);
    }
}

/// Sets the allocator up for every job but refinement: huge pages off ([`huge_pages`]) and
/// freed memory returned at once ([`keep_freed_memory`]); refinement changes both back
/// ([`for_refinement`]). `main` calls it first, before a command reads its input: the few
/// pages the start-up allocated stay as they are, every later one follows these settings.
pub fn allocator_at_start() {
    huge_pages(false);
    let delay = if std::env::var_os("MIMALLOC_PURGE_DELAY").is_some() {
        // SAFETY: reading an option only reads the environment and the option table.
        let delay = unsafe { libmimalloc_sys::mi_option_get(MI_OPTION_PURGE_DELAY) };
        #[allow(clippy::useless_conversion)] // `c_long` is 32 bits on some targets.
        i64::from(delay)
    } else {
        REFINEMENT_PURGE_DELAY_MS
    };
    KEPT_PURGE_DELAY.store(delay, Ordering::Relaxed);
    keep_freed_memory(false);
}

/// Refuses a job estimated to need `estimate` bytes when that exceeds `max` (the
/// `--max-memory` cap) or, without a cap, the memory the system reports as available:
/// the error is `NAME: WHAT needs about X MiB, more than the limit of Y MiB (WHICH); HINT`,
/// and nothing has been allocated or written yet.
pub fn check(
    name: &str,
    what: &str,
    estimate: u64,
    max: Option<u64>,
    hint: &str,
) -> anyhow::Result<()> {
    check_against(
        name,
        what,
        estimate,
        max.or_else(available),
        max.is_some(),
        hint,
    )
}

/// [`check`] against `limit` (`capped`: the `--max-memory` cap, else the memory
/// available; `None`: not known, no check).
fn check_against(
    name: &str,
    what: &str,
    estimate: u64,
    limit: Option<u64>,
    capped: bool,
    hint: &str,
) -> anyhow::Result<()> {
    match limit {
        Some(limit) if estimate > limit => Err(too_large(
            name,
            what,
            (estimate, false),
            limit,
            capped,
            hint,
        )),
        _ => Ok(()),
    }
}

/// The error of a job estimated to need `estimate` bytes, more than `limit` (`capped`:
/// the `--max-memory` cap, else the memory available): `NAME: WHAT needs about X MiB,
/// more than the limit of Y MiB (WHICH); HINT`, or `needs at least` for an estimate
/// known to be low (`at_least`).
pub fn too_large(
    name: &str,
    what: &str,
    (estimate, at_least): (u64, bool),
    limit: u64,
    capped: bool,
    hint: &str,
) -> anyhow::Error {
    anyhow::anyhow!(
        "{name}: {what} needs {} {}, more than the limit of {}{}; {hint}",
        if at_least { "at least" } else { "about" },
        size(estimate),
        size(limit),
        which(capped),
    )
}

/// Which limit a job was held to: `--max-memory` (`capped`) or the memory available.
fn which(capped: bool) -> &'static str {
    if capped {
        " (--max-memory)"
    } else {
        " (the memory available)"
    }
}

/// `bytes` in MiB (rounded up), in KiB below 1 MiB, in bytes below 1 KiB.
pub fn size(bytes: u64) -> String {
    if bytes < 1 << 10 {
        format!("{bytes} bytes")
    } else if bytes < 1 << 20 {
        format!("{} KiB", bytes.div_ceil(1 << 10))
    } else {
        format!("{} MiB", bytes.div_ceil(1 << 20))
    }
}

/// The memory guard of a job that builds an exact limit surface and evaluates it
/// (`limit`, `tessellate`, `bench --limit-grid`), in the library's three steps (see
/// `subsurf::limit::LimitSurface::new_within`): refused before building when the surface
/// without its configurations and the job's own buffers (`reserved`) would not fit, the
/// build stopped as soon as the configurations it finds would not, and refused before any
/// point is evaluated when the evaluation would not. The limit (`--max-memory`, else the
/// memory available) is read once, before the job allocates.
pub struct SurfaceGuard<'a> {
    /// The input's name (errors start with it).
    pub name: &'a str,
    /// What the job does, as in "tessellating at rate 8".
    pub what: String,
    /// The `--max-memory` cap.
    pub max: Option<u64>,
    /// What to do when the evaluation would not fit, as in "use a lower --rate".
    pub hint: &'a str,
    /// Whether the job evaluates quads only (grids, as `osd-oracle limit` and `benchlimit`
    /// sample), so that the surface of other faces is not built.
    pub quads_only: bool,
}

impl SurfaceGuard<'_> {
    /// The limit surface of `mesh`, for a job that evaluates points `1 / divisions` of a
    /// face's side apart and needs `reserved` bytes of its own besides.
    pub fn limit_surface<'a>(
        &self,
        mesh: impl Into<Cow<'a, PolyMesh>>,
        options: Options,
        divisions: u32,
        reserved: u64,
    ) -> anyhow::Result<LimitSurface> {
        use anyhow::Context as _;
        let mesh = mesh.into();
        let limit = self.max.or_else(available);
        let check = |estimate: u64| {
            check_against(
                self.name,
                &self.what,
                estimate,
                limit,
                self.max.is_some(),
                self.hint,
            )
        };
        check(LimitSurface::estimate_build_memory(&mesh).saturating_add(reserved))?;
        let mut builder = LimitSurface::builder(mesh, options);
        if self.quads_only {
            builder = builder.faces(|_, verts| verts.len() == 4);
        }
        if let Some(limit) = limit {
            builder = builder.max_bytes(limit.saturating_sub(reserved));
        }
        let surface = match builder.build() {
            Err(BuildError::TooLarge { configurations, .. }) => anyhow::bail!(
                "{}: {} needs more than {}{}: building the limit surface stopped after \
                 finding {configurations} distinct neighbourhoods of irregular faces \
                 (configurations), more than fit",
                self.name,
                self.what,
                size(limit.unwrap_or(u64::MAX)),
                which(self.max.is_some()),
            ),
            built => built.with_context(|| self.name.to_owned())?,
        };
        check(surface.estimate_memory(divisions).saturating_add(reserved))?;
        Ok(surface)
    }

    /// A Loop or bilinear limit surface (`build`) whose estimated memory is `surface`
    /// bytes ([`LoopSurface::estimate_memory`](subsurf::limit::LoopSurface::estimate_memory):
    /// the topology, the points and the configuration trees it may keep; for bilinear, the
    /// topology and the points, [`LimitSurface::estimate_build_memory`]), for a job that
    /// needs `reserved` bytes of its own besides.
    pub fn local_surface<S, E>(
        &self,
        surface: u64,
        reserved: u64,
        build: impl FnOnce() -> Result<S, E>,
    ) -> anyhow::Result<S>
    where
        E: std::error::Error + Send + Sync + 'static,
    {
        use anyhow::Context as _;
        let estimate = surface.saturating_add(reserved);
        check(self.name, &self.what, estimate, self.max, self.hint)?;
        build().with_context(|| self.name.to_owned())
    }
}

/// Samples of an `n`×`n` grid on every quad face of `mesh` and on every sub-face of its
/// other faces (what `limit --grid n` evaluates, holes included).
pub fn grid_samples(mesh: &subsurf::mesh::PolyMesh, n: u32) -> u64 {
    let subfaces = mesh
        .faces()
        .map(|f| if f.len() == 4 { 1 } else { f.len() as u64 })
        .fold(0u64, u64::saturating_add);
    subfaces.saturating_mul(u64::from(n) * u64::from(n))
}

/// An upper bound of the vertices a tessellation at `rate` has: `(rate + 1)²` per quad,
/// `n (rate/2 + 1)²` per `n`-gon (its sub-faces; the rate rounded up to even), as if no
/// sample were shared.
pub fn tessellation_vertices(mesh: &subsurf::mesh::PolyMesh, rate: u32) -> u64 {
    let r = u64::from(rate);
    let half = r.div_ceil(2);
    mesh.faces()
        .map(|f| match f.len() {
            4 => (r + 1).saturating_mul(r + 1),
            n => (n as u64).saturating_mul((half + 1).saturating_mul(half + 1)),
        })
        .fold(0u64, u64::saturating_add)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The process's transparent-huge-page flag as the kernel reports it (`THP_enabled` of
    /// `/proc/self/status`, Linux 5.0 on), if it does.
    #[cfg(target_os = "linux")]
    fn thp_enabled() -> Option<bool> {
        let status = std::fs::read_to_string("/proc/self/status").ok()?;
        let line = status.lines().find(|l| l.starts_with("THP_enabled:"))?;
        Some(line.split_whitespace().nth(1)? == "1")
    }

    /// The allocator's purge delay (see `keep_freed_memory`) as it is now.
    fn purge_delay() -> i64 {
        // SAFETY: reading an option of the allocator.
        #[allow(clippy::useless_conversion)] // `c_long` is 32 bits on some targets.
        i64::from(unsafe { libmimalloc_sys::mi_option_get(MI_OPTION_PURGE_DELAY) })
    }

    /// Huge pages are off once `allocator_at_start` ran (as `main` does first), `huge_pages` turns them on and off again, and `for_refinement` turns them on
    /// from `HUGE_PAGES_FROM` bytes only; freed memory is returned at once from the start
    /// and kept again for any refinement. (One test: both settings are the whole
    /// process's.)
    #[cfg(target_os = "linux")]
    #[test]
    fn the_allocator_is_set_for_limit_jobs_from_the_start_and_for_refinement_on_request() {
        allocator_at_start();
        let kept = KEPT_PURGE_DELAY.load(Ordering::Relaxed);
        assert_ne!(kept, UNCHANGED, "allocator_at_start did not set the delay");
        if std::env::var_os("MIMALLOC_PURGE_DELAY").is_none() {
            assert_eq!(kept, REFINEMENT_PURGE_DELAY_MS);
        }
        assert_eq!(
            purge_delay(),
            0,
            "freed memory is returned at once from the start"
        );
        keep_freed_memory(true);
        assert_eq!(purge_delay(), kept);
        keep_freed_memory(false);
        assert_eq!(purge_delay(), 0);
        let Some(start) = thp_enabled() else {
            return; // A kernel that does not report the flag.
        };
        assert!(!start, "allocator_at_start did not turn huge pages off");
        huge_pages(true);
        assert_eq!(thp_enabled(), Some(true));
        huge_pages(false);
        assert_eq!(thp_enabled(), Some(false));
        for_refinement(HUGE_PAGES_FROM - 1);
        assert_eq!(purge_delay(), kept, "refinement does not keep freed memory");
        assert_eq!(
            thp_enabled(),
            Some(false),
            "a small job turned huge pages on"
        );
        for_refinement(HUGE_PAGES_FROM);
        assert_eq!(thp_enabled(), Some(true), "a large job left huge pages off");
        huge_pages(false);
        keep_freed_memory(false);
    }

    fn quad_and_triangle() -> subsurf::mesh::PolyMesh {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
        ];
        let faces: Vec<Vec<u32>> = vec![vec![0, 1, 2, 3], vec![1, 4, 2]];
        subsurf::mesh::PolyMesh::from_faces(p, &faces).expect("valid mesh")
    }

    #[test]
    fn counts_are_upper_bounds_of_the_output() {
        let m = quad_and_triangle();
        // The quad's 5 × 5 grid and one per sub-face of the triangle.
        assert_eq!(grid_samples(&m, 5), 25 + 3 * 25);
        // Rate 4: the quad 5 × 5 samples, the triangle 3 sub-faces of 3 × 3.
        assert_eq!(tessellation_vertices(&m, 4), 25 + 27);
        // Rate 3 is rounded up to 4 for the triangle.
        assert_eq!(tessellation_vertices(&m, 3), 16 + 27);
        assert_eq!(tessellation_vertices(&m, u32::MAX), u64::MAX);
    }

    /// The surface guard refuses in each of its three steps: before building (the cap
    /// below the surface without configurations), while building (the cap below the
    /// first configuration), and before evaluating (the cap below the evaluation's
    /// levels); with the cap at the estimate the surface is built.
    #[test]
    fn surface_guard_refuses_before_building_while_building_and_before_evaluating() {
        let mesh = quad_and_triangle();
        let options = Options::default();
        let reserved = 1000;
        let guard = |max: u64| SurfaceGuard {
            name: "in.obj",
            what: "sampling".to_owned(),
            max: Some(max),
            hint: "use less",
            quads_only: false,
        };
        let build = LimitSurface::estimate_build_memory(&mesh) + reserved;
        let e = guard(build - 1)
            .limit_surface(&mesh, options, 4, reserved)
            .expect_err("below the surface without configurations");
        assert!(
            e.to_string().starts_with("in.obj: sampling needs about"),
            "{e}"
        );
        let e = guard(build)
            .limit_surface(&mesh, options, 4, reserved)
            .expect_err("below the first configuration");
        assert!(
            e.to_string().contains("building the limit surface stopped"),
            "{e}"
        );
        let s = LimitSurface::new(&mesh, options).expect("surface");
        assert!(s.num_configurations() > 0);
        let (shallow, deep) = (s.estimate_memory(4), s.estimate_memory(1 << 10));
        assert!(shallow < deep);
        let e = guard(deep + reserved - 1)
            .limit_surface(&mesh, options, 1 << 10, reserved)
            .expect_err("below the evaluation");
        assert_eq!(
            e.to_string(),
            format!(
                "in.obj: sampling needs about {}, more than the limit of {} (--max-memory); \
                 use less",
                size(deep + reserved),
                size(deep + reserved - 1)
            )
        );
        let built = guard(deep + reserved)
            .limit_surface(&mesh, options, 1 << 10, reserved)
            .expect("within the cap");
        assert_eq!(built.num_configurations(), s.num_configurations());
    }

    #[test]
    fn check_refuses_above_the_cap_only() {
        assert!(check("in.obj", "x", 1 << 20, Some(1 << 20), "h").is_ok());
        assert_eq!(size(1000), "1000 bytes");
        assert_eq!(size(1025), "2 KiB");
        assert_eq!(size((1 << 20) + 1), "2 MiB");
        let e = check(
            "in.obj",
            "sampling",
            (3 << 20) + 1,
            Some(2 << 20),
            "use less",
        )
        .expect_err("over the cap");
        assert_eq!(
            e.to_string(),
            "in.obj: sampling needs about 4 MiB, more than the limit of 2 MiB (--max-memory); \
             use less"
        );
    }
}
