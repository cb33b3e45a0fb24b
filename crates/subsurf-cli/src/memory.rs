//! How much memory a job may use when `--max-memory` is not given.

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
/// write hundreds of MB of fresh buffers (refinement): one fault per 2 MiB instead of per
/// 4 KiB, 15 % of the time of a 4 M-vertex refinement. The other jobs allocate many small
/// blocks (a limit surface's nodes and configuration trees) spread over the arena, and
/// each 2 MiB page touched is resident whole: `bench --limit-grid 8` on `catmark_bishop`
/// peaked at 29 MiB with huge pages and 14 MiB without, at the same speed. A page faulted
/// in huge stays huge, so they are off from before the first allocation
/// ([`HUGE_PAGES_OFF_AT_START`]) and refinement turns them back on when it is large
/// enough ([`huge_pages_for`]).
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

/// Estimated job size (bytes) from which refinement runs on huge pages ([`huge_pages_for`]).
///
/// Each thread's partly used 2 MiB pages stay resident whole, 10–40 MiB over the job on
/// two threads, which below about this size put the peak above OpenSubdiv's for the
/// same refinement (`catmark_bishop` level 4, estimated 37 MiB: 88 MiB with huge pages,
/// 75 MiB without, OpenSubdiv 50 MiB; `catmark_pawn` level 5, 92 MiB: 124, 112 and 121
/// MiB). From here on their speed is worth more than that (two threads: `catmark_pawn`
/// level 5 26 % faster, `catmark_bishop` level 4 17 %) and the peak stays below
/// OpenSubdiv's (`catmark_bishop` level 5, 147 MiB: 154 MiB against 190 MiB).
pub const HUGE_PAGES_FROM: u64 = 128 << 20;

/// Turns huge pages on ([`huge_pages`]) for a refinement estimated to need `estimate`
/// bytes, if that is at least [`HUGE_PAGES_FROM`]; below it they stay off.
pub fn huge_pages_for(estimate: u64) {
    if estimate >= HUGE_PAGES_FROM {
        huge_pages(true);
    }
}

/// Turns huge pages off ([`huge_pages`]) before the allocator's first page is touched: a
/// constructor of priority 100, which runs before mimalloc's (priority 101, which
/// reserves its first arena) and so before the first allocation (the standard library's
/// own constructor, priority 99, only stores the program's arguments). Turned off in
/// `main` instead, a huge page faulted in before it stayed resident: 3–4 MiB of every
/// job's peak.
#[cfg(target_os = "linux")]
#[used]
#[link_section = ".init_array.00100"]
pub static HUGE_PAGES_OFF_AT_START: extern "C" fn() = {
    extern "C" fn off() {
        huge_pages(false);
    }
    off
};

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
    let Some(limit) = max.or_else(available) else {
        return Ok(());
    };
    if estimate > limit {
        anyhow::bail!(
            "{name}: {what} needs about {}, more than the limit of {}{}; {hint}",
            size(estimate),
            size(limit),
            if max.is_some() {
                " (--max-memory)"
            } else {
                " (the memory available)"
            },
        );
    }
    Ok(())
}

/// `bytes` in MiB (rounded up), or in KiB below 1 MiB.
pub fn size(bytes: u64) -> String {
    if bytes < 1 << 20 {
        format!("{} KiB", bytes.div_ceil(1 << 10))
    } else {
        format!("{} MiB", bytes.div_ceil(1 << 20))
    }
}

/// Bytes per regular face (a quad whose vertices all have four faces) of a
/// [`subsurf::limit::LimitSurface`], an upper bound (measured peak above an empty job:
/// 0.43 KiB per face on a 240 000-quad mesh, 0.8 KiB on a 15 000-quad one, 1.2 KiB with an
/// 8×8 grid evaluated, input included).
pub const SURFACE_BYTES_PER_FACE: u64 = 4 << 10;

/// Bytes per face that is not a quad of a limit surface before evaluation: each such
/// face's neighbourhood is a configuration tree, shared with the faces whose
/// neighbourhood is the same. The bound is for faces that share none: measured when the
/// key of a configuration still depended on the corners faces are listed from and nearly
/// every triangle of a scan had its own, `rocker-arm` (20 088 triangles, 19 826
/// configurations) peaked at 19 KiB per face with an 8×8 grid evaluated on its (no)
/// quads, `cow` (5 804 triangles, 4 060) at 14 KiB. Meshes whose faces share
/// configurations take far less (`rocker-arm` now 376 configurations, 1.6 KiB per face;
/// 30 k triangles of a refined quad mesh, 744 configurations: 1.5 KiB); an estimate from
/// the configurations would have to find them first, which is most of building the
/// surface.
pub const NON_QUAD_BYTES: u64 = 32 << 10;

/// Bytes per face that is not a quad and per level of its tree that evaluation builds, one
/// level per halving of the spacing of the samples (`ceil(log2 n)` levels for `n` samples
/// along a side): `rocker-arm` tessellated at rate 2 peaked at 41 KiB per face, at rate 8
/// at 152 KiB; `cow` at 30 and 110 KiB.
pub const NON_QUAD_LEVEL_BYTES: u64 = 48 << 10;

/// Bytes per quad with a vertex that does not have four faces (next to an extraordinary
/// vertex or a boundary), and per level of its tree evaluated, on top of
/// [`SURFACE_BYTES_PER_FACE`]: `suzanne` (500 faces, 222 such quads, 32 triangles, 246
/// configurations) peaked at 10 MiB above an empty job with an 8×8 grid evaluated, 26 MiB
/// tessellated at rate 8 (the tessellation included); this bound gives 18 and 28 MiB.
pub const IRREGULAR_QUAD_LEVEL_BYTES: u64 = 20 << 10;

/// Estimated memory of the exact limit surface of `mesh` (plus the mesh itself), with
/// `samples` points along each side of the quads evaluated (and of the sub-faces of the
/// other faces, if `all_faces`), `l = ceil(log2 samples)` levels: per vertex and per quad
/// [`SURFACE_BYTES_PER_FACE`], per quad with a vertex that does not have four faces
/// `l` × [`IRREGULAR_QUAD_LEVEL_BYTES`] more, per other face [`NON_QUAD_BYTES`] and, if
/// evaluated, `l` × [`NON_QUAD_LEVEL_BYTES`]. An upper bound on the meshes measured; on
/// meshes whose irregular faces share their neighbourhoods (refined meshes, most quad
/// models) 3–20× above the peak.
pub fn surface(mesh: &subsurf::mesh::PolyMesh, samples: u32, all_faces: bool) -> u64 {
    let mut faces_at = vec![0u32; mesh.num_vertices()];
    for f in mesh.faces() {
        for &v in f {
            if let Some(n) = faces_at.get_mut(v as usize) {
                *n = n.saturating_add(1);
            }
        }
    }
    // ceil(log2 samples), without overflow at u32::MAX.
    let levels = u64::from(u32::BITS - (samples.max(1) - 1).leading_zeros());
    let mut bytes = (mesh.num_vertices() as u64).saturating_mul(SURFACE_BYTES_PER_FACE);
    for f in mesh.faces() {
        let face = if f.len() != 4 {
            let evaluated = if all_faces { levels } else { 0 };
            NON_QUAD_BYTES.saturating_add(NON_QUAD_LEVEL_BYTES.saturating_mul(evaluated))
        } else if f.iter().all(|&v| faces_at.get(v as usize) == Some(&4)) {
            SURFACE_BYTES_PER_FACE
        } else {
            SURFACE_BYTES_PER_FACE.saturating_add(IRREGULAR_QUAD_LEVEL_BYTES.saturating_mul(levels))
        };
        bytes = bytes.saturating_add(face);
    }
    bytes
}

/// Samples of an `n`×`n` grid on every quad face of `mesh` (what `limit --grid n` and
/// `bench --limit-grid n` evaluate).
pub fn grid_samples(mesh: &subsurf::mesh::PolyMesh, n: u32) -> u64 {
    let quads = mesh.faces().filter(|f| f.len() == 4).count() as u64;
    quads.saturating_mul(u64::from(n) * u64::from(n))
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

    /// Huge pages are off from the start of the process (the constructor ran before any
    /// test), `huge_pages` turns them on and off again, and `huge_pages_for` turns them on
    /// from `HUGE_PAGES_FROM` bytes only. (One test: the flag is the whole process's.)
    #[cfg(target_os = "linux")]
    #[test]
    fn huge_pages_are_off_from_the_start_and_switchable() {
        let Some(start) = thp_enabled() else {
            return; // A kernel that does not report the flag.
        };
        assert!(!start, "the constructor did not turn huge pages off");
        huge_pages(true);
        assert_eq!(thp_enabled(), Some(true));
        huge_pages(false);
        assert_eq!(thp_enabled(), Some(false));
        huge_pages_for(HUGE_PAGES_FROM - 1);
        assert_eq!(
            thp_enabled(),
            Some(false),
            "a small job turned huge pages on"
        );
        huge_pages_for(HUGE_PAGES_FROM);
        assert_eq!(thp_enabled(), Some(true), "a large job left huge pages off");
        huge_pages(false);
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
        assert_eq!(grid_samples(&m, 5), 25);
        // Rate 4: the quad 5 × 5 samples, the triangle 3 sub-faces of 3 × 3.
        assert_eq!(tessellation_vertices(&m, 4), 25 + 27);
        // Rate 3 is rounded up to 4 for the triangle.
        assert_eq!(tessellation_vertices(&m, 3), 16 + 27);
        assert_eq!(tessellation_vertices(&m, u32::MAX), u64::MAX);
    }

    /// The surface estimate charges each kind of face its bound: regular quads (all four
    /// vertices with four faces) the least, quads at other vertices more per level
    /// evaluated, other faces the most, and their levels only when they are evaluated.
    #[test]
    fn surface_estimate_charges_irregular_faces_by_level() {
        let (k, v) = (SURFACE_BYTES_PER_FACE, 5 * SURFACE_BYTES_PER_FACE);
        // A quad and a triangle: no vertex has four faces.
        let mesh = quad_and_triangle();
        assert_eq!(surface(&mesh, 1, false), v + k + NON_QUAD_BYTES);
        assert_eq!(surface(&mesh, 1, true), v + k + NON_QUAD_BYTES);
        let quad8 = k + 3 * IRREGULAR_QUAD_LEVEL_BYTES;
        assert_eq!(surface(&mesh, 8, false), v + quad8 + NON_QUAD_BYTES);
        assert_eq!(
            surface(&mesh, 8, true),
            v + quad8 + NON_QUAD_BYTES + 3 * NON_QUAD_LEVEL_BYTES
        );
        // A 3×3 grid of quads: only the middle one is regular.
        let p: Vec<[f64; 3]> = (0..16)
            .map(|i| [(i % 4) as f64, (i / 4) as f64, 0.0])
            .collect();
        let faces: Vec<[u32; 4]> = (0..9)
            .map(|q| {
                let c = (q % 3 + 4 * (q / 3)) as u32;
                [c, c + 1, c + 5, c + 4]
            })
            .collect();
        let grid = subsurf::mesh::PolyMesh::from_faces(p, &faces).expect("valid mesh");
        let per_level = 8 * IRREGULAR_QUAD_LEVEL_BYTES;
        assert_eq!(surface(&grid, 1, false), 25 * k);
        assert_eq!(surface(&grid, 4, true), 25 * k + 2 * per_level);
        // 32 levels for the largest count, without overflow (tests run unoptimised too).
        let all = v + k + 32 * IRREGULAR_QUAD_LEVEL_BYTES + NON_QUAD_BYTES;
        assert_eq!(
            surface(&mesh, u32::MAX, true),
            all + 32 * NON_QUAD_LEVEL_BYTES
        );
    }

    #[test]
    fn check_refuses_above_the_cap_only() {
        assert!(check("in.obj", "x", 1 << 20, Some(1 << 20), "h").is_ok());
        assert_eq!(size(1000), "1 KiB");
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
