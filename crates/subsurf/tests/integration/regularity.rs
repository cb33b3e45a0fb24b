//! The regularity certificate ([Wang et al. 2016]) against the exact limit surface.
//!
//! - The patch neighbourhoods the certificate reads are the evaluator's patches: the
//!   tangents are the B-spline combinations of the neighbourhood's differences.
//! - Random planar and spatial nets (thousands, seeded): a certified face never has a
//!   singular or folded sample, the spatial witnesses separate the sampled tangents, and
//!   the global certificate implies the local one. The rate at which the local certificate
//!   succeeds where the global one fails is printed (`--nocapture`).
//! - The bundled examples after the paper's figures are certified; a folded net is refused
//!   with the offending face named; an edge-only corner is singular, as derived.

// Control-point grids are indexed [i][j] as in the patch formulas.
#![allow(clippy::needless_range_loop)]

use subsurf::io::parse_obj;
use subsurf::limit::bspline;
use subsurf::limit::LimitSurface;
use subsurf::mesh::{BoundaryInterpolation, Options, PolyMesh, Topology};
use subsurf::regularity::block;
use subsurf::regularity::{
    check_regularity, Certificate, Class, Dimension, Inapplicable, Mode, Refusal,
    RegularityOptions, RegularityReport, Sampled, Sign, Witness,
};

fn corners() -> Options {
    Options {
        boundary: BoundaryInterpolation::EdgeAndCorner,
        ..Options::default()
    }
}

fn opts(scheme: Options, samples: usize) -> RegularityOptions {
    RegularityOptions {
        scheme,
        dimension: None,
        samples,
    }
}

/// An `m × n` grid of quads with vertex `(i, j)` at `f(i, j)`.
fn grid(m: usize, n: usize, f: impl Fn(usize, usize) -> [f64; 3]) -> PolyMesh {
    let mut pos = Vec::new();
    for j in 0..=n {
        for i in 0..=m {
            pos.push(f(i, j));
        }
    }
    let id = |i: usize, j: usize| (j * (m + 1) + i) as u32;
    let mut faces = Vec::new();
    for j in 0..n {
        for i in 0..m {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    PolyMesh::from_faces(pos, &faces).expect("valid grid")
}

/// xorshift64*: a small seeded generator (no dependency, same numbers everywhere).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

fn example(text: &str, name: &str) -> (PolyMesh, Options) {
    let obj = parse_obj(text.as_bytes(), name).expect("example parses");
    let options = obj.options.resolve(Options::default());
    (obj.mesh, options)
}

#[test]
fn neighbourhood_differences_give_the_evaluators_tangents() {
    // A bent, jittered grid with a boundary, corners tagged: interior, boundary and corner
    // patches. S_u must be Σ N²ᵢ(u) N³ⱼ(v) ΔuP[i][j] over the block with phantom points.
    let mut rng = Rng(7);
    let mesh = grid(5, 4, |i, j| {
        let (x, y) = (i as f64, j as f64);
        [x + 0.2 * y * y / 4.0, y + 0.1 * x, 0.3 * (x * y).sin()]
    });
    let mut p = mesh.positions().to_vec();
    for q in &mut p {
        for c in q.iter_mut() {
            *c += rng.range(-0.1, 0.1);
        }
    }
    let mut mesh = mesh;
    mesh.positions_mut().copy_from_slice(&p);
    let (t, _) = Topology::from_mesh(&mesh, &corners()).expect("topology");
    let surface = LimitSurface::new(&mesh, corners()).expect("surface");
    for f in 0..t.num_faces() {
        let b = block(&t, f).expect("every face of a tagged grid is a regular patch");
        // Control points with phantoms: columns first (along u), then rows (along v).
        let mut cp = [[[0.0; 3]; 4]; 4];
        let real = |i: usize, j: usize| b.cells[i][j].map(|v| p[v as usize]);
        let ext =
            |a: [f64; 3], c: [f64; 3]| [2.0 * a[0] - c[0], 2.0 * a[1] - c[1], 2.0 * a[2] - c[2]];
        let row_phantom = |j: usize| (0..4).all(|i| b.cells[i][j].is_none());
        let col_phantom = |i: usize| (0..4).all(|j| b.cells[i][j].is_none());
        for j in 0..4 {
            if row_phantom(j) {
                continue;
            }
            for i in 0..4 {
                cp[i][j] = match real(i, j) {
                    Some(x) => x,
                    None if i == 0 && col_phantom(0) => {
                        ext(real(1, j).unwrap(), real(2, j).unwrap())
                    }
                    None if i == 3 && col_phantom(3) => {
                        ext(real(2, j).unwrap(), real(1, j).unwrap())
                    }
                    None => panic!("face {f}: cell ({i},{j}) missing"),
                };
            }
        }
        for i in 0..4 {
            if row_phantom(0) {
                cp[i][0] = ext(cp[i][1], cp[i][2]);
            }
            if row_phantom(3) {
                cp[i][3] = ext(cp[i][2], cp[i][1]);
            }
        }
        for (u, v) in [(0.0, 0.0), (0.3, 0.8), (1.0, 0.5), (0.5, 1.0), (1.0, 1.0)] {
            let want = surface.eval(f as u32, u, v).expect("eval");
            let got = bspline::eval(&cp, u, v);
            for k in 0..3 {
                assert!(
                    (want.p[k] - got.p[k]).abs() < 1e-12,
                    "face {f} position at ({u},{v})"
                );
                assert!(
                    (want.du[k] - got.du[k]).abs() < 1e-11,
                    "face {f} S_u at ({u},{v})"
                );
                assert!(
                    (want.dv[k] - got.dv[k]).abs() < 1e-11,
                    "face {f} S_v at ({u},{v})"
                );
            }
        }
    }
}

/// Checks the soundness properties on one report; returns (local, global, local-only)
/// certified face counts.
fn check_sound(mesh: &PolyMesh, r: &RegularityReport) -> (usize, usize, usize) {
    let surface = LimitSurface::new(mesh, corners()).expect("surface");
    for (f, fr) in r.faces.iter().enumerate() {
        if fr.global.is_certified() {
            assert!(
                fr.local.is_certified(),
                "face {f}: global certificate without local"
            );
        }
        if fr.local.is_certified() {
            let sampled = fr.sampled.expect("sampled");
            assert!(
                sampled.is_regular(),
                "face {f} certified but sampled singular: {sampled:?}\n{:?}",
                mesh.positions()
            );
            assert_ne!(r.class(f, Mode::Local), Class::Contradiction);
            if let Certificate::Certified(Witness::Spatial { n, m }) = fr.local {
                // The witnesses separate the actual tangents.
                let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
                for (u, v) in [(0.0, 0.0), (0.25, 0.75), (0.5, 0.5), (1.0, 0.0), (1.0, 1.0)] {
                    let d = surface.eval(f as u32, u, v).expect("eval");
                    assert!(dot(&n, &d.du) > 0.0 && dot(&n, &d.dv) < 0.0, "face {f}: n");
                    assert!(dot(&m, &d.du) > 0.0 && dot(&m, &d.dv) > 0.0, "face {f}: m");
                }
            }
        }
    }
    let local = r.faces.iter().filter(|f| f.local.is_certified()).count();
    let global = r.faces.iter().filter(|f| f.global.is_certified()).count();
    (local, global, r.local_only())
}

/// Random planar nets: grids bent along an arc by a random angle, jittered by a random
/// amount (some fold).
fn random_planar(rng: &mut Rng) -> PolyMesh {
    let m = 2 + (rng.next() * 4.0) as usize;
    let n = 2 + (rng.next() * 3.0) as usize;
    let bend = rng.range(0.0, 2.5);
    let jitter = rng.range(0.0, 0.6);
    let rot = rng.range(0.0, std::f64::consts::TAU);
    let mut noise: Vec<[f64; 2]> = Vec::new();
    for _ in 0..(m + 1) * (n + 1) {
        noise.push([rng.range(-jitter, jitter), rng.range(-jitter, jitter)]);
    }
    let r0 = m as f64 / bend.max(1e-3);
    grid(m, n, |i, j| {
        let (x, y) = if bend > 0.05 {
            let t = bend * (i as f64 / m as f64 - 0.5);
            let r = r0 + j as f64;
            (r * t.sin(), r * t.cos() - r0)
        } else {
            (i as f64, j as f64)
        };
        let e = noise[j * (m + 1) + i];
        let (x, y) = (x + e[0], y + e[1]);
        [
            x * rot.cos() - y * rot.sin(),
            x * rot.sin() + y * rot.cos(),
            0.0,
        ]
    })
}

/// Random spatial nets: height fields and fully random bumps over jittered grids.
fn random_spatial(rng: &mut Rng) -> PolyMesh {
    let m = 2 + (rng.next() * 4.0) as usize;
    let n = 2 + (rng.next() * 3.0) as usize;
    let height = rng.range(0.0, 3.0);
    let jitter = rng.range(0.0, 0.6);
    let curl = rng.range(0.0, 2.0);
    let mut noise: Vec<[f64; 3]> = Vec::new();
    for _ in 0..(m + 1) * (n + 1) {
        noise.push([
            rng.range(-jitter, jitter),
            rng.range(-jitter, jitter),
            rng.range(-height, height),
        ]);
    }
    grid(m, n, |i, j| {
        let e = noise[j * (m + 1) + i];
        let (x, y) = (i as f64, j as f64);
        // Curl the grid around the y axis by up to 2 radians.
        let t = curl * (x / m as f64 - 0.5);
        let r = m as f64 / curl.max(0.3);
        let (cx, cz) = if curl > 0.3 {
            (r * t.sin(), r * (1.0 - t.cos()))
        } else {
            (x, 0.0)
        };
        [cx + e[0], y + e[1], cz + e[2] + 1e-3]
    })
}

fn sweep(count: usize, seed: u64, spatial: bool) -> (usize, usize, usize, usize, usize) {
    let mut rng = Rng(seed);
    let (mut faces, mut local, mut global, mut local_only, mut nets_local_only) = (0, 0, 0, 0, 0);
    for _ in 0..count {
        let mesh = if spatial {
            random_spatial(&mut rng)
        } else {
            random_planar(&mut rng)
        };
        let r = check_regularity(&mesh, &opts(corners(), 5)).expect("check");
        assert_eq!(
            r.dimension,
            if spatial {
                Dimension::Spatial
            } else {
                Dimension::Planar
            }
        );
        let (l, g, lo) = check_sound(&mesh, &r);
        faces += r.faces.len();
        local += l;
        global += g;
        local_only += lo;
        if r.certified(Mode::Local) && !r.certified(Mode::Global) {
            nets_local_only += 1;
        }
    }
    (faces, local, global, local_only, nets_local_only)
}

fn report_sweep(what: &str, count: usize, s: (usize, usize, usize, usize, usize)) {
    let (faces, local, global, local_only, nets) = s;
    println!(
        "{what}: {count} nets, {faces} faces: local certifies {local} ({:.1}%), global {global} ({:.1}%); \
         local-only faces {local_only}; nets certified locally but not globally: {nets} ({:.1}%)",
        100.0 * local as f64 / faces as f64,
        100.0 * global as f64 / faces as f64,
        100.0 * nets as f64 / count as f64
    );
}

#[test]
fn random_planar_nets_are_never_certified_where_the_limit_folds() {
    let s = sweep(4000, 0x5eed_0001, false);
    report_sweep("planar", 4000, s);
    assert!(
        s.1 > s.0 / 10,
        "the certificate should certify a fair share: {s:?}"
    );
    assert!(
        s.3 > 0,
        "local certificates should succeed where global ones fail: {s:?}"
    );
}

#[test]
fn random_spatial_nets_are_never_certified_where_the_normal_vanishes() {
    let s = sweep(3000, 0x5eed_0002, true);
    report_sweep("spatial", 3000, s);
    assert!(
        s.1 > s.0 / 10,
        "the certificate should certify a fair share: {s:?}"
    );
}

#[test]
#[ignore = "large sweep (about 20 s): cargo test -p subsurf --test integration regularity:: -- --ignored --nocapture"]
fn large_random_sweep() {
    let s = sweep(40000, 0x5eed_0003, false);
    report_sweep("planar (large)", 40000, s);
    let s = sweep(20000, 0x5eed_0004, true);
    report_sweep("spatial (large)", 20000, s);
}

#[test]
fn the_papers_kind_of_examples_are_certified() {
    for (name, text) in [
        (
            "gear",
            include_str!("../../../../examples/meshes/regularity-gear.obj"),
        ),
        (
            "dolphin",
            include_str!("../../../../examples/meshes/regularity-dolphin.obj"),
        ),
        (
            "butterfly",
            include_str!("../../../../examples/meshes/regularity-butterfly.obj"),
        ),
    ] {
        let (mesh, scheme) = example(text, name);
        let r = check_regularity(&mesh, &opts(scheme, 9)).expect("check");
        assert_eq!(r.dimension, Dimension::Planar, "{name}");
        let c = r.counts(Mode::Local);
        println!(
            "{name}: {} faces, local certifies {}, global certifies {}",
            r.faces.len(),
            c.certified,
            r.counts(Mode::Global).certified
        );
        assert!(r.certified(Mode::Local), "{name}: {:?}", c);
        assert_eq!(c.not_regular, 0, "{name}");
        assert_eq!(c.contradictions, 0, "{name}");
    }
}

#[test]
fn a_straight_strip_is_certified_globally_as_theorem_3_says() {
    let mesh = grid(4, 2, |i, j| {
        [
            i as f64 + 0.1 * j as f64,
            j as f64 + 0.05 * (i * i) as f64,
            0.0,
        ]
    });
    let r = check_regularity(&mesh, &opts(corners(), 7)).expect("check");
    assert!(r.certified(Mode::Global));
    assert!(r.certified(Mode::Local));
    assert_eq!(r.orientation, Sign::Positive);
    // Mirrored, the Jacobian is negative everywhere: still certified (orientation follows).
    let mirrored = grid(4, 2, |i, j| [-(i as f64), j as f64, 0.0]);
    let r = check_regularity(&mirrored, &opts(corners(), 7)).expect("check");
    assert_eq!(r.orientation, Sign::Negative);
    assert!(r.certified(Mode::Global));
}

#[test]
fn a_folded_net_is_refused_and_the_face_named() {
    // 5×2 grid whose columns 2 and 3 swap places: the control net folds over, and the
    // limit surface too (on the middle column S_u·x = (1.5 − 6 + 1.5)/8 < 0 at u = ½).
    let xs = [0.0, 1.0, 3.5, 2.5, 4.0, 5.0];
    let mesh = grid(5, 2, |i, j| [xs[i], j as f64, 0.0]);
    let r = check_regularity(&mesh, &opts(corners(), 9)).expect("check");
    assert!(!r.certified(Mode::Local) && !r.certified(Mode::Global));
    let folded: Vec<_> = r
        .faces
        .iter()
        .filter_map(|f| match f.sampled {
            Some(Sampled::NotRegular { at }) => Some(at),
            _ => None,
        })
        .collect();
    assert!(!folded.is_empty(), "the limit surface folds");
    for at in &folded {
        assert!(
            at.value <= 0.0,
            "a fold: the Jacobian changes sign ({at:?})"
        );
        let f = at.face as usize;
        assert!(!r.faces[f].local.is_certified(), "face {f}");
        assert_eq!(r.class(f, Mode::Local), Class::NotRegular);
        assert!(
            matches!(r.faces[f].local, Certificate::Refused(Refusal::Cones(_))),
            "{:?}",
            r.faces[f]
        );
    }
    // The middle faces (column 2) are among the folded ones.
    assert!(folded.iter().any(|at| at.face == 2 || at.face == 7));
}

#[test]
fn an_edge_only_corner_makes_the_parametrisation_singular_whatever_the_cones() {
    // The derivation in the module docs: at a smooth (edge-only) corner the boundary curve
    // is smooth, so S_u and S_v turn antiparallel towards the corner ((A − B)/2 and
    // (B − A)/2): the Jacobian tends to 0 there. A perfect square grid.
    let mesh = grid(3, 3, |i, j| [i as f64, j as f64, 0.0]);
    let r = check_regularity(&mesh, &opts(Options::default(), 5)).expect("check");
    assert_eq!(
        r.faces[0].local,
        Certificate::NotApplicable(Inapplicable::SmoothCorner { vertex: 0 })
    );
    let surface = LimitSurface::new(&mesh, Options::default()).expect("surface");
    let sine = |e: f64| {
        let d = surface.eval(0, e, e).expect("eval");
        let det = d.du[0] * d.dv[1] - d.du[1] * d.dv[0];
        det / (d.du[0].hypot(d.du[1]) * d.dv[0].hypot(d.dv[1]))
    };
    let (a, b, c) = (sine(1e-2), sine(1e-4), sine(1e-6));
    assert!(a > 0.0 && b > 0.0 && c > 0.0);
    assert!(b < a / 30.0 && c < b / 30.0 && c < 1e-4, "{a} {b} {c}");
    // The middle face has a regular patch and is certified.
    assert!(r.faces[4].local.is_certified());
    // With the corners tagged every face is certified.
    let r = check_regularity(&mesh, &opts(corners(), 5)).expect("check");
    assert!(r.certified(Mode::Global));
}

#[test]
fn interior_extraordinary_vertices_are_named_as_not_applicable() {
    let text = include_str!("../../../../examples/meshes/cube.obj");
    let (mesh, scheme) = example(text, "cube");
    let r = check_regularity(&mesh, &opts(scheme, 3)).expect("check");
    assert_eq!(r.dimension, Dimension::Spatial);
    for f in &r.faces {
        assert!(
            matches!(
                f.local,
                Certificate::NotApplicable(Inapplicable::InteriorExtraordinary { valence: 3, .. })
            ),
            "{f:?}"
        );
        // The cube's limit surface is regular all the same.
        assert_eq!(
            r.class(f.face as usize, Mode::Local),
            Class::RegularNotCertified
        );
    }
    assert!(r.frames.is_err(), "valence 3 twists the (i, j) labelling");
}

#[test]
fn a_ring_is_certified_locally_but_not_globally() {
    // Annulus, 16 × 2: every direction occurs among its u-differences.
    let n = 16;
    let mut pos = Vec::new();
    for j in 0..3 {
        for i in 0..n {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            let r = 1.0 + 0.5 * j as f64;
            pos.push([r * t.cos(), r * t.sin(), 0.0]);
        }
    }
    let faces: Vec<[u32; 4]> = (0..2)
        .flat_map(|j| {
            (0..n).map(move |i| {
                let id = |i: usize, j: usize| (j * n + i % n) as u32;
                [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]
            })
        })
        .collect();
    let mesh = PolyMesh::from_faces(pos, &faces).expect("ring");
    let r = check_regularity(&mesh, &opts(Options::default(), 5)).expect("check");
    assert!(r.certified(Mode::Local));
    assert!(!r.certified(Mode::Global));
    assert_eq!(r.local_only(), faces.len());
}

#[test]
fn the_certificate_is_invariant_under_quarter_turns_and_scaling() {
    let mut rng = Rng(99);
    for _ in 0..200 {
        let mesh = random_planar(&mut rng);
        let base = check_regularity(&mesh, &opts(corners(), 0)).expect("check");
        // Exact transformations only (a quarter turn and a power of two), so that the
        // coordinates, and hence every exact sign, transform without rounding.
        let k = 2f64.powi((rng.next() * 40.0) as i32 - 20);
        let mut quarter = mesh.clone();
        for p in quarter.positions_mut() {
            *p = [-k * p[1], k * p[0], 0.0];
        }
        let q = check_regularity(&quarter, &opts(corners(), 0)).expect("check");
        for f in 0..base.faces.len() {
            assert_eq!(
                base.faces[f].local.is_certified(),
                q.faces[f].local.is_certified(),
                "face {f}"
            );
            assert_eq!(
                base.faces[f].global.is_certified(),
                q.faces[f].global.is_certified()
            );
        }
    }
}

#[test]
fn nets_at_the_edge_of_certification_are_still_regular() {
    // For a fixed noise pattern, bisect the noise amplitude to the largest value at which
    // every face is still certified locally: there some pair of cones (nearly) touches.
    // The certified net just below the threshold must still sample regular, densely.
    let mut rng = Rng(0xed9e);
    let mut probed = 0;
    for round in 0..60 {
        let spatial = round % 2 == 1;
        let (m, n) = (3, 3);
        let noise: Vec<[f64; 3]> = (0..(m + 1) * (n + 1))
            .map(|_| {
                [
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                ]
            })
            .collect();
        let net = |a: f64| {
            grid(m, n, |i, j| {
                let e = noise[j * (m + 1) + i];
                let z = if spatial {
                    0.7 * a * e[2] + 0.01 * (i * j) as f64
                } else {
                    0.0
                };
                [i as f64 + a * e[0], j as f64 + a * e[1], z]
            })
        };
        let certified = |a: f64| {
            check_regularity(&net(a), &opts(corners(), 0))
                .expect("check")
                .certified(Mode::Local)
        };
        if !certified(0.0) || certified(2.0) {
            continue;
        }
        let (mut lo, mut hi) = (0.0, 2.0);
        // 30 halvings: about 2e-9 from the threshold, above the evaluator's rounding.
        for _ in 0..30 {
            let mid = 0.5 * (lo + hi);
            if certified(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let mesh = net(lo);
        let r = check_regularity(&mesh, &opts(corners(), 33)).expect("check");
        assert!(r.certified(Mode::Local));
        // Near the threshold a sample may fall below the sampling tolerance (e.g. a corner
        // of a corner patch, where det J is exactly the cross product of the two corner
        // edges); its sign must still be the certified one.
        for f in &r.faces {
            let w = f.sampled.expect("sampled").worst();
            assert!(w.value > 0.0, "amplitude {lo}: {w:?}");
        }
        probed += 1;
    }
    assert!(probed > 20, "only {probed} thresholds probed");
}

#[test]
fn a_triangle_is_not_applicable_and_leaves_no_global_labelling() {
    // A 5×4 grid with a triangle on its bottom-left boundary edge.
    let m = 5;
    let mut pos = Vec::new();
    for j in 0..5 {
        for i in 0..=m {
            pos.push([i as f64, j as f64, 0.0]);
        }
    }
    pos.push([0.5, -0.8, 0.0]);
    let tip = (pos.len() - 1) as u32;
    let id = |i: usize, j: usize| (j * (m + 1) + i) as u32;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for j in 0..4 {
        for i in 0..m {
            faces.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    faces.push(vec![id(1, 0), id(0, 0), tip]);
    let tri = faces.len() - 1;
    let mesh = PolyMesh::from_faces(pos, &faces).expect("mesh");
    let r = check_regularity(&mesh, &opts(corners(), 5)).expect("check");
    assert_eq!(
        r.faces[tri].local,
        Certificate::NotApplicable(Inapplicable::NotQuad { size: 3 })
    );
    assert!(r.frames.is_err());
    // Far from the triangle the local certificate still holds; globally nothing does.
    let far = 3 * m + 3;
    assert!(r.faces[far].local.is_certified());
    assert!(matches!(
        r.faces[far].global,
        Certificate::Refused(Refusal::NoFrame(_))
    ));
    assert_eq!(r.counts(Mode::Global).certified, 0);
    assert_eq!(r.counts(Mode::Local).contradictions, 0);
}

#[test]
fn a_planar_face_folded_against_the_nets_orientation_is_refused() {
    // Two separate grids: a large counter-clockwise one and a small mirrored one. Each is
    // regular on its own, but the small one's Jacobian has the sign opposite to the net's
    // orientation: as a planar parametrisation the net folds, and it is not certified.
    let big = grid(4, 4, |i, j| [i as f64, j as f64, 0.0]);
    let small = grid(2, 2, |i, j| [10.0 - i as f64, j as f64, 0.0]);
    let mut pos = big.positions().to_vec();
    let offset = pos.len() as u32;
    pos.extend_from_slice(small.positions());
    let mut faces: Vec<Vec<u32>> = big.faces().map(|f| f.to_vec()).collect();
    faces.extend(
        small
            .faces()
            .map(|f| f.iter().map(|&v| v + offset).collect::<Vec<_>>()),
    );
    let mesh = PolyMesh::from_faces(pos, &faces).expect("mesh");
    let r = check_regularity(&mesh, &opts(corners(), 5)).expect("check");
    assert_eq!(r.orientation, Sign::Positive);
    for f in 0..16 {
        assert!(r.faces[f].local.is_certified() && r.faces[f].global.is_certified());
    }
    for f in 16..20 {
        assert_eq!(r.faces[f].local, Certificate::Refused(Refusal::Orientation));
        assert_eq!(
            r.faces[f].global,
            Certificate::Refused(Refusal::Orientation)
        );
        assert_eq!(r.class(f, Mode::Local), Class::NotRegular);
    }
    assert_eq!(r.frames.as_ref().map(|f| f.num_components), Ok(2));
}

#[test]
fn the_json_report_and_the_summary_read_the_report_in_one_mode() {
    // The folded net: faces refused and sampled not regular, so every field has content.
    let xs = [0.0, 1.0, 3.5, 2.5, 4.0, 5.0];
    let mesh = grid(5, 2, |i, j| [xs[i], j as f64, 0.0]);
    let r = check_regularity(&mesh, &opts(corners(), 9)).expect("check");
    for mode in [Mode::Global, Mode::Local] {
        let j: serde_json::Value =
            serde_json::from_str(&r.to_json(Some("net \"1\".obj"), mode)).expect("JSON");
        assert_eq!(j["file"], "net \"1\".obj");
        assert_eq!(j["mode"], mode.name());
        assert_eq!(j["dimension"], "planar");
        assert_eq!(j["orientation"], 1);
        assert_eq!(j["certified"], r.regular(mode));
        let c = r.counts(mode);
        assert_eq!(j["counts"]["refused"], c.refused);
        assert_eq!(j["counts"]["not_regular"], c.not_regular);
        assert_eq!(j["faces"].as_array().map(Vec::len), Some(r.faces.len()));
        for (f, face) in j["faces"].as_array().expect("faces").iter().enumerate() {
            let cert = r.certificate(f, mode);
            assert_eq!(face["face"], f);
            assert_eq!(face[mode.name()], cert.name());
            assert_eq!(
                face[format!("{}_reason", mode.name())].as_str(),
                cert.reason().as_deref()
            );
            assert_eq!(face["class"], r.class(f, mode).name());
            let worst = r.faces[f].sampled.expect("sampled").worst();
            assert_eq!(face["worst_sample"]["value"].as_f64(), Some(worst.value));
        }
        let failing = r.failing_faces(mode);
        assert!(!failing.is_empty());
        let text = r.summary("net.obj", mode);
        assert!(
            text.starts_with("net.obj: planar net, counter-clockwise, 10 faces\n"),
            "{text}"
        );
        assert_eq!(
            text.lines().filter(|l| l.starts_with("  face ")).count(),
            failing.len()
        );
        assert!(text.ends_with(&format!(
            "verdict ({} certificate): not certified\n",
            mode.name()
        )));
    }
    let spatial = grid(2, 2, |i, j| [i as f64, j as f64, (i * j) as f64]);
    let r = check_regularity(&spatial, &opts(corners(), 0)).expect("check");
    let j: serde_json::Value = serde_json::from_str(&r.to_json(None, Mode::Local)).expect("JSON");
    assert!(j["file"].is_null() && j["orientation"].is_null());
    assert_eq!(j["samples"], 0);
    assert!(j["faces"][0]["worst_sample"].is_null());
    assert_eq!(j["certified"], r.regular(Mode::Local));
}
