//! # The shape-adjustable Catmull-Clark scheme and mixed subdivision, as specified
//!
//! - `c = ½` is Catmull-Clark exactly: on every OpenSubdiv regression shape, levels 1–4,
//!   refined and at the limit, the adjustable scheme reproduces OpenSubdiv's own results
//!   (the golden files of `osd_golden.rs`) within 1e-12 of the bounding-box diagonal.
//! - `c = 0` leaves the control mesh fixed: old vertices stay, edge points are midpoints and
//!   face points centroids.
//! - On a regular grid one step is the tensor product of the curve scheme
//!   `p'₂ᵢ = (c/4) pᵢ₋₁ + (1 − c/2) pᵢ + (c/4) pᵢ₊₁`, `p'₂ᵢ₊₁ = (pᵢ + pᵢ₊₁)/2`, computed here
//!   independently by refining rows, then columns (closed grids; open grids with fixed
//!   corners, whose boundary rows follow the same curve rule).
//! - Affine invariance for every `c`, with creases, n-gons and boundaries.
//! - The mixed surface (`k` steps with `c`, then Catmull-Clark) is, on a regular region, the
//!   bicubic B-spline of the `c`-refined net (evaluated here from the uniform cubic B-spline
//!   basis); with `c = ½` it is the Catmull-Clark limit surface.

use flate2::read::GzDecoder;
use std::io::Read;
use std::path::{Path, PathBuf};

use subsurf::io::read_obj;
use subsurf::limit::{LimitSurface, SurfacePoint};
use subsurf::mesh::{BoundaryInterpolation, Crease, Options, PolyMesh, Topology};
use subsurf::scheme::Adjustable;
use subsurf::{subdivide, Mixed, MixedSurface, Scheme, SubdivideOptions};

type P = [f64; 3];

fn adj(c: f64) -> Adjustable {
    Adjustable::new(c).expect("c in [0, 1]")
}

fn shapes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/shapes/osd")
}

fn shape_names() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(shapes_dir())
        .expect("shapes directory")
        .filter_map(|e| {
            let p = e.ok()?.path();
            let stem = p.file_stem()?.to_string_lossy().into_owned();
            (p.extension()? == "obj" && stem.starts_with("catmark_")).then_some(stem)
        })
        .collect();
    names.sort();
    assert!(names.len() >= 80, "found {} shapes", names.len());
    names
}

fn diagonal(mesh: &PolyMesh) -> f64 {
    let (lo, hi) = mesh.bounding_box().expect("a non-empty mesh");
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

fn max_diff(a: &P, b: &P) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max)
}

/// One case of a golden file: level, limit?, vertex count, face count, sampled vertices.
struct Case {
    level: u32,
    limit: bool,
    verts: usize,
    faces: usize,
    samples: Vec<(usize, P)>,
}

/// Reads `tests/golden/osd/<name>.txt.gz` (format: `tests/golden/README.md`).
fn golden(name: &str) -> (BoundaryInterpolation, Vec<Case>) {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/golden/osd/{name}.txt.gz"));
    let mut text = String::new();
    GzDecoder::new(std::fs::File::open(&path).expect("golden file"))
        .read_to_string(&mut text)
        .expect("gzip text");
    let mut boundary = BoundaryInterpolation::EdgeOnly;
    let mut cases: Vec<Case> = Vec::new();
    let mut open = false;
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let t: Vec<&str> = line.split_whitespace().collect();
        match t.as_slice() {
            ["shape", _, "boundary", b] => boundary = b.parse().expect("boundary mode"),
            ["case", l, mode, "verts", n, "faces", f, ..] => {
                cases.push(Case {
                    level: l.parse().expect("level"),
                    limit: *mode == "limit",
                    verts: n.parse().expect("count"),
                    faces: f.parse().expect("count"),
                    samples: Vec::new(),
                });
                open = true;
            }
            ["case", ..] => open = false, // oracle-failed: nothing to compare
            ["end"] => open = false,
            [i, x, y, z] if open => {
                let f = |s: &str| s.parse::<f64>().expect("number");
                let case = cases.last_mut().expect("a case is open");
                case.samples
                    .push((i.parse().expect("index"), [f(x), f(y), f(z)]));
            }
            _ => panic!("{name}: unexpected golden line: {line}"),
        }
    }
    (boundary, cases)
}

fn load(name: &str) -> (PolyMesh, Options) {
    let obj = read_obj(&shapes_dir().join(format!("{name}.obj"))).expect("shape");
    let options = obj.options.resolve(Options::default());
    (obj.mesh, options)
}

#[test]
fn c_one_half_reproduces_opensubdiv_on_every_golden_shape() {
    let mut failures = Vec::new();
    let mut worst: f64 = 0.0;
    let mut compared = 0usize;
    for name in shape_names() {
        let (mesh, mut options) = load(&name);
        let (boundary, cases) = golden(&name);
        options.boundary = boundary;
        let tol = 1e-12 * diagonal(&mesh);
        for case in &cases {
            let opts = SubdivideOptions {
                levels: case.level,
                options,
                limit: case.limit,
                ..Default::default()
            };
            let out = subdivide(
                &mesh,
                &SubdivideOptions {
                    scheme: Scheme::Adjustable(Mixed::all(Adjustable::CATMULL_CLARK)),
                    ..opts.clone()
                },
            )
            .expect("refines");
            let m = &out.mesh;
            if m.num_vertices() != case.verts || m.num_faces() != case.faces {
                failures.push(format!(
                    "{name} L{} limit={}: {} vertices, {} faces; OpenSubdiv {} and {}",
                    case.level,
                    case.limit,
                    m.num_vertices(),
                    m.num_faces(),
                    case.verts,
                    case.faces
                ));
                continue;
            }
            for &(i, want) in &case.samples {
                let d = max_diff(&m.positions()[i], &want);
                worst = worst.max(d / diagonal(&mesh));
                compared += 1;
                if d > tol {
                    failures.push(format!(
                        "{name} L{} limit={} vertex {i}: off by {d:e}",
                        case.level, case.limit
                    ));
                }
            }
        }
    }
    println!("c = 1/2: {compared} sampled vertices, largest error {worst:.1e} of the diagonal");
    assert!(compared > 50_000, "only {compared} vertices compared");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn c_zero_leaves_the_control_mesh_fixed() {
    for name in [
        "catmark_pawn",
        "catmark_nonquads",
        "catmark_cube_creases1",
        "catmark_edgeonly",
    ] {
        let (mesh, options) = load(name);
        let base = Topology::from_mesh(&mesh, &options).expect("valid").0;
        let opts = SubdivideOptions {
            levels: 1,
            options,
            ..Default::default()
        };
        let out = subdivide(
            &mesh,
            &SubdivideOptions {
                scheme: Scheme::Adjustable(Mixed::all(adj(0.0))),
                ..opts.clone()
            },
        )
        .expect("refines");
        let (nv, nf) = (mesh.num_vertices(), mesh.num_faces());
        let p = out.mesh.positions();
        let old = mesh.positions();
        // Old vertices: exactly where they were.
        assert_eq!(&p[..nv], old, "{name}");
        // Face points: centroids; edge points: midpoints.
        for (f, fv) in mesh.faces().enumerate() {
            let mut c = [0.0; 3];
            for &v in fv {
                (0..3).for_each(|k| c[k] += old[v as usize][k] / fv.len() as f64);
            }
            assert!(max_diff(&p[nv + f], &c) < 1e-13, "{name} face {f}");
        }
        for e in 0..base.num_edges() {
            let [a, b] = base.edge_vertices(e);
            let mid = [0, 1, 2].map(|k| 0.5 * (old[a as usize][k] + old[b as usize][k]));
            assert_eq!(p[nv + nf + e], mid, "{name} edge {e}");
        }
        // Three levels: the old vertices still have not moved.
        let deep = SubdivideOptions { levels: 3, ..opts };
        let out = subdivide(
            &mesh,
            &SubdivideOptions {
                scheme: Scheme::Adjustable(Mixed::all(adj(0.0))),
                ..deep.clone()
            },
        )
        .expect("refines");
        assert_eq!(&out.mesh.positions()[..nv], old, "{name}");
    }
}

// ---------------------------------------------------------------------------------------
// Regular grids and the curve scheme.

/// Deterministic pseudo-random numbers in [-1, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// A grid of `ni × nj` points, `g[i][j]`.
type Grid = Vec<Vec<P>>;

/// One step of the curve scheme on a polygon (closed, or open with fixed ends).
fn curve_step(p: &[P], c: f64, closed: bool) -> Vec<P> {
    let n = p.len();
    let at = |i: isize| p[i.rem_euclid(n as isize) as usize];
    let mut out = Vec::new();
    let last = if closed { n } else { n - 1 };
    for (i, b) in p.iter().enumerate() {
        let ii = i as isize;
        let even = if !closed && (i == 0 || i == n - 1) {
            *b
        } else {
            let (a, d) = (at(ii - 1), at(ii + 1));
            [0, 1, 2].map(|k| 0.25 * c * a[k] + (1.0 - 0.5 * c) * b[k] + 0.25 * c * d[k])
        };
        out.push(even);
        if i < last {
            let d = at(ii + 1);
            out.push([0, 1, 2].map(|k| 0.5 * (b[k] + d[k])));
        }
    }
    out
}

/// The tensor-product step: rows, then columns.
fn grid_step(g: &Grid, c: f64, closed: bool) -> Grid {
    let rows: Grid = g.iter().map(|r| curve_step(r, c, closed)).collect();
    let nj = rows[0].len();
    let cols: Vec<Vec<P>> = (0..nj)
        .map(|j| {
            let col: Vec<P> = rows.iter().map(|r| r[j]).collect();
            curve_step(&col, c, closed)
        })
        .collect();
    (0..cols[0].len())
        .map(|i| (0..nj).map(|j| cols[j][i]).collect())
        .collect()
}

/// The quad mesh of a grid (closed: a torus), vertex `(i, j)` = `i·nj + j`, faces
/// `[(i,j), (i+1,j), (i+1,j+1), (i,j+1)]` (so `u` runs along `i`, `v` along `j`).
fn grid_mesh(g: &Grid, closed: bool) -> PolyMesh {
    let (ni, nj) = (g.len(), g[0].len());
    let id = |i: usize, j: usize| ((i % ni) * nj + (j % nj)) as u32;
    let (fi, fj) = if closed { (ni, nj) } else { (ni - 1, nj - 1) };
    let faces: Vec<[u32; 4]> = (0..fi)
        .flat_map(|i| {
            (0..fj).map(move |j| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
        })
        .collect();
    PolyMesh::from_faces(g.concat(), &faces).expect("a valid grid")
}

fn random_grid(ni: usize, nj: usize, rng: &mut Lcg, closed: bool) -> Grid {
    (0..ni)
        .map(|i| {
            (0..nj)
                .map(|j| {
                    if closed {
                        // A bumpy torus.
                        let (a, b) = (
                            i as f64 * std::f64::consts::TAU / ni as f64,
                            j as f64 * std::f64::consts::TAU / nj as f64,
                        );
                        let r = 1.0 + 0.1 * rng.next();
                        [
                            (3.0 + r * b.cos()) * a.cos(),
                            (3.0 + r * b.cos()) * a.sin(),
                            r * b.sin(),
                        ]
                    } else {
                        [
                            i as f64 + 0.3 * rng.next(),
                            j as f64 + 0.3 * rng.next(),
                            rng.next(),
                        ]
                    }
                })
                .collect()
        })
        .collect()
}

/// Grid coordinates (doubled) of every child vertex after one step: vertex `v` → `2·v`,
/// face → its cell's centre, edge → its midpoint (OpenSubdiv's child numbering: vertices,
/// then faces, then edges in the base topology's order).
fn child_coords(g: &Grid, mesh: &PolyMesh, closed: bool) -> Vec<(usize, usize)> {
    let (ni, nj) = (g.len(), g[0].len());
    let coord = |v: u32| (v as usize / nj, v as usize % nj);
    // Doubled coordinate of the midpoint of `a`..`b` along one axis of period `n`.
    let mid = |a: usize, b: usize, n: usize| -> usize {
        if a == b {
            2 * a
        } else if (a + 1) % n == b {
            2 * a + 1
        } else {
            2 * b + 1
        }
    };
    let (ti, tj) = if closed {
        (ni, nj)
    } else {
        (usize::MAX, usize::MAX)
    };
    let topo = Topology::from_mesh(mesh, &Options::default())
        .expect("valid")
        .0;
    let mut out: Vec<(usize, usize)> = (0..mesh.num_vertices() as u32)
        .map(|v| {
            let (i, j) = coord(v);
            (2 * i, 2 * j)
        })
        .collect();
    for fv in mesh.faces() {
        let (i0, j0) = coord(fv[0]);
        out.push((mid(i0, (i0 + 1) % ti, ti), mid(j0, (j0 + 1) % tj, tj)));
    }
    for e in 0..topo.num_edges() {
        let [a, b] = topo.edge_vertices(e);
        let ((ia, ja), (ib, jb)) = (coord(a), coord(b));
        out.push((mid(ia, ib, ti), mid(ja, jb, tj)));
    }
    out
}

fn check_tensor_product(g: &Grid, c: f64, closed: bool) -> Grid {
    let mesh = grid_mesh(g, closed);
    let options = Options {
        boundary: BoundaryInterpolation::EdgeAndCorner,
        ..Options::default()
    };
    let opts = SubdivideOptions {
        levels: 1,
        options,
        ..Default::default()
    };
    let out = subdivide(
        &mesh,
        &SubdivideOptions {
            scheme: Scheme::Adjustable(Mixed::all(adj(c))),
            ..opts.clone()
        },
    )
    .expect("refines");
    let want = grid_step(g, c, closed);
    let coords = child_coords(g, &mesh, closed);
    assert_eq!(coords.len(), out.mesh.num_vertices());
    for (v, &(i, j)) in coords.iter().enumerate() {
        let d = max_diff(&out.mesh.positions()[v], &want[i][j]);
        assert!(
            d < 1e-13,
            "c={c} closed={closed} child {v} at ({i},{j}): off by {d:e}"
        );
    }
    want
}

#[test]
fn regular_grid_step_is_the_tensor_product_of_the_curve_scheme() {
    let mut rng = Lcg(7);
    for c in [0.0, 0.2, 0.5, 0.75, 1.0] {
        // A closed grid (every vertex regular), two steps; an open grid with fixed corners.
        let g = random_grid(6, 5, &mut rng, true);
        let g1 = check_tensor_product(&g, c, true);
        check_tensor_product(&g1, c, true);
        let g = random_grid(5, 4, &mut rng, false);
        let g1 = check_tensor_product(&g, c, false);
        check_tensor_product(&g1, c, false);
    }
}

/// An infinitely sharp crease along a grid line is refined by the curve scheme along it,
/// whatever lies beside it (its ends, on the boundary, are corners and stay).
#[test]
fn creases_follow_the_curve_scheme() {
    let mut rng = Lcg(5);
    for c in [0.0, 0.3, 0.5, 1.0] {
        let g = random_grid(5, 7, &mut rng, false);
        let mut mesh = grid_mesh(&g, false);
        let nj = g[0].len();
        let row = 2; // vertices (2, j)
        for j in 0..nj - 1 {
            mesh.tags.creases.push(Crease {
                v0: (row * nj + j) as u32,
                v1: (row * nj + j + 1) as u32,
                sharpness: 10.0,
            });
        }
        let opts = SubdivideOptions {
            levels: 1,
            ..Default::default()
        };
        let out = subdivide(
            &mesh,
            &SubdivideOptions {
                scheme: Scheme::Adjustable(Mixed::all(adj(c))),
                ..opts.clone()
            },
        )
        .expect("refines");
        let want = curve_step(&g[row], c, false);
        let coords = child_coords(&g, &mesh, false);
        let mut checked = 0;
        for (v, &(i, j)) in coords.iter().enumerate() {
            if i == 2 * row {
                let d = max_diff(&out.mesh.positions()[v], &want[j]);
                assert!(d < 1e-13, "c={c} crease point {j}: off by {d:e}");
                checked += 1;
            }
        }
        assert_eq!(checked, 2 * nj - 1);
    }
}

#[test]
fn refinement_is_affine_invariant_for_every_c() {
    let a = [[0.9, -0.3, 0.2], [0.1, 1.2, -0.4], [0.3, 0.2, 0.7]];
    let t = [5.0, -2.0, 11.0];
    let map = |p: &P| [0, 1, 2].map(|r| (0..3).map(|k| a[r][k] * p[k]).sum::<f64>() + t[r]);
    for name in [
        "catmark_cube_creases1",
        "catmark_nonquads",
        "catmark_chaikin1",
        "catmark_hole_test1",
    ] {
        let (mesh, options) = load(name);
        let moved = PolyMesh::from_faces(
            mesh.positions().iter().map(map).collect(),
            &mesh.faces().map(<[u32]>::to_vec).collect::<Vec<_>>(),
        )
        .map(|mut m| {
            m.tags = mesh.tags.clone();
            m
        })
        .expect("valid");
        let tol = 1e-12 * diagonal(&moved);
        for c in [0.0, 0.3, 0.8, 1.0] {
            for steps in [1, 2] {
                let opts = SubdivideOptions {
                    levels: 3,
                    options,
                    ..Default::default()
                };
                let mixed = Mixed {
                    scheme: adj(c),
                    steps,
                };
                let x = subdivide(
                    &mesh,
                    &SubdivideOptions {
                        scheme: Scheme::Adjustable(mixed),
                        ..opts.clone()
                    },
                )
                .expect("refines");
                let y = subdivide(
                    &moved,
                    &SubdivideOptions {
                        scheme: Scheme::Adjustable(mixed),
                        ..opts.clone()
                    },
                )
                .expect("refines");
                for (p, q) in x.mesh.positions().iter().zip(y.mesh.positions()) {
                    assert!(max_diff(&map(p), q) < tol, "{name} c={c} steps={steps}");
                }
            }
        }
    }
}

#[test]
fn steps_beyond_k_are_catmull_clark() {
    // k adjustable steps then Catmull-Clark = refine k with c, then refine the output with
    // plain Catmull-Clark.
    let (mesh, options) = load("catmark_cube_creases1");
    let mixed = Mixed {
        scheme: adj(0.3),
        steps: 1,
    };
    let opts = |levels| SubdivideOptions {
        levels,
        options,
        ..Default::default()
    };
    let both = subdivide(
        &mesh,
        &SubdivideOptions {
            scheme: Scheme::Adjustable(mixed),
            ..opts(3).clone()
        },
    )
    .expect("refines");
    let first = subdivide(
        &mesh,
        &SubdivideOptions {
            scheme: Scheme::Adjustable(mixed),
            ..opts(1).clone()
        },
    )
    .expect("refines");
    let then = subdivide(&first.mesh, &opts(2)).expect("refines");
    // Re-reading the output renumbers edges (so vertices), but faces and their corners keep
    // their order: compare corner by corner.
    assert_eq!(both.mesh.num_vertices(), then.mesh.num_vertices());
    assert_eq!(both.mesh.num_faces(), then.mesh.num_faces());
    for (fa, fb) in both.mesh.faces().zip(then.mesh.faces()) {
        for (&a, &b) in fa.iter().zip(fb) {
            let (p, q) = (
                both.mesh.positions()[a as usize],
                then.mesh.positions()[b as usize],
            );
            assert!(max_diff(&p, &q) < 1e-13, "{p:?} {q:?}");
        }
    }
    // And c ≠ ½ does change the shape.
    let cc = subdivide(&mesh, &opts(3)).expect("refines");
    let moved = cc
        .mesh
        .positions()
        .iter()
        .zip(both.mesh.positions())
        .map(|(p, q)| max_diff(p, q))
        .fold(0.0, f64::max);
    assert!(moved > 1e-3, "{moved}");
}

// ---------------------------------------------------------------------------------------
// The mixed surface.

/// Uniform cubic B-spline basis and its first two derivatives at `t`.
fn bspline_basis(t: f64) -> [[f64; 4]; 3] {
    let s = 1.0 - t;
    [
        [
            s * s * s / 6.0,
            (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t * t * t / 6.0,
        ],
        [
            -s * s / 2.0,
            (3.0 * t * t - 4.0 * t) / 2.0,
            (-3.0 * t * t + 2.0 * t + 1.0) / 2.0,
            t * t / 2.0,
        ],
        [s, 3.0 * t - 2.0, -3.0 * t + 1.0, t],
    ]
}

#[test]
fn mixed_surface_on_a_regular_region_is_the_bicubic_spline_of_the_refined_net() {
    let mut rng = Lcg(11);
    let g = random_grid(8, 7, &mut rng, false);
    let mesh = grid_mesh(&g, false);
    let options = Options {
        boundary: BoundaryInterpolation::EdgeAndCorner,
        ..Options::default()
    };
    for c in [0.0, 0.3, 0.5, 0.9] {
        for k in [1u32, 2] {
            let s = MixedSurface::new(
                &mesh,
                options,
                Mixed {
                    scheme: adj(c),
                    steps: k,
                },
            )
            .expect("builds");
            let mut net = g.clone();
            for _ in 0..k {
                net = grid_step(&net, c, false);
            }
            let scale = f64::from(1u32 << k);
            // Interior input faces (i, j) with i, j in 2..=4: their refined 4×4 windows exist.
            for (fi, fj) in [(2usize, 2usize), (3, 4), (4, 3)] {
                let face = (fi * 6 + fj) as u32; // faces are numbered (i, j) → i·(nj−1) + j
                for (u, v) in [
                    (0.1, 0.2),
                    (0.5, 0.5),
                    (0.77, 0.31),
                    (0.0, 1.0),
                    (0.26, 0.9),
                ] {
                    let got = s.eval(face, u, v).expect("evaluates");
                    // The refined cell and the local parameter.
                    let (x, y) = (u * scale, v * scale);
                    let (a, b) = (
                        (x.floor() as usize).min(scale as usize - 1),
                        (y.floor() as usize).min(scale as usize - 1),
                    );
                    let (ls, lt) = (x - a as f64, y - b as f64);
                    let (ci, cj) = (fi * scale as usize + a, fj * scale as usize + b);
                    let (bu, bv) = (bspline_basis(ls), bspline_basis(lt));
                    let mut want = [[0.0; 3]; 4]; // p, du, dv, duv
                    for r in 0..4 {
                        for q in 0..4 {
                            let p = net[ci + r - 1][cj + q - 1];
                            for k3 in 0..3 {
                                want[0][k3] += bu[0][r] * bv[0][q] * p[k3];
                                want[1][k3] += bu[1][r] * bv[0][q] * p[k3] * scale;
                                want[2][k3] += bu[0][r] * bv[1][q] * p[k3] * scale;
                                want[3][k3] += bu[1][r] * bv[1][q] * p[k3] * scale * scale;
                            }
                        }
                    }
                    let tag = format!("c={c} k={k} face ({fi},{fj}) at ({u},{v})");
                    assert!(max_diff(&got.p, &want[0]) < 1e-12, "{tag}: position");
                    assert!(max_diff(&got.du, &want[1]) < 1e-10, "{tag}: du");
                    assert!(max_diff(&got.dv, &want[2]) < 1e-10, "{tag}: dv");
                    assert!(max_diff(&got.duv, &want[3]) < 1e-9, "{tag}: duv");
                }
            }
        }
    }
}

#[test]
fn mixed_surface_with_one_half_is_the_catmull_clark_limit_surface() {
    let mut rng = Lcg(3);
    for name in [
        "catmark_pawn",
        "catmark_nonquads",
        "catmark_cube_creases1",
        "catmark_hole_test1",
        "catmark_edgecorner",
        "catmark_edgenone",
        "catmark_chaikin1",
        "catmark_nonman_edges",
    ] {
        let (mesh, options) = load(name);
        let tol = 1e-12 * diagonal(&mesh);
        let cc = LimitSurface::new(&mesh, options).expect("builds");
        let mixed = MixedSurface::new(
            &mesh,
            options,
            Mixed {
                scheme: Adjustable::CATMULL_CLARK,
                steps: 2,
            },
        )
        .expect("builds");
        assert_eq!(mixed.num_faces(), mesh.num_faces());
        for face in 0..mesh.num_faces() as u32 {
            for subface in 0..cc.num_subfaces(face as usize) as u32 {
                // Corners and interior points (derivatives only away from corners, where
                // they are tangent directions whose length depends on the level).
                for (u, v) in [(0.0, 0.0), (1.0, 1.0), (0.5, 0.5)]
                    .into_iter()
                    .chain((0..3).map(|_| (0.5 + 0.45 * rng.next(), 0.5 + 0.45 * rng.next())))
                {
                    let p = SurfacePoint {
                        face,
                        subface,
                        u,
                        v,
                    };
                    match (cc.eval_point(p), mixed.eval_point(p)) {
                        (Ok(a), Ok(b)) => {
                            assert!(max_diff(&a.p, &b.p) < tol, "{name} {p:?}");
                            if u > 0.0 && u < 1.0 {
                                let dt = 1e-9 * (1.0 + a.du.iter().map(|x| x.abs()).sum::<f64>());
                                assert!(max_diff(&a.du, &b.du) < dt, "{name} {p:?} du");
                                assert!(max_diff(&a.dv, &b.dv) < dt, "{name} {p:?} dv");
                            }
                        }
                        (Err(a), Err(b)) => assert_eq!(a, b, "{name} {p:?}"),
                        (a, b) => panic!("{name} {p:?}: {a:?} vs {b:?}"),
                    }
                }
            }
        }
    }
}

#[test]
fn mixed_surface_rejects_points_off_the_mesh() {
    let (mesh, options) = load("catmark_nonquads");
    let s = MixedSurface::new(
        &mesh,
        options,
        Mixed {
            scheme: adj(0.4),
            steps: 1,
        },
    )
    .expect("builds");
    assert!(s.eval(mesh.num_faces() as u32, 0.5, 0.5).is_err());
    assert!(s.eval(0, 1.5, 0.5).is_err());
    assert!(s.eval(0, f64::NAN, 0.5).is_err());
    // A surface needs finitely many adjustable steps: "every step" is refused, not a panic.
    assert!(MixedSurface::new(&mesh, options, Mixed::all(adj(0.4))).is_err());
    let (big, n) = mesh
        .faces()
        .enumerate()
        .find(|(_, f)| f.len() != 4)
        .map(|(i, f)| (i, f.len() as u32))
        .expect("an n-gon");
    let p = |subface| SurfacePoint {
        face: big as u32,
        subface,
        u: 0.5,
        v: 0.5,
    };
    assert!(s.eval_point(p(n - 1)).is_ok());
    assert!(s.eval_point(p(n)).is_err());
}
