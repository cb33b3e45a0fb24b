//! # The limit of face-varying data against OpenSubdiv's `Bfr`
//!
//! Each shape of `tests/golden/fvar_limit/` (OpenSubdiv's Catmull-Clark regression shapes
//! with `vt` from `tests/shapes/osd/`, `tests/golden/fvar/textured_cube.obj`, and
//! `tests/golden/fvar_limit/seam_creases.obj`, made for the rules no regression shape
//! reaches: sharp edges on one side of a seam, an infinitely sharp edge inside a subset) was
//! evaluated by OpenSubdiv 3.5 in each of the six face-varying modes (`osd-oracle limit SHAPE
//! 3 --fvar MODE`: `Bfr::SurfaceFactory::InitFaceVaryingSurface` and
//! `Surface<double>::Evaluate` on a 3 × 3 grid of up to 12 quad faces; written by
//! `scripts/fvar-limit-golden.py`, format in `tests/golden/fvar_limit/README.md`).
//! [`FaceVaryingSurface`] is evaluated at the same points and `(s, t)` compared within
//! `1e-12 × d`, `d` the diagonal of the bounding box of the shape's `vt` values (the
//! tolerance the positions' golden test uses, relative to the data's size), except where
//! `Bfr` is itself approximate: see [`BFR_APPROXIMATE`].
//!
//! The same files hold OpenSubdiv's `PrimvarRefiner::LimitFaceVarying` after two levels
//! (`osd-oracle refine SHAPE 2 --fvar MODE --limit`) for some shapes: `subdivide` with
//! `limit` must give the same `vt` values index for index within 1e-12.

use subsurf::io::read_obj;
use subsurf::limit::{FaceVaryingSurface, SurfacePoint};
use subsurf::mesh::{FaceVaryingInterpolation, Options, PolyMesh};
use subsurf::{subdivide, SubdivideOptions};

/// Agreement with `Bfr`, relative to the diagonal of the `vt` values' bounding box.
const TOL: f64 = 1e-12;

/// Vertices where `Bfr` is itself approximate, `(shape, vertex, bound)`: darts (an interior
/// vertex with exactly one infinitely sharp edge), where `Bfr` returns the value of
/// OpenSubdiv's limit masks after 10 levels of refinement, not the limit
/// (`tests/golden/limit/README.md`, "What the data shows about `Bfr`": up to 7.4e-6 of the
/// diagonal for positions). At the samples on these vertices `|ours − osd| ≤ bound × d`.
/// `seam_creases`' vertex 6 ends its infinitely sharp crease `7 6` away from the seam, so
/// the channel's value mesh has the dart in every mode but `all`.
const BFR_APPROXIMATE: &[(&str, u32, f64)] = &[("seam_creases", 6, 1e-6)];

/// The bound on `|ours − osd| / d` at sample `(face, u, v)` of `shape`: [`TOL`], or the
/// bound of a [`BFR_APPROXIMATE`] vertex the sample lies on.
fn bound(shape: &str, mesh: &PolyMesh, face: u32, u: f64, v: f64) -> f64 {
    let corner = match (u, v) {
        (0.0, 0.0) => 0,
        (1.0, 0.0) => 1,
        (1.0, 1.0) => 2,
        (0.0, 1.0) => 3,
        _ => return TOL,
    };
    let vertex = mesh.face(face as usize)[corner];
    (BFR_APPROXIMATE.iter())
        .find(|&&(s, x, _)| s == shape && x == vertex)
        .map_or(TOL, |&(_, _, b)| b)
}

use crate::common::tests_dir as dir;

/// A `limit` row: face, `u`, `v` and OpenSubdiv's `[s, t]`.
type Row = (u32, f64, f64, [f64; 2]);

/// One `limit` case: a mode and its rows `(face, u, v, [s, t])`, or `None` where the oracle
/// crashed.
struct LimitCase {
    mode: FaceVaryingInterpolation,
    rows: Option<Vec<Row>>,
}

/// One `refine-limit` case: a mode, the number of values and samples `(index, [s, t])`.
struct RefineCase {
    mode: FaceVaryingInterpolation,
    values: usize,
    samples: Vec<(usize, [f64; 2])>,
}

enum Case {
    Limit(LimitCase),
    Refine(RefineCase),
}

fn parse(text: &str) -> (String, Vec<Case>) {
    let mut shape = String::new();
    let mut cases = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let t: Vec<&str> = line.split_whitespace().collect();
        let num = |i: usize| -> f64 { t[i].parse().unwrap() };
        match (t.first().copied(), cases.last_mut()) {
            (Some("shape"), _) => shape = t[1].to_string(),
            (Some("limit"), _) => cases.push(Case::Limit(LimitCase {
                mode: t[1].parse().unwrap(),
                rows: (t[2] != "oracle-failed").then(Vec::new),
            })),
            (Some("refine-limit"), _) => cases.push(Case::Refine(RefineCase {
                mode: t[2].parse().unwrap(),
                values: t[4].parse().unwrap(),
                samples: Vec::new(),
            })),
            (Some("end") | None, _) => {}
            (Some(i), Some(Case::Limit(c))) => c.rows.as_mut().expect("rows").push((
                i.parse().unwrap(),
                num(1),
                num(2),
                [num(3), num(4)],
            )),
            (Some(i), Some(Case::Refine(c))) => {
                c.samples.push((i.parse().unwrap(), [num(1), num(2)]))
            }
            (Some(_), None) => panic!("a row before any case"),
        }
    }
    (shape, cases)
}

fn load(shape: &str) -> (PolyMesh, Options) {
    let own = dir("golden/fvar_limit").join(format!("{shape}.obj"));
    let path = if own.exists() {
        own
    } else if shape == "textured_cube" {
        dir("golden/fvar").join("textured_cube.obj")
    } else {
        dir("shapes/osd").join(format!("{shape}.obj"))
    };
    let obj = read_obj(&path).unwrap();
    (obj.mesh, obj.options.resolve(Options::default()))
}

/// Diagonal of the bounding box of the mesh's `uv` values.
fn uv_diagonal(mesh: &PolyMesh) -> f64 {
    let uv = &mesh.face_varying[0];
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for i in 0..uv.num_values() {
        for k in 0..2 {
            lo[k] = lo[k].min(uv.value(i)[k]);
            hi[k] = hi[k].max(uv.value(i)[k]);
        }
    }
    ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt()
}

/// The problems of one `limit` case and its largest error relative to `d`.
fn check_limit(
    shape: &str,
    mesh: &PolyMesh,
    options: Options,
    c: &LimitCase,
) -> (Vec<String>, f64) {
    let Some(rows) = &c.rows else {
        return (Vec::new(), 0.0);
    };
    let at = format!("{shape} limit {}", c.mode);
    let options = Options {
        face_varying: c.mode,
        ..options
    };
    let surface = match FaceVaryingSurface::new(mesh, options, 0) {
        Ok(s) => s,
        Err(e) => return (vec![format!("{at}: {e}")], f64::INFINITY),
    };
    let d = uv_diagonal(mesh);
    let points: Vec<SurfacePoint> = (rows.iter())
        .map(|&(face, u, v, _)| SurfacePoint {
            face,
            subface: 0,
            u,
            v,
        })
        .collect();
    let got = match surface.eval_many(&points) {
        Ok(g) => g,
        Err(e) => return (vec![format!("{at}: {e}")], f64::INFINITY),
    };
    let (mut problems, mut worst) = (Vec::new(), 0.0f64);
    for (i, &(face, u, v, st)) in rows.iter().enumerate() {
        let x = got.value_at(i);
        let e = (x[0] - st[0]).abs().max((x[1] - st[1]).abs()) / d;
        worst = worst.max(e);
        if e > bound(shape, mesh, face, u, v) {
            problems.push(format!(
                "{at}: face {face} ({u}, {v}): {x:?}, expected {st:?} (error {e:.1e} × d)"
            ));
        }
    }
    (problems, worst)
}

/// The problems of one `refine-limit` case and its largest error.
fn check_refine(
    shape: &str,
    mesh: &PolyMesh,
    options: Options,
    c: &RefineCase,
) -> (Vec<String>, f64) {
    let at = format!("{shape} refine-limit {}", c.mode);
    let opts = SubdivideOptions {
        levels: 2,
        options: Options {
            face_varying: c.mode,
            ..options
        },
        limit: true,
        ..Default::default()
    };
    let out = subdivide(mesh, &opts).unwrap().mesh;
    let uv = &out.face_varying[0];
    if uv.num_values() != c.values {
        return (
            vec![format!(
                "{at}: {} values, expected {}",
                uv.num_values(),
                c.values
            )],
            f64::INFINITY,
        );
    }
    let (mut problems, mut worst) = (Vec::new(), 0.0f64);
    for &(i, st) in &c.samples {
        let x = uv.value(i);
        let e = (x[0] - st[0]).abs().max((x[1] - st[1]).abs());
        worst = worst.max(e);
        if e > 1e-12 {
            problems.push(format!(
                "{at}: value {i} is {x:?}, expected {st:?} (error {e:.1e})"
            ));
        }
    }
    (problems, worst)
}

#[test]
fn face_varying_limit_matches_opensubdiv() {
    let files = crate::common::golden_texts("golden/fvar_limit");
    assert!(files.len() >= 70, "golden files missing: {}", files.len());
    let mut problems = Vec::new();
    for text in files {
        let (shape, cases) = parse(&text);
        let (mesh, options) = load(&shape);
        let (mut lim, mut refined) = (0.0f64, 0.0f64);
        for c in &cases {
            let (p, w) = match c {
                Case::Limit(c) => check_limit(&shape, &mesh, options, c),
                Case::Refine(c) => check_refine(&shape, &mesh, options, c),
            };
            match c {
                Case::Limit(_) => lim = lim.max(w),
                Case::Refine(_) => refined = refined.max(w),
            }
            problems.extend(p);
        }
        println!("{shape:28} limit {lim:.1e} × d   refine --limit {refined:.1e}");
    }
    let n = problems.len();
    problems.truncate(60);
    assert!(n == 0, "{n} problems:\n{}", problems.join("\n"));
}
