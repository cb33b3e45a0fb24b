//! # `BilinearSurface` against OpenSubdiv's `Bfr` (`SCHEME_BILINEAR`), shape by shape
//!
//! `tests/golden/bilinear_bfr/<shape>.txt.gz` holds what `Bfr` evaluates with the bilinear
//! scheme on every face with a surface of OpenSubdiv's three bilinear regression shapes and of
//! five Catmull-Clark ones (holes, semi-sharp and infinitely sharp creases, a corner, boundary
//! mode `none`, texture seams, triangles, pentagons and hexagons): a quad on the grid
//! `(u, v) = (i/3, j/3)`, any other face on the grid `(s, t) = (i/3, j/3)` of each sub-face,
//! written in `Bfr`'s `(u, v)` of the face ([`Parameterization`]), with the limit of the
//! texture coordinates (made by `scripts/bilinear-limit-bfr-golden.py`, see
//! `tests/golden/README.md`). This test compares, for each shape:
//!
//! 1. **Coverage and layout**: the rows are those of every face with a surface here, each
//!    sub-face's grid in turn, at `Parameterization::to_face` of its `(s, t)`.
//! 2. **Positions**: `|ours − osd| ≤ 1e-12 d`, `d` the diagonal of the input's bounding box.
//! 3. **First derivatives** by `Bfr`'s `(u, v)` (twice those by a sub-face's `(s, t)`):
//!    `|d_ours − d_osd| ≤ 1e-12 max(|d_osd|, d)`, everywhere (a bilinear patch has no
//!    singular point).
//! 4. **Texture coordinates**: [`FaceVaryingSurface::for_scheme`] with the bilinear scheme
//!    equals `Bfr`'s `s t` to 1e-12 in every face-varying mode (bilinear face-varying data is
//!    linear whatever the mode; the script checked that `Bfr`'s rows do not change with
//!    it) and with the shape's own boundary mode.
//!
//! The tags and modes that do not change a bilinear surface (creases, corners, boundary
//! mode, `none` included) are passed as the shapes give them; the script checked that `Bfr`'s
//! rows are the same with every boundary mode. Closed forms on the same shapes (sub-face
//! corners, derivatives against differences, watertightness) are tested below.

use flate2::read::GzDecoder;
use std::collections::BTreeMap;
use std::io::Read;
use std::path::PathBuf;

use subsurf::io::read_obj;
use subsurf::limit::{
    BilinearSurface, Derivatives, FaceVaryingSurface, Order, Parameterization, SurfacePoint,
};
use subsurf::mesh::{FaceVaryingInterpolation, Options, PolyMesh};
use subsurf::Scheme;

type V3 = [f64; 3];

/// Samples per side of each (sub-)face's grid in the golden files.
const GRID: usize = 4;

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: V3) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn golden_dir() -> PathBuf {
    crate_dir().join("tests/golden/bilinear_bfr")
}

/// One row: `face u v px py pz dux duy duz dvx dvy dvz [s t]`.
struct Row {
    face: u32,
    u: f64,
    v: f64,
    p: V3,
    du: V3,
    dv: V3,
    st: Option<[f64; 2]>,
}

fn load(name: &str) -> Vec<Row> {
    let path = golden_dir().join(format!("{name}.txt.gz"));
    let mut text = String::new();
    GzDecoder::new(std::fs::File::open(&path).expect("golden file"))
        .read_to_string(&mut text)
        .expect("gzip");
    let mut rows = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let x: Vec<f64> = (line.split_whitespace())
            .map(|t| t.parse().expect("number"))
            .collect();
        assert!(x.len() == 12 || x.len() == 14, "{name}: {line}");
        rows.push(Row {
            face: x[0] as u32,
            u: x[1],
            v: x[2],
            p: [x[3], x[4], x[5]],
            du: [x[6], x[7], x[8]],
            dv: [x[9], x[10], x[11]],
            st: (x.len() == 14).then(|| [x[12], x[13]]),
        });
    }
    rows
}

/// The shapes with golden data, their meshes and the options of their tags.
fn shapes() -> Vec<(String, PolyMesh, Options)> {
    let mut names: Vec<String> = std::fs::read_dir(golden_dir())
        .expect("tests/golden/bilinear_bfr")
        .filter_map(|e| {
            let f = e.ok()?.file_name().to_string_lossy().into_owned();
            f.strip_suffix(".txt.gz").map(str::to_owned)
        })
        .collect();
    names.sort();
    assert_eq!(names.len(), 8, "{names:?}");
    (names.into_iter())
        .map(|name| {
            let path = crate_dir().join(format!("tests/shapes/osd/{name}.obj"));
            let obj = read_obj(&path).expect("shape");
            let options = obj.options.resolve(Options::default());
            (name, obj.mesh, options)
        })
        .collect()
}

/// The points of the golden layout of `s`: every face with a surface, each sub-face's grid,
/// `s = i/3` outer, `t = j/3` inner; with the face's `(u, v)` of each.
fn layout(s: &BilinearSurface, mesh: &PolyMesh) -> Vec<(SurfacePoint, (f64, f64))> {
    let mut out = Vec::new();
    for f in (0..mesh.num_faces()).filter(|&f| s.has_surface(f)) {
        let param = Parameterization::new(mesh.face(f).len());
        for subface in 0..param.num_subfaces() {
            for k in 0..GRID * GRID {
                let (u, v) = ((k / GRID) as f64 / 3.0, (k % GRID) as f64 / 3.0);
                let p = SurfacePoint {
                    face: f as u32,
                    subface: subface as u32,
                    u,
                    v,
                };
                out.push((p, param.to_face(subface, u, v)));
            }
        }
    }
    out
}

#[test]
fn bilinear_limit_surface_matches_opensubdiv_bfr() {
    let modes = [
        FaceVaryingInterpolation::All,
        FaceVaryingInterpolation::None,
        FaceVaryingInterpolation::CornersPlus1,
    ];
    let mut failures = Vec::new();
    let mut fvar_shapes = 0;
    for (name, mesh, options) in shapes() {
        let mut fail = |s: String| {
            if failures.len() < 40 {
                failures.push(format!("{name}: {s}"));
            }
        };
        let s = BilinearSurface::new(&mesh).expect("surface");
        let rows = load(&name);
        let diag = mesh
            .bounding_box()
            .map_or(1.0, |(lo, hi)| norm(sub(hi, lo)));
        let points = layout(&s, &mesh);
        if points.len() != rows.len() {
            fail(format!("{} rows, {} points here", rows.len(), points.len()));
            continue;
        }
        let pts: Vec<SurfacePoint> = points.iter().map(|x| x.0).collect();
        let got = s.eval_many(&pts, Order::First);
        let uv = mesh.face_varying.iter().position(|c| c.name() == "uv");
        let st: Vec<_> = (modes.iter())
            .filter_map(|&face_varying| {
                let o = Options {
                    face_varying,
                    ..options
                };
                let c = uv?;
                let surface = FaceVaryingSurface::for_scheme(&mesh, Scheme::Bilinear, o, c);
                Some(
                    (surface.map_err(|e| e.to_string()))
                        .and_then(|u| u.eval_many(&pts).map_err(|e| e.to_string())),
                )
            })
            .collect();
        fvar_shapes += usize::from(!st.is_empty());
        for (mode, values) in modes.iter().zip(&st) {
            if let Err(e) = values {
                fail(format!("texture coordinates in mode {mode:?}: {e}"));
            }
        }
        let (mut wp, mut wd, mut wst) = (0.0f64, 0.0f64, 0.0f64);
        for (i, (((p, fuv), r), d)) in points.iter().zip(&rows).zip(&got).enumerate() {
            let at = format!("face {} ({}, {})", r.face, r.u, r.v);
            if (p.face, fuv.0, fuv.1) != (r.face, r.u, r.v) {
                fail(format!(
                    "row {i}: {at}, expected face {} at {fuv:?}",
                    p.face
                ));
                break;
            }
            let d: &Derivatives = match d {
                Ok(d) => d,
                Err(e) => {
                    fail(format!("{at}: {e}"));
                    continue;
                }
            };
            let e = norm(sub(d.p, r.p)) / diag;
            wp = wp.max(e);
            if e > 1e-12 {
                fail(format!("{at}: position {e:.2e}"));
            }
            let k = Parameterization::new(mesh.face(p.face as usize).len()).derivative_scale();
            for (x, y) in [(d.du, r.du), (d.dv, r.dv)] {
                let e = norm(sub(x.map(|c| k * c), y)) / norm(y).max(diag);
                wd = wd.max(e);
                if e > 1e-12 {
                    fail(format!("{at}: derivative {e:.2e}"));
                }
            }
            if r.st.is_none() != st.is_empty() {
                fail(format!("{at}: s t in the golden row and here differ"));
            }
            for (mode, values) in modes.iter().zip(&st) {
                let (Some(want), Ok(values)) = (r.st, values) else {
                    continue;
                };
                let o = values.value_at(i);
                let e = (o[0] - want[0]).abs().max((o[1] - want[1]).abs());
                wst = wst.max(e);
                if e > 1e-12 {
                    fail(format!("{at}: s t {e:.2e} in mode {mode:?}"));
                }
            }
        }
        eprintln!(
            "{name:24} rows {:4}  position {wp:.1e}  derivative {wd:.1e}  st {wst:.1e}",
            rows.len()
        );
    }
    assert_eq!(fvar_shapes, 8, "every shape has texture coordinates");
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The point at fraction `t` along edge `i` (from vertex `i` to `i + 1`) of face `f` of `s`:
/// on a quad the side of the square; on an `n`-gon sub-face `i`'s side `v = 0` for
/// `t ≤ ½`, then sub-face `i + 1`'s side `u = 0` (its `v` runs toward edge `i`'s midpoint).
fn edge_point(s: &BilinearSurface, mesh: &PolyMesh, f: usize, i: usize, t: f64) -> V3 {
    let n = mesh.face(f).len();
    let (subface, u, v) = match (n, i) {
        (4, 0) => (0, t, 0.0),
        (4, 1) => (0, 1.0, t),
        (4, 2) => (0, 1.0 - t, 1.0),
        (4, _) => (0, 0.0, 1.0 - t),
        _ if t <= 0.5 => (i, 2.0 * t, 0.0),
        _ => ((i + 1) % n, 0.0, 2.0 * (1.0 - t)),
    };
    let p = SurfacePoint {
        face: f as u32,
        subface: subface as u32,
        u,
        v,
    };
    s.eval_point(p).expect("eval").p
}

/// A face's use of an edge: the face, the edge's index in it, and whether it runs the edge
/// from its larger vertex to its smaller.
type EdgeUse = (usize, usize, bool);

/// Closed forms on every face of the shapes, quads and others: the corners of each sub-face
/// are the face's vertex, the midpoints of its edges and its centroid; the first derivatives
/// and the twist are the differences of positions; neighbouring faces agree along every
/// edge they share (watertight), within 1e-15 of the diagonal.
#[test]
fn closed_forms_and_watertightness_on_the_shapes() {
    let mut all_shared = 0;
    for (name, mesh, _) in shapes() {
        let s = BilinearSurface::new(&mesh).expect("surface");
        let pos = mesh.positions();
        let diag = mesh
            .bounding_box()
            .map_or(1.0, |(lo, hi)| norm(sub(hi, lo)));
        let tol = 1e-15 * diag;
        let eval = |f: usize, j: usize, u: f64, v: f64| {
            let p = SurfacePoint {
                face: f as u32,
                subface: j as u32,
                u,
                v,
            };
            s.eval_point(p).expect("eval")
        };
        let mid = |a: u32, b: u32| -> V3 {
            std::array::from_fn(|k| 0.5 * (pos[a as usize][k] + pos[b as usize][k]))
        };
        for f in (0..mesh.num_faces()).filter(|&f| s.has_surface(f)) {
            let fv = mesh.face(f);
            let n = fv.len();
            let centroid: V3 = std::array::from_fn(|k| {
                fv.iter().map(|&v| pos[v as usize][k]).sum::<f64>() / n as f64
            });
            for j in 0..s.num_subfaces(f) {
                let corners: [V3; 4] = if n == 4 {
                    std::array::from_fn(|c| pos[fv[c] as usize])
                } else {
                    let (a, b, c) = (fv[(j + n - 1) % n], fv[j], fv[(j + 1) % n]);
                    [pos[b as usize], mid(b, c), centroid, mid(a, b)]
                };
                for (c, (u, v)) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
                    .into_iter()
                    .enumerate()
                {
                    let e = norm(sub(eval(f, j, u, v).p, corners[c]));
                    assert!(e <= tol, "{name}: face {f} sub {j} corner {c}: {e:.1e}");
                }
                let (u, v, h) = (0.4, 0.7, 1e-4);
                let d = eval(f, j, u, v);
                let p = |a: f64, b: f64| eval(f, j, u + a, v + b).p;
                let fd =
                    |a: V3, b: V3, w: f64| -> V3 { std::array::from_fn(|k| (a[k] - b[k]) / w) };
                let du = fd(p(h, 0.0), p(-h, 0.0), 2.0 * h);
                let dv = fd(p(0.0, h), p(0.0, -h), 2.0 * h);
                let duv = fd(
                    fd(p(h, h), p(h, -h), 1.0),
                    fd(p(-h, h), p(-h, -h), 1.0),
                    4.0 * h * h,
                );
                assert!(
                    norm(sub(d.du, du)) <= 1e-9 * diag,
                    "{name}: face {f} sub {j}: du"
                );
                assert!(
                    norm(sub(d.dv, dv)) <= 1e-9 * diag,
                    "{name}: face {f} sub {j}: dv"
                );
                assert!(
                    norm(sub(d.duv, duv)) <= 1e-5 * diag,
                    "{name}: face {f} sub {j}: duv"
                );
                assert_eq!((d.duu, d.dvv), ([0.0; 3], [0.0; 3]));
            }
        }
        // Watertight: the faces around every edge, at the same fraction from its first end.
        let mut edges: BTreeMap<(u32, u32), Vec<EdgeUse>> = BTreeMap::new();
        for f in (0..mesh.num_faces()).filter(|&f| s.has_surface(f)) {
            let fv = mesh.face(f);
            for i in 0..fv.len() {
                let (a, b) = (fv[i], fv[(i + 1) % fv.len()]);
                edges
                    .entry((a.min(b), a.max(b)))
                    .or_default()
                    .push((f, i, a > b));
            }
        }
        let mut shared = 0;
        for faces in edges.values().filter(|x| x.len() > 1) {
            shared += 1;
            for t in [0.0, 0.2, 1.0 / 3.0, 0.5, 0.9, 1.0] {
                let at = |&(f, i, flip): &(usize, usize, bool)| {
                    edge_point(&s, &mesh, f, i, if flip { 1.0 - t } else { t })
                };
                let first = at(&faces[0]);
                for x in &faces[1..] {
                    let e = norm(sub(at(x), first));
                    assert!(
                        e <= tol,
                        "{name}: faces {} and {} at {t}: {e:.1e}",
                        faces[0].0,
                        x.0
                    );
                }
            }
        }
        eprintln!("{name:24} {shared} shared edges");
        all_shared += shared;
    }
    assert!(all_shared > 100, "{all_shared} shared edges");
}
