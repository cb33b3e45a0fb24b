//! # subsurf against OpenSubdiv, shape by shape
//!
//! Every one of OpenSubdiv's 87 Catmull-Clark regression shapes (`tests/shapes/osd/catmark_*.obj`, copied verbatim
//! from OpenSubdiv 3.6.0) is refined with Catmull-Clark to levels 1, 2, 3 and 4, once plainly
//! ("refine") and once with the last level's vertices moved to their limit positions ("limit"),
//! and the result is compared with what OpenSubdiv 3.5 itself computed for the same file
//! (`tests/golden/osd/<shape>.txt.gz`, written by `scripts/make-golden.sh` through the
//! `osd-oracle` program over Debian's `libosd-dev`; format and provenance in
//! `tests/golden/README.md`). The boundary mode is the shape's `t interpolateboundary` tag
//! (edge-only when absent), recorded in the golden file; crease method and triangle rule come
//! from the shape's tags, read by both sides.
//!
//! ## What must agree, for every shape × level × mode
//!
//! 1. **Vertex count**: all vertices of the last level, in OpenSubdiv's sense — including
//!    vertices used only by hole faces, which are refined but not written.
//! 2. **Faces**: the number of faces written (holes left out), the histogram of their sizes,
//!    and the face list itself, exactly and in order, through an FNV-1a 64-bit hash over, for
//!    each face, its size and then its 0-based vertex indices, each as a little-endian `u32`
//!    (offset basis `0xcbf29ce484222325`, prime `0x100000001b3`).
//! 3. **Positions, index for index**: up to 256 vertices per case (all of them when N ≤ 256,
//!    else the indices ⌊k·N/256⌋, k = 0..255) must be within
//!    `tol = 1e-12 × (diagonal of the input mesh's bounding box)` of OpenSubdiv's, measured as
//!    the largest absolute coordinate difference.
//! 4. **Sums over all vertices**: Σx, Σy, Σz within `tol·N`, and Σ|p|² within
//!    `4·tol·N·(max|p| + 1)`. A wrong vertex that the samples miss still moves these.
//!
//! ## Why vertices can be compared by index
//!
//! subsurf does not merely produce the same surface as OpenSubdiv; it numbers what it
//! produces the same way. At each level, OpenSubdiv's uniform refinement (`Vtr`, as used by
//! `Far::TopologyRefiner::RefineUniform` with default options) appends the child vertices of
//! the parent *vertices* first, then those of the parent *faces*, then those of the parent
//! *edges*, each group in parent order, and it makes the child faces of each parent face in
//! face order, one per corner. subsurf follows that order (and OpenSubdiv's edge numbering),
//! so vertex `i` here and vertex `i` in OpenSubdiv are the same point of the same surface.
//! Check 2 proves the numbering agrees for faces — with identical face lists, a permutation of
//! vertices would show up as different indices — and check 3 then compares positions without
//! any nearest-neighbour matching, which could hide swapped or duplicated vertices.
//!
//! ## Reading the result
//!
//! `osd_golden_all_shapes` runs everything, gathers *every* difference into one report (shape,
//! level, mode, what differs, largest error and where) and fails once at the end. With
//! `cargo test -p subsurf --test integration osd_golden:: -- --nocapture` it also prints a table of
//! the largest sampled error per shape, relative to the input's bounding-box diagonal (the check
//! is ≤ 1e-12). A case on which the oracle itself failed (`oracle-failed` in the golden file)
//! is skipped with a note.

use flate2::read::GzDecoder;
use std::cell::{Cell, RefCell};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Read;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, Once};

use subsurf::io::read_obj;
use subsurf::mesh::{BoundaryInterpolation, Options, PolyMesh};
use subsurf::{subdivide, SubdivideOptions};

/// Relative tolerance: OpenSubdiv agreement to 1e-12 of the input's size.
const REL_TOL: f64 = 1e-12;
/// Levels and modes recorded for every shape.
const LEVELS: [u32; 4] = [1, 2, 3, 4];
/// Vertices sampled per case when there are more.
const SAMPLES: usize = 256;

// ---------------------------------------------------------------------------------------------
// Golden data
// ---------------------------------------------------------------------------------------------

/// One golden file: what OpenSubdiv produced for one shape.
#[derive(Debug)]
pub(super) struct Golden {
    pub(super) name: String,
    pub(super) boundary: BoundaryInterpolation,
    pub(super) cases: Vec<GoldenCase>,
}

#[derive(Debug)]
pub(super) struct GoldenCase {
    pub(super) level: u32,
    pub(super) limit: bool,
    pub(super) expect: Expect,
}

#[derive(Debug)]
pub(super) enum Expect {
    /// The oracle did not produce this case (the reason it gave).
    OracleFailed(String),
    Data(CaseData),
}

#[derive(Debug)]
pub(super) struct CaseData {
    pub(super) verts: usize,
    faces: usize,
    /// Face size → count.
    pub(super) sizes: BTreeMap<usize, usize>,
    facehash: u64,
    /// Σx, Σy, Σz, Σ(x²+y²+z²).
    sums: [f64; 4],
    /// (index, position) as OpenSubdiv printed them.
    pub(super) samples: Vec<(usize, [f64; 3])>,
}

pub(super) fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub(super) fn shapes_dir() -> PathBuf {
    crate_dir().join("tests/shapes/osd")
}

fn golden_dir() -> PathBuf {
    crate_dir().join("tests/golden/osd")
}

/// Names (without `.obj`) of all Catmull-Clark shapes, sorted.
fn shape_names() -> Vec<String> {
    shape_names_with_prefix("catmark_")
}

/// Names (without `.obj`) of the shapes whose names start with `prefix` (the scheme's
/// name), sorted.
pub(super) fn shape_names_with_prefix(prefix: &str) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(shapes_dir())
        .expect("tests/shapes/osd is missing")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter_map(|f| f.strip_suffix(".obj").map(str::to_owned))
        .filter(|f| f.starts_with(prefix))
        .collect();
    names.sort();
    assert!(!names.is_empty(), "no {prefix}* shapes in tests/shapes/osd");
    names
}

fn load_golden(name: &str) -> Result<Golden, String> {
    load_golden_from(&golden_dir(), name)
}

/// The golden file `DIR/<name>.txt.gz`.
pub(super) fn load_golden_from(dir: &std::path::Path, name: &str) -> Result<Golden, String> {
    let path = dir.join(format!("{name}.txt.gz"));
    let file = std::fs::File::open(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut text = String::new();
    GzDecoder::new(file)
        .read_to_string(&mut text)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    parse_golden(&text).map_err(|e| format!("{}: {e}", path.display()))
}

fn parse_golden(text: &str) -> Result<Golden, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.starts_with('#') && !l.trim().is_empty());
    let (ln, head) = lines.next().ok_or("empty file")?;
    let head: Vec<&str> = head.split_whitespace().collect();
    let (name, boundary) = match head.as_slice() {
        ["shape", name, "boundary", b] => (
            name.to_string(),
            b.parse::<BoundaryInterpolation>()
                .map_err(|e| format!("line {ln}: {e}"))?,
        ),
        _ => return Err(format!("line {ln}: expected 'shape NAME boundary MODE'")),
    };
    let mut cases = Vec::new();
    let mut current: Option<(u32, bool, CaseData)> = None;
    for (ln, line) in lines {
        let err = |what: &str| format!("line {ln}: {what}: {line}");
        let tok: Vec<&str> = line.split_whitespace().collect();
        if let Some((level, limit, data)) = current.as_mut() {
            if tok == ["end"] {
                let (level, limit, data) = (*level, *limit, std::mem::replace(data, empty_case()));
                cases.push(GoldenCase {
                    level,
                    limit,
                    expect: Expect::Data(data),
                });
                current = None;
                continue;
            }
            let [i, x, y, z] = tok.as_slice() else {
                return Err(err("expected 'idx x y z'"));
            };
            let f = |s: &str| s.parse::<f64>().map_err(|_| err("bad number"));
            let i: usize = i.parse().map_err(|_| err("bad index"))?;
            data.samples.push((i, [f(x)?, f(y)?, f(z)?]));
            continue;
        }
        if tok.first() != Some(&"case") || tok.len() < 4 {
            return Err(err("expected 'case'"));
        }
        let level: u32 = tok[1].parse().map_err(|_| err("bad level"))?;
        let limit = match tok[2] {
            "refine" => false,
            "limit" => true,
            _ => return Err(err("mode must be refine or limit")),
        };
        if tok[3] == "oracle-failed" {
            let reason = tok[4..].join(" ");
            cases.push(GoldenCase {
                level,
                limit,
                expect: Expect::OracleFailed(reason),
            });
            continue;
        }
        let [_, _, _, "verts", n, "faces", f, "sizes", sizes, "facehash", h, "sum", sx, sy, sz, sq] =
            tok.as_slice()
        else {
            return Err(err("malformed case line"));
        };
        let num = |s: &str| s.parse::<f64>().map_err(|_| err("bad number"));
        let mut data = CaseData {
            verts: n.parse().map_err(|_| err("bad vertex count"))?,
            faces: f.parse().map_err(|_| err("bad face count"))?,
            sizes: BTreeMap::new(),
            facehash: u64::from_str_radix(h, 16).map_err(|_| err("bad facehash"))?,
            sums: [num(sx)?, num(sy)?, num(sz)?, num(sq)?],
            samples: Vec::new(),
        };
        if *sizes != "-" {
            for kv in sizes.split(',') {
                let (k, c) = kv.split_once(':').ok_or_else(|| err("bad sizes"))?;
                data.sizes.insert(
                    k.parse().map_err(|_| err("bad sizes"))?,
                    c.parse().map_err(|_| err("bad sizes"))?,
                );
            }
        }
        current = Some((level, limit, data));
    }
    if current.is_some() {
        return Err("last case has no 'end'".into());
    }
    Ok(Golden {
        name,
        boundary,
        cases,
    })
}

fn empty_case() -> CaseData {
    CaseData {
        verts: 0,
        faces: 0,
        sizes: BTreeMap::new(),
        facehash: 0,
        sums: [0.0; 4],
        samples: Vec::new(),
    }
}

/// The indices that are sampled out of `n` vertices.
pub(super) fn sample_indices(n: usize) -> Vec<usize> {
    if n <= SAMPLES {
        (0..n).collect()
    } else {
        (0..SAMPLES).map(|k| k * n / SAMPLES).collect()
    }
}

/// FNV-1a 64 over each face's size and 0-based vertex indices, as little-endian `u32`s.
fn face_hash(mesh: &PolyMesh) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |x: u32| {
        for b in x.to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for f in mesh.faces() {
        eat(f.len() as u32);
        for &v in f {
            eat(v);
        }
    }
    h
}

fn face_sizes(mesh: &PolyMesh) -> BTreeMap<usize, usize> {
    let mut sizes = BTreeMap::new();
    for f in mesh.faces() {
        *sizes.entry(f.len()).or_insert(0) += 1;
    }
    sizes
}

fn fmt_sizes(sizes: &BTreeMap<usize, usize>) -> String {
    if sizes.is_empty() {
        return "-".into();
    }
    sizes
        .iter()
        .map(|(k, c)| format!("{k}:{c}"))
        .collect::<Vec<_>>()
        .join(",")
}

pub(super) fn diagonal(mesh: &PolyMesh) -> f64 {
    match mesh.bounding_box() {
        Some((lo, hi)) => {
            ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt()
        }
        None => 0.0,
    }
}

fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "(non-string panic)".into()
    }
}

thread_local! {
    /// Set while `quiet_catch` runs on this thread: panics are recorded, not printed.
    static QUIET: Cell<bool> = const { Cell::new(false) };
    static LAST_PANIC: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// Runs `f`, turning a panic into `Err("message at file:line")` for the report instead of
/// printing it (hundreds of identical panic messages would bury the report). Panics elsewhere,
/// and on other threads, are printed as usual.
pub(super) fn quiet_catch<R>(f: impl FnOnce() -> R) -> Result<R, String> {
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if QUIET.with(Cell::get) {
                let at = info
                    .location()
                    .map(|l| format!(" (at {}:{})", l.file(), l.line()));
                let msg = format!(
                    "{}{}",
                    panic_message(info.payload()),
                    at.unwrap_or_default()
                );
                LAST_PANIC.with(|p| *p.borrow_mut() = Some(msg));
            } else {
                previous(info);
            }
        }));
    });
    QUIET.with(|q| q.set(true));
    let r = catch_unwind(AssertUnwindSafe(f));
    QUIET.with(|q| q.set(false));
    r.map_err(|p| {
        LAST_PANIC
            .with(|l| l.borrow_mut().take())
            .unwrap_or_else(|| panic_message(&*p))
    })
}

fn mode(limit: bool) -> &'static str {
    if limit {
        "limit"
    } else {
        "refine"
    }
}

// ---------------------------------------------------------------------------------------------
// Comparison
// ---------------------------------------------------------------------------------------------

/// Everything found for one shape.
#[derive(Default)]
struct ShapeReport {
    name: String,
    boundary: String,
    /// Input bounding-box diagonal.
    diag: f64,
    /// (level, limit) → largest sampled error relative to `diag`, when positions were compared.
    max_rel_err: BTreeMap<(u32, bool), f64>,
    /// Cases that failed, for the table.
    failed_cases: Vec<(u32, bool)>,
    /// One line per difference.
    failures: Vec<String>,
    /// Skipped cases and other remarks.
    notes: Vec<String>,
}

fn check_shape(name: &str) -> ShapeReport {
    let mut rep = ShapeReport {
        name: name.to_owned(),
        ..Default::default()
    };
    let golden = match load_golden(name) {
        Ok(g) => g,
        Err(e) => {
            rep.failures
                .push(format!("{name}: cannot read golden data: {e}"));
            return rep;
        }
    };
    rep.boundary = golden.boundary.to_string();
    let path = shapes_dir().join(format!("{name}.obj"));
    let obj = match quiet_catch(|| read_obj(&path)) {
        Ok(Ok(obj)) => obj,
        Ok(Err(e)) => {
            rep.failures.push(format!("{name}: read_obj failed: {e}"));
            rep.failed_cases = all_cases(&golden);
            return rep;
        }
        Err(p) => {
            rep.failures.push(format!("{name}: read_obj panicked: {p}"));
            rep.failed_cases = all_cases(&golden);
            return rep;
        }
    };
    let mut scheme: Options = obj.options.resolve(Options::default());
    if scheme.boundary != golden.boundary {
        rep.failures.push(format!(
            "{name}: boundary from the file's tags is {} but OpenSubdiv was run with {} \
             (compared with {} below)",
            scheme.boundary, golden.boundary, golden.boundary
        ));
        scheme.boundary = golden.boundary;
    }
    rep.diag = diagonal(&obj.mesh);
    let tol = REL_TOL * rep.diag;

    for case in &golden.cases {
        let what = format!("{name} level {} {}", case.level, mode(case.limit));
        let data = match &case.expect {
            Expect::OracleFailed(why) => {
                rep.notes
                    .push(format!("{what}: skipped, the oracle failed ({why})"));
                continue;
            }
            Expect::Data(d) => d,
        };
        let opts = SubdivideOptions {
            levels: case.level,
            scheme: subsurf::Scheme::CatmullClark,
            options: scheme,
            limit: case.limit,
            keep_holes: false,
            max_memory: None,
        };
        let out = match quiet_catch(|| subdivide(&obj.mesh, &opts)) {
            Ok(Ok(out)) => out,
            Ok(Err(e)) => {
                rep.failures.push(format!("{what}: subdivide failed: {e}"));
                rep.failed_cases.push((case.level, case.limit));
                continue;
            }
            Err(p) => {
                rep.failures
                    .push(format!("{what}: subdivide panicked: {p}"));
                rep.failed_cases.push((case.level, case.limit));
                continue;
            }
        };
        let before = rep.failures.len();
        compare_case(
            &what,
            &out.mesh,
            data,
            tol,
            rep.diag,
            &mut rep.failures,
            |e| {
                rep.max_rel_err.insert((case.level, case.limit), e);
            },
        );
        if rep.failures.len() > before {
            rep.failed_cases.push((case.level, case.limit));
        }
    }
    rep
}

fn all_cases(golden: &Golden) -> Vec<(u32, bool)> {
    golden.cases.iter().map(|c| (c.level, c.limit)).collect()
}

/// Compares one refined mesh with OpenSubdiv's; pushes one line per kind of difference and
/// reports the largest sampled error relative to `diag` through `max_err`.
pub(super) fn compare_case(
    what: &str,
    mesh: &PolyMesh,
    want: &CaseData,
    tol: f64,
    diag: f64,
    failures: &mut Vec<String>,
    max_err: impl FnOnce(f64),
) {
    // 1. Vertex count.
    let n = mesh.num_vertices();
    if n != want.verts {
        failures.push(format!(
            "{what}: {n} vertices, OpenSubdiv has {}",
            want.verts
        ));
    }

    // 2. Faces: count, sizes, order.
    let sizes = face_sizes(mesh);
    if mesh.num_faces() != want.faces || sizes != want.sizes {
        failures.push(format!(
            "{what}: {} faces (sizes {}), OpenSubdiv has {} (sizes {})",
            mesh.num_faces(),
            fmt_sizes(&sizes),
            want.faces,
            fmt_sizes(&want.sizes)
        ));
    }
    let hash = face_hash(mesh);
    if hash != want.facehash {
        let first = first_faces(mesh);
        failures.push(format!(
            "{what}: face list differs from OpenSubdiv's (facehash {hash:016x} vs {:016x}){first}",
            want.facehash
        ));
    }
    if n != want.verts {
        return; // indices mean different vertices: positions cannot be compared
    }

    // 3. Sampled positions, index for index.
    let pos = mesh.positions();
    let (mut worst, mut worst_err, mut bad) =
        (want.samples.first().map_or(0, |s| s.0), 0.0f64, 0usize);
    for &(i, p) in &want.samples {
        let q = pos[i];
        let e = (0..3).map(|k| (q[k] - p[k]).abs()).fold(0.0, f64::max);
        let e = if e.is_nan() || q.iter().any(|x| x.is_nan()) {
            f64::INFINITY
        } else {
            e
        };
        if e > tol {
            bad += 1;
        }
        if e > worst_err {
            worst_err = e;
            worst = i;
        }
    }
    max_err(if diag > 0.0 {
        worst_err / diag
    } else {
        worst_err
    });
    if bad > 0 {
        let p = pos[worst];
        let w = want
            .samples
            .iter()
            .find(|s| s.0 == worst)
            .map(|s| s.1)
            .unwrap_or_default();
        failures.push(format!(
            "{what}: {bad} of {} sampled vertices off by more than tol {tol:.3e}; \
             max error {worst_err:.3e} ({:.2e} x diag) at vertex {worst}: ours {p:?}, OpenSubdiv {w:?}",
            want.samples.len(),
            worst_err / diag
        ));
    }

    // 4. Sums over all vertices.
    let mut s = [0.0f64; 4];
    let mut max_norm = 0.0f64;
    for p in pos {
        s[0] += p[0];
        s[1] += p[1];
        s[2] += p[2];
        let q = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
        s[3] += q;
        max_norm = max_norm.max(q.sqrt());
    }
    let nf = n as f64;
    let bounds = [
        tol * nf,
        tol * nf,
        tol * nf,
        4.0 * tol * nf * (max_norm + 1.0),
    ];
    let names = ["sum x", "sum y", "sum z", "sum |p|^2"];
    for k in 0..4 {
        let d = (s[k] - want.sums[k]).abs();
        if d.is_nan() || d > bounds[k] {
            failures.push(format!(
                "{what}: {} over all {n} vertices is {:.17e}, OpenSubdiv {:.17e} (difference {d:.3e} > {:.3e})",
                names[k], s[k], want.sums[k], bounds[k]
            ));
        }
    }
}

/// Our first faces, to help read a face-list difference (only OpenSubdiv's hash is stored).
fn first_faces(mesh: &PolyMesh) -> String {
    let first: Vec<String> = mesh.faces().take(2).map(|f| format!("{f:?}")).collect();
    if first.is_empty() {
        String::new()
    } else {
        format!("; our first faces: {}", first.join(" "))
    }
}

/// Runs `check_shape` over `names` on all cores, results in the order of `names`.
fn check_shapes(names: &[String]) -> Vec<ShapeReport> {
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<ShapeReport>>> =
        Mutex::new((0..names.len()).map(|_| None).collect());
    let workers = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(names.len())
        .max(1);
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= names.len() {
                    break;
                }
                let rep = check_shape(&names[i]);
                results.lock().unwrap()[i] = Some(rep);
            });
        }
    });
    results
        .into_inner()
        .unwrap()
        .into_iter()
        .map(|r| r.expect("worker died"))
        .collect()
}

/// The table of largest sampled errors (relative to the input diagonal) and, when anything
/// differs, the full failure report.
fn report(reports: &[ShapeReport]) -> (String, String) {
    let mut table = String::new();
    let _ = writeln!(
        table,
        "largest sampled error / input bounding-box diagonal (check: <= {REL_TOL:e}); * = case failed, - = not compared"
    );
    let _ = write!(table, "{:<28} {:<16} {:>9} ", "shape", "boundary", "diag");
    for limit in [false, true] {
        for l in LEVELS {
            let _ = write!(
                table,
                " {:>8}",
                format!("{}{l}", if limit { "lim" } else { "ref" })
            );
        }
    }
    table.push('\n');
    for r in reports {
        let diag = if r.diag > 0.0 {
            format!("{:.3e}", r.diag)
        } else {
            "-".into()
        };
        let _ = write!(table, "{:<28} {:<16} {diag:>9} ", r.name, r.boundary);
        for limit in [false, true] {
            for l in LEVELS {
                let failed = r.failed_cases.contains(&(l, limit));
                let cell = match r.max_rel_err.get(&(l, limit)) {
                    Some(&0.0) => "0".to_string(),
                    Some(&e) => format!("{e:.1e}"),
                    None => "-".to_string(),
                };
                let _ = write!(
                    table,
                    " {:>8}",
                    if failed { format!("{cell}*") } else { cell }
                );
            }
        }
        table.push('\n');
    }
    let mut fails = String::new();
    for r in reports {
        for f in &r.failures {
            let _ = writeln!(fails, "  {f}");
        }
    }
    let notes: Vec<&String> = reports.iter().flat_map(|r| &r.notes).collect();
    if !notes.is_empty() {
        let _ = writeln!(table, "notes:");
        for n in notes {
            let _ = writeln!(table, "  {n}");
        }
    }
    (table, fails)
}

fn run_and_report(names: &[String]) {
    let reports = check_shapes(names);
    let (table, fails) = report(&reports);
    println!("{table}");
    if !fails.is_empty() {
        let shapes = reports.iter().filter(|r| !r.failures.is_empty()).count();
        let cases: usize = reports.iter().map(|r| r.failed_cases.len()).sum();
        panic!(
            "subsurf differs from OpenSubdiv on {shapes} of {} shapes ({cases} failed cases):\n{fails}",
            reports.len()
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------------------------

/// Every shape, levels 1-4, refined and limit: see the module documentation.
#[test]
fn osd_golden_all_shapes() {
    run_and_report(&shape_names());
}

/// Boundary mode edge-only (`t interpolateboundary 1/0/0 2`): a quad grid with boundary
/// corners that stay smooth.
#[test]
fn osd_golden_boundary_edge_only() {
    run_and_report(&["catmark_edgeonly".to_owned()]);
}

/// Boundary mode edge-and-corner (`t interpolateboundary 1/0/0 1`): boundary corners stay put.
#[test]
fn osd_golden_boundary_edge_and_corner() {
    run_and_report(&["catmark_edgecorner".to_owned()]);
}

/// Boundary mode none (`t interpolateboundary 1/0/0 0`): faces at the boundary become holes;
/// they shape their neighbours but are not written.
#[test]
fn osd_golden_boundary_none() {
    run_and_report(&["catmark_edgenone".to_owned()]);
}

/// The golden data itself, without the library: one file per shape and no strays, the
/// boundary recorded matches the shape's `t interpolateboundary` tag, every level and mode is
/// present, samples are at the documented indices, histograms add up to the face counts.
#[test]
fn osd_golden_data_is_complete() {
    let names = shape_names();
    let mut problems = Vec::new();
    let mut strays: Vec<String> = std::fs::read_dir(golden_dir())
        .expect("tests/golden/osd is missing")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter_map(|f| f.strip_suffix(".txt.gz").map(str::to_owned))
        .filter(|g| !names.contains(g))
        .collect();
    strays.sort();
    for s in strays {
        problems.push(format!("golden file {s}.txt.gz has no shape"));
    }
    for name in &names {
        let g = match load_golden(name) {
            Ok(g) => g,
            Err(e) => {
                problems.push(e);
                continue;
            }
        };
        if g.name != *name {
            problems.push(format!("{name}: golden file names shape {}", g.name));
        }
        let obj_text = std::fs::read_to_string(shapes_dir().join(format!("{name}.obj"))).unwrap();
        let tagged = boundary_tag(&obj_text);
        if g.boundary != tagged {
            problems.push(format!(
                "{name}: golden boundary {} but the shape's tag says {tagged}",
                g.boundary
            ));
        }
        let mut seen: Vec<(u32, bool)> = g.cases.iter().map(|c| (c.level, c.limit)).collect();
        seen.sort();
        let want: Vec<(u32, bool)> = LEVELS
            .iter()
            .flat_map(|&l| [(l, false), (l, true)])
            .collect();
        if seen != want {
            problems.push(format!("{name}: cases {seen:?}, expected {want:?}"));
        }
        for c in &g.cases {
            let Expect::Data(d) = &c.expect else { continue };
            let idx: Vec<usize> = d.samples.iter().map(|s| s.0).collect();
            if idx != sample_indices(d.verts) {
                problems.push(format!(
                    "{name} level {} {}: sample indices are not the documented ones",
                    c.level,
                    mode(c.limit)
                ));
            }
            if d.sizes.values().sum::<usize>() != d.faces {
                problems.push(format!(
                    "{name} level {} {}: size histogram does not add up",
                    c.level,
                    mode(c.limit)
                ));
            }
            if d.samples.iter().any(|s| s.1.iter().any(|x| !x.is_finite()))
                || d.sums.iter().any(|x| !x.is_finite())
            {
                problems.push(format!(
                    "{name} level {} {}: non-finite values",
                    c.level,
                    mode(c.limit)
                ));
            }
        }
    }
    assert!(
        problems.is_empty(),
        "golden data problems:\n  {}",
        problems.join("\n  ")
    );
}

/// The boundary mode a shape's OBJ text asks for, read directly from its tags (independent of
/// the library's reader): `t interpolateboundary 1/0/0 K`, edge-only when absent.
pub(super) fn boundary_tag(obj: &str) -> BoundaryInterpolation {
    let mut b = BoundaryInterpolation::EdgeOnly;
    for line in obj.lines() {
        let t: Vec<&str> = line.split_whitespace().collect();
        if t.len() >= 4 && t[0] == "t" && t[1] == "interpolateboundary" {
            b = BoundaryInterpolation::from_tag_value(t[3].parse().unwrap()).unwrap();
        }
    }
    b
}

/// The face hash is the one `scripts/golden.py` computes: the constant below is its value for
/// the faces `[0 1 2] [0 2 3]` (bytes `03000000 00000000 01000000 02000000 03000000 00000000
/// 02000000 03000000`), so the two implementations cannot drift apart unnoticed.
#[test]
fn face_hash_matches_golden_py() {
    let m = PolyMesh::from_faces(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        &[vec![0u32, 1, 2], vec![0, 2, 3]],
    )
    .unwrap();
    assert_eq!(format!("{:016x}", face_hash(&m)), "652180a55d53e897");
}
