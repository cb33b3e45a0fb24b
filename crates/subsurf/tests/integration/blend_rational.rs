//! [Jiang et al.] with rational (NURBS) input, and the G1 fill's output mesh.
//!
//! - A NURBS patch's corner-interpolating mesh, a blend of NURBS patches and a fill bounded
//!   by NURBS curves are refined in homogeneous coordinates: their regular parts reproduce
//!   the NURBS patch and curves exactly (compared with `NurbsSurface` / `NurbsCurve`
//!   evaluation, The NURBS Book A4.1–A4.4), and the blend joins NURBS patches C2.
//! - With all weights 1, rational input gives the polynomial result bit for bit.
//! - The G1 fill's surface has no face of zero area and is otherwise its refined mesh's
//!   real part, watertight.

use std::collections::{HashMap, HashSet};

use super::blend::{diff, graph_patches, hole_curves, norm, ring_of_patches, surface};
use subsurf::blend::corner_interpolating_mesh;
use subsurf::blend::fill_g1;
use subsurf::blend::{blend, BlendError, BoundaryCurve};
use subsurf::blend::{fill, reweight_ends, FillOptions};
use subsurf::blend::{nurss_refine_once, real_part, refine_with_skirt};
use subsurf::mesh::PolyMesh;
use subsurf::nurbs::{BSplineSurface, Curve, NurbsCurve, NurbsSurface, Surface};

/// Weights in [0.55, 1.75], varying over the net.
fn weight(i: usize, j: usize, k: usize) -> f64 {
    0.55 + 0.3 * ((i * 7 + j * 3 + k * 5) % 5) as f64
}

fn rational(
    s: &BSplineSurface<3>,
    k: usize,
    w: impl Fn(usize, usize, usize) -> f64,
) -> NurbsSurface {
    let (nu, nv) = s.size();
    let weights = (0..nu * nv).map(|p| w(p / nv, p % nv, k)).collect();
    NurbsSurface::new(
        s.knots_u().clone(),
        s.knots_v().clone(),
        s.points().to_vec(),
        weights,
    )
    .unwrap()
}

#[test]
fn the_corner_interpolating_limit_of_a_nurbs_patch_is_the_patch() {
    let s = surface(
        vec![0., 0., 0., 0., 0.7, 1.6, 3., 3., 3., 3.],
        vec![0., 0., 0., 0., 1.2, 2., 2., 2., 2.],
        |i, j| {
            let (x, y) = (i as f64, j as f64);
            [x + 0.1 * y, y - 0.05 * x * x, (0.8 * x).sin() + 0.1 * x * y]
        },
    );
    let n = rational(&s, 0, weight);
    let c = corner_interpolating_mesh(&n).unwrap();
    assert!(
        !c.mesh.knots.weights.is_empty(),
        "the mesh carries the weights"
    );
    let mut grids = [c.grid.clone()];
    let out = refine_with_skirt(&c.mesh, 3, &mut grids, nurss_refine_once).unwrap();
    let g = &grids[0];
    let h = g
        .homogeneous_bspline(&out, 1..g.rows - 1, 1..g.cols - 1)
        .unwrap();
    let limit = NurbsSurface::from_homogeneous(h).unwrap();
    let ((u0, u1), (v0, v1)) = n.domain();
    let mut worst: f64 = 0.0;
    for i in 0..=20 {
        for j in 0..=20 {
            let u = u0 + (u1 - u0) * i as f64 / 20.0;
            let v = v0 + (v1 - v0) * j as f64 / 20.0;
            // (The limit's knots are sums of intervals: its domain may end 1 ulp early.)
            let (lu, lv) = (u.min(limit.domain().0 .1), v.min(limit.domain().1 .1));
            let (a, b) = (
                n.eval_second(u, v).unwrap(),
                limit.eval_second(lu, lv).unwrap(),
            );
            for (x, y) in [(a.p, b.p), (a.du, b.du), (a.dv, b.dv)] {
                worst = worst.max(diff(x, y) / norm(x).max(1.0));
            }
        }
    }
    assert!(worst < 1e-9, "max relative deviation {worst:e}");
}

#[test]
fn blended_nurbs_patches_join_c2() {
    let polys = ring_of_patches(3);
    let patches: Vec<NurbsSurface> = polys
        .iter()
        .enumerate()
        .map(|(k, s)| rational(s, k, weight))
        .collect();
    let b = blend(&patches, 3).unwrap();
    assert!(!b.control.mesh.knots.weights.is_empty());
    for (k, p) in patches.iter().enumerate() {
        let Surface::Nurbs(limit) = b.boundary_surface(k).unwrap() else {
            panic!("patch {k}: the limit of a rational blend is rational");
        };
        let t = p.knots_u().as_slice();
        let vt = p.knots_v().as_slice();
        let (v0, v1) = (vt[3], vt[vt.len() - 4]);
        for s in 0..40 {
            let v = (v0 + (v1 - v0) * s as f64 / 39.0).min(v1);
            let a = p.eval_second(t[3], v).unwrap();
            let (lu, lv) = (t[3].min(limit.domain().0 .1), v.min(limit.domain().1 .1));
            let l = limit.eval_second(lu, lv).unwrap();
            for (name, x, y) in [
                ("position", a.p, l.p),
                ("d/du", a.du, l.du),
                ("d2/du2", a.duu, l.duu),
                ("d/dv", a.dv, l.dv),
                ("d2/dv2", a.dvv, l.dvv),
            ] {
                assert!(
                    diff(x, y) <= 1e-8 * norm(x).max(1.0),
                    "patch {k}, v = {v}: {name} {x:?} vs {y:?}"
                );
            }
        }
    }
}

#[test]
fn weights_of_one_give_the_polynomial_results_exactly() {
    let ones = |s: &BSplineSurface<3>| rational(s, 0, |_, _, _| 1.0);
    let polys = ring_of_patches(4);
    let nurbs: Vec<NurbsSurface> = polys.iter().map(ones).collect();
    assert_eq!(blend(&nurbs, 2).unwrap(), blend(&polys, 2).unwrap());
    let curves = hole_curves(5);
    let nurbs_curves: Vec<NurbsCurve> = curves
        .iter()
        .map(|c| {
            NurbsCurve::new(
                c.knots().clone(),
                c.points().to_vec(),
                vec![1.0; c.points().len()],
            )
            .unwrap()
        })
        .collect();
    let opts = FillOptions::default();
    let (a, b) = (
        fill(&nurbs_curves, 2, &opts).unwrap(),
        fill(&curves, 2, &opts).unwrap(),
    );
    assert_eq!(a, b);
    assert!(a.curves.iter().all(|c| matches!(c, Curve::BSpline(_))));
    let g = graph_patches(3);
    let gn: Vec<NurbsSurface> = g.iter().map(ones).collect();
    assert_eq!(
        fill_g1(&gn, 2, &opts).unwrap(),
        fill_g1(&g, 2, &opts).unwrap()
    );
    // One weight per patch is a polynomial patch too.
    let twos: Vec<NurbsSurface> = g.iter().map(|s| rational(s, 0, |_, _, _| 2.0)).collect();
    let (x, y) = (
        fill_g1(&twos, 2, &opts).unwrap(),
        fill_g1(&g, 2, &opts).unwrap(),
    );
    for (p, q) in x.refined.positions().iter().zip(y.refined.positions()) {
        assert!(diff(*p, *q) < 1e-12);
    }
}

#[test]
fn the_same_input_gives_the_same_meshes() {
    // The extension layer's faces must not follow a hash map's order (random per call).
    let curves = hole_curves(6);
    let opts = FillOptions::default();
    for _ in 0..4 {
        assert_eq!(
            fill(&curves, 1, &opts).unwrap(),
            fill(&curves, 1, &opts).unwrap()
        );
    }
}

#[test]
fn the_g1_fill_refuses_patches_with_unequal_weights() {
    let g = graph_patches(3);
    let mut patches: Vec<NurbsSurface> = g.iter().map(|s| rational(s, 0, |_, _, _| 1.0)).collect();
    patches[2] = rational(&g[2], 2, weight);
    let e = fill_g1(&patches, 1, &FillOptions::default()).unwrap_err();
    assert!(matches!(e, BlendError::RationalG1 { index: 2 }), "{e}");
}

/// The distance from `p` to the curve `c`: dense samples, then golden-section search.
fn distance_to(c: &Curve, p: [f64; 3]) -> f64 {
    let (a, b) = c.domain();
    let d = |t: f64| diff(c.eval(t.clamp(a, b)).unwrap(), p);
    let n = 400;
    let best = (0..=n)
        .map(|i| a + (b - a) * i as f64 / n as f64)
        .min_by(|&x, &y| d(x).total_cmp(&d(y)))
        .unwrap();
    let step = (b - a) / n as f64;
    let (mut lo, mut hi) = ((best - step).max(a), (best + step).min(b));
    let r = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..200 {
        let (x1, x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if d(x1) < d(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    d(0.5 * (lo + hi))
}

#[test]
fn a_hole_bounded_by_nurbs_curves_is_filled_interpolating_them() {
    // Weights that differ at the shared corners: the curves are reparametrized (Möbius)
    // and scaled so that each corner has one weight, without changing them as point sets.
    let inputs: Vec<Curve> = hole_curves(4)
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let n = c.points().len();
            let w = (0..n).map(|j| weight(j, j + 1, k)).collect();
            Curve::Nurbs(NurbsCurve::new(c.knots().clone(), c.points().to_vec(), w).unwrap())
        })
        .collect();
    let f = fill(&inputs, 3, &FillOptions::default()).unwrap();
    assert!(!f.control.knots.weights.is_empty());
    let limit = f.boundary_curves().unwrap();
    for (k, ((c, l), input)) in f.curves.iter().zip(&limit).zip(&inputs).enumerate() {
        assert!(matches!(l, Curve::Nurbs(_)), "side {k}: rational");
        let (a, b) = c.domain();
        let lb = l.domain().1;
        assert!((b - lb).abs() < 1e-12, "side {k}: domains");
        for s in 0..=40 {
            let t = (a + (b - a) * s as f64 / 40.0).min(lb);
            let p = c.eval(t).unwrap();
            let d = diff(p, l.eval(t).unwrap());
            assert!(
                d < 4e-9,
                "side {k}, t = {t}: the limit is {d:e} off the curve"
            );
            let e = distance_to(input, p);
            assert!(e < 1e-9, "side {k}, t = {t}: {e:e} off the input curve");
        }
        let ends = [input.points()[0], input.points()[input.points().len() - 1]];
        assert!(
            ends.iter().any(|&q| diff(q, l.points()[0]) < 1e-12),
            "side {k}: corner"
        );
    }
}

#[test]
fn reweighting_the_ends_keeps_the_curve_and_scales_the_end_weight_ratio() {
    let c = &hole_curves(3)[1];
    let w = (0..c.points().len()).map(|j| weight(j, 2 * j, 1)).collect();
    let nurbs = NurbsCurve::new(c.knots().clone(), c.points().to_vec(), w).unwrap();
    let h = BoundaryCurve::homogeneous(&nurbs).into_owned();
    let ratio = |c: &subsurf::nurbs::BSplineCurve<4>| {
        let p = c.points();
        p[p.len() - 1][3] / p[0][3]
    };
    for phi in [0.3, 2.5] {
        let r = reweight_ends(&h, phi).unwrap();
        assert!((ratio(&r) / ratio(&h) - phi).abs() < 1e-12 * phi);
        assert_eq!(r.domain(), h.domain());
        let moved = NurbsCurve::from_homogeneous(r).unwrap();
        // x ↦ y = x / (ρ + (1 − ρ) x) on the normalized domain, ρ = phi^(−1/3).
        let rho = phi.powf(-1.0 / 3.0);
        let (a, b) = h.domain();
        for s in 0..=50 {
            let x = s as f64 / 50.0;
            let y = x / (rho + (1.0 - rho) * x);
            let p = moved.eval(a + (b - a) * x).unwrap();
            let q = nurbs.eval((a + (b - a) * y).min(b)).unwrap();
            assert!(diff(p, q) < 1e-12, "phi {phi}, x = {x}: {p:?} vs {q:?}");
        }
    }
}

/// Twice the area of face `f` (the length of its Newell normal).
fn twice_area(m: &PolyMesh, f: usize) -> f64 {
    let fv: Vec<u32> = m.faces().nth(f).unwrap().to_vec();
    let p = |i: usize| m.positions()[fv[i % fv.len()] as usize];
    let mut n = [0.0; 3];
    for i in 0..fv.len() {
        let (a, b) = (p(i), p(i + 1));
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    norm(n)
}

#[test]
fn the_g1_fill_surface_has_no_zero_area_face_and_is_the_real_part_elsewhere() {
    let f = fill_g1(&graph_patches(5), 3, &FillOptions::default()).unwrap();
    let real = real_part(&f.refined).unwrap();
    let merged = f.surface().unwrap();
    let (lo, hi) = real.bounding_box().unwrap();
    let diag = diff(lo, hi);
    let zero = |a: f64| a <= 1e-12 * diag * diag;
    let degenerate = (0..real.num_faces())
        .filter(|&k| zero(twice_area(&real, k)))
        .count();
    assert!(degenerate > 0, "the tripled knots make zero-area quads");
    for k in 0..merged.num_faces() {
        assert!(!zero(twice_area(&merged, k)), "face {k} has zero area");
    }
    assert_eq!(merged.num_faces(), real.num_faces() - degenerate);
    // Watertight and consistently oriented: every edge in one face (the boundary, one
    // loop) or two of opposite directions; a disk (V − E + F = 1).
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for fv in merged.faces() {
        for i in 0..fv.len() {
            *directed.entry((fv[i], fv[(i + 1) % fv.len()])).or_default() += 1;
        }
    }
    assert!(
        directed.values().all(|&c| c == 1),
        "an edge repeated in one direction"
    );
    let boundary: HashMap<u32, u32> = directed
        .keys()
        .filter(|(a, b)| !directed.contains_key(&(*b, *a)))
        .map(|&(a, b)| (a, b))
        .collect();
    let start = *boundary.keys().next().unwrap();
    let (mut v, mut steps) = (boundary[&start], 1);
    while v != start {
        v = boundary[&v];
        steps += 1;
        assert!(steps <= boundary.len(), "the boundary is not one loop");
    }
    assert_eq!(steps, boundary.len(), "the boundary is not one loop");
    let edges = directed.len() - (directed.len() - boundary.len()) / 2;
    assert_eq!(
        merged.num_vertices() as i64 - edges as i64 + merged.num_faces() as i64,
        1
    );
    // Nothing moved: every vertex is one of the real part's, and every vertex of the real
    // part is within the merge tolerance of one of the result's.
    let bits = |p: [f64; 3]| p.map(f64::to_bits);
    let kept: HashSet<[u64; 3]> = real.positions().iter().map(|&p| bits(p)).collect();
    assert!(merged.positions().iter().all(|&p| kept.contains(&bits(p))));
    for &p in real.positions() {
        let near = merged
            .positions()
            .iter()
            .map(|&q| diff(p, q))
            .fold(f64::INFINITY, f64::min);
        assert!(near <= 1e-12 * diag, "a vertex moved by {near:e}");
    }
}
