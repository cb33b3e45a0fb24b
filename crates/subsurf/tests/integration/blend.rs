//! [Jiang et al.]: skirt removal, corner interpolation, C2 patch blending and N-sided hole
//! filling. References are independent: de Boor evaluation of the input B-splines, and the
//! exact limit of the regular part of the refined mesh (`VertexGrid::bspline`, whose
//! exactness is checked against knot insertion in the library's unit tests).

use subsurf::blend::corner_interpolating_mesh;
use subsurf::blend::BlendError;
use subsurf::blend::{blend, blend_control_mesh};
use subsurf::blend::{
    catmark_refine_once, catmark_step, nurss_refine_once, nurss_step, refine_with_skirt,
};
use subsurf::blend::{fill, patch_boundary, FillOptions};
use subsurf::nurbs::{BSplineCurve, BSplineSurface, KnotVector};

pub(crate) fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

pub(crate) fn diff(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
}

pub(crate) fn surface(
    ku: Vec<f64>,
    kv: Vec<f64>,
    f: impl Fn(usize, usize) -> [f64; 3],
) -> BSplineSurface<3> {
    let ku = KnotVector::new(3, ku).unwrap();
    let kv = KnotVector::new(3, kv).unwrap();
    let (nu, nv) = (ku.num_points(), kv.num_points());
    let pts = (0..nu)
        .flat_map(|i| (0..nv).map(move |j| (i, j)))
        .map(|(i, j)| f(i, j))
        .collect();
    BSplineSurface::new(ku, kv, pts).unwrap()
}

#[test]
fn skirt_removal_with_equal_intervals_is_catmull_clark_skirt_removal() {
    let s = surface(
        vec![0., 1., 2., 3., 4., 5., 6., 7., 8., 9., 10.],
        vec![0., 1., 2., 3., 4., 5., 6., 7., 8., 9.],
        |i, j| [i as f64, j as f64, ((i * j) as f64).sqrt() * 0.3],
    );
    let mesh = plain_grid(&s);
    let a = nurss_step(&mesh).unwrap().mesh;
    let b = catmark_step(&mesh).unwrap().mesh;
    assert_eq!(a.num_faces(), b.num_faces());
    for (p, q) in a.positions().iter().zip(b.positions()) {
        assert!(diff(*p, *q) < 1e-12);
    }
    // Two steps through the generic driver agree as well.
    let a2 = refine_with_skirt(&mesh, 2, &mut [], nurss_refine_once).unwrap();
    let b2 = refine_with_skirt(&mesh, 2, &mut [], catmark_refine_once).unwrap();
    for (p, q) in a2.positions().iter().zip(b2.positions()) {
        assert!(diff(*p, *q) < 1e-12);
    }
}

/// The net of `s` as a plain quad grid (no knot intervals: all 1).
fn plain_grid(s: &BSplineSurface<3>) -> subsurf::mesh::PolyMesh {
    let (nu, nv) = s.size();
    let pts = s.points().to_vec();
    let (m, _) =
        subsurf::blend::grid_mesh(nu, nv, pts, &vec![1.0; nu - 1], &vec![1.0; nv - 1]).unwrap();
    m
}

#[test]
fn the_corner_interpolating_limit_of_a_clamped_patch_is_the_patch() {
    let s = surface(
        vec![0., 0., 0., 0., 0.7, 1.6, 3., 3., 3., 3.],
        vec![0., 0., 0., 0., 1.2, 2., 2., 2., 2.],
        |i, j| {
            let (x, y) = (i as f64, j as f64);
            [
                x + 0.1 * y,
                y - 0.05 * x * x,
                (0.8 * x).sin() * (0.6 * y).cos() + 0.1 * x * y,
            ]
        },
    );
    let c = corner_interpolating_mesh(&s).unwrap();
    let mut grids = [c.grid.clone()];
    let out = refine_with_skirt(&c.mesh, 3, &mut grids, nurss_refine_once).unwrap();
    let g = &grids[0];
    // The real part (without the extension layer) is the refined net of the patch.
    let limit = g.bspline(&out, 1..g.rows - 1, 1..g.cols - 1).unwrap();
    let ((u0, u1), (v0, v1)) = s.domain();
    assert!((limit.domain().0 .0 - u0).abs() < 1e-12 && (limit.domain().1 .1 - v1).abs() < 1e-12);
    let size = 10.0;
    let mut worst: f64 = 0.0;
    for i in 0..=20 {
        for j in 0..=20 {
            let u = u0 + (u1 - u0) * i as f64 / 20.0;
            let v = v0 + (v1 - v0) * j as f64 / 20.0;
            // (The limit's knots are sums of intervals: its domain may end 1 ulp early.)
            let (lu, lv) = (u.min(limit.domain().0 .1), v.min(limit.domain().1 .1));
            worst = worst.max(diff(s.eval(u, v).unwrap(), limit.eval(lu, lv).unwrap()));
        }
    }
    assert!(worst < 1e-9 * size, "max deviation {worst:e}");
    // The refined real corners are the patch corners.
    let (nu, nv) = s.size();
    let corner = |r: usize, cc: usize| out.positions()[g.at(r, cc) as usize];
    assert!(diff(corner(1, 1), s.points()[0]) < 1e-12);
    assert!(diff(corner(g.rows - 2, g.cols - 2), s.points()[nu * nv - 1]) < 1e-12);
}

/// `n` patches around the origin, each over an angular sector, first row at the inner
/// radius; sizes, knots and heights differ per patch.
pub(crate) fn ring_of_patches(n: usize) -> Vec<BSplineSurface<3>> {
    (0..n)
        .map(|k| {
            let rows = 4 + k % 3;
            let cols = 5 + (k % 2) * 2;
            let cumulative = |n: usize, f: &dyn Fn(usize) -> f64| {
                let mut t = vec![0.0];
                for i in 0..n - 1 {
                    t.push(t[i] + f(i));
                }
                t
            };
            let ku = cumulative(rows + 4, &|i| 1.0 + 0.4 * ((i * (k + 2)) % 3) as f64);
            let kv = cumulative(cols + 4, &|j| 0.5 + 0.3 * ((j * (k + 1)) % 4) as f64);
            let sector = std::f64::consts::TAU / n as f64;
            surface(ku, kv, move |i, j| {
                let a = sector * (k as f64 + 0.15 + 0.7 * j as f64 / (cols - 1) as f64);
                let r = 2.0 + 0.6 * i as f64;
                [
                    r * a.cos(),
                    r * a.sin(),
                    0.3 * (2.0 * a).sin() + 0.05 * r * r,
                ]
            })
        })
        .collect()
}

fn check_c2_blend(n: usize, levels: u32) {
    let patches = ring_of_patches(n);
    let b = blend(&patches, levels).unwrap();
    for (k, p) in patches.iter().enumerate() {
        let limit = b.boundary_spline(k).unwrap();
        let t = p.knots_u().as_slice();
        // The blend ends on the patch's first-row boundary u = u_3.
        assert!((limit.domain().0 .1 - t[3]).abs() < 1e-12);
        let vt = p.knots_v().as_slice();
        let (v0, v1) = (vt[3], vt[vt.len() - 4]);
        for s in 0..50 {
            let v = (v0 + (v1 - v0) * s as f64 / 49.0).min(v1);
            let a = p.eval_second(t[3], v).unwrap();
            // (The limit's knots are sums of intervals: its domain may end 1 ulp early.)
            let (lu, lv) = (t[3].min(limit.domain().0 .1), v.min(limit.domain().1 .1));
            let l = limit.eval_second(lu, lv).unwrap();
            for (name, x, y) in [
                ("position", a.p, l.p),
                ("d/du", a.du, l.du),
                ("d2/du2", a.duu, l.duu),
                ("d/dv", a.dv, l.dv),
                ("d2/dudv", a.duv, l.duv),
                ("d2/dv2", a.dvv, l.dvv),
            ] {
                let scale = norm(x).max(1.0);
                assert!(
                    diff(x, y) <= 1e-8 * scale,
                    "{n} patches, patch {k}, v = {v}: {name} {x:?} vs {y:?}"
                );
            }
        }
    }
}

#[test]
fn three_blended_patches_join_their_base_patches_c2() {
    check_c2_blend(3, 3);
}

#[test]
fn five_blended_patches_join_their_base_patches_c2() {
    check_c2_blend(5, 2);
}

#[test]
fn two_patches_blend_too() {
    check_c2_blend(2, 2);
}

#[test]
fn the_blend_mesh_shares_three_rows_with_each_patch() {
    let patches = ring_of_patches(3);
    let b = blend_control_mesh(&patches).unwrap();
    for (k, p) in patches.iter().enumerate() {
        let g = &b.strips[k];
        let (_, nv) = p.size();
        for r in 0..4 {
            for j in 0..nv {
                let v = g.at(r + 1, j + 1) as usize;
                assert_eq!(b.mesh.positions()[v], p.points()[r * nv + j]);
            }
        }
    }
}

#[test]
fn blend_rejects_unfit_patches_naming_them() {
    let mut patches = ring_of_patches(3);
    let quad = KnotVector::new(2, vec![0., 0., 0., 1., 2., 2., 2.]).unwrap();
    let pts = vec![[0.0; 3]; 16];
    patches[1] = BSplineSurface::new(quad.clone(), quad, pts).unwrap();
    let e = blend_control_mesh(&patches).unwrap_err();
    assert!(matches!(e, BlendError::Degree { index: 1, .. }), "{e}");
    assert!(e.to_string().contains("patch 1"));
    assert!(matches!(
        blend_control_mesh(&ring_of_patches(1)).unwrap_err(),
        BlendError::Count { found: 1, .. }
    ));
}

/// `n` clamped boundary curves with 5 or 6 control points and non-uniform knots around a
/// wavy loop; curve `k` runs from corner `k` to corner `k + 1`.
pub(crate) fn hole_curves(n: usize) -> Vec<BSplineCurve<3>> {
    let corner = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        [2.0 * a.cos(), 2.0 * a.sin(), 0.4 * (3.0 * a).cos()]
    };
    (0..n)
        .map(|k| {
            let (a, b) = (corner(k), corner((k + 1) % n));
            let m = 5 + k % 2;
            let pts: Vec<[f64; 3]> = (0..m)
                .map(|j| {
                    let t = j as f64 / (m - 1) as f64;
                    let bump = (std::f64::consts::PI * t).sin();
                    let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
                    let out = [mid[0] * 0.3 * bump, mid[1] * 0.3 * bump];
                    [
                        a[0] + (b[0] - a[0]) * t + out[0],
                        a[1] + (b[1] - a[1]) * t + out[1],
                        a[2] + (b[2] - a[2]) * t + 0.2 * bump,
                    ]
                })
                .collect();
            let mut knots = vec![0.0; 4];
            for i in 0..m - 4 {
                knots.push(1.0 + i as f64 * 0.7 + 0.2 * k as f64);
            }
            let end = 1.0 + (m - 4) as f64 * 0.9 + 0.3 * k as f64;
            knots.extend([end; 4]);
            BSplineCurve::new(KnotVector::new(3, knots).unwrap(), pts).unwrap()
        })
        .collect()
}

fn check_fill_interpolates(n: usize, levels: u32, reverse_one: bool) {
    let mut curves = hole_curves(n);
    if reverse_one {
        curves[1] = subsurf::blend::reversed(&curves[1]).unwrap();
    }
    let f = fill(&curves, levels, &FillOptions::default()).unwrap();
    let limit = f.boundary_curves().unwrap();
    assert_eq!(limit.len(), n);
    // The prepared curves are the input curves, affinely reparametrized (maybe reversed).
    for (k, (c, input)) in f.curves.iter().zip(&curves).enumerate() {
        let ((a, b), (ia, ib)) = (c.domain(), input.domain());
        let err = |rev: bool| {
            (0..=40)
                .map(|s| {
                    let x = s as f64 / 40.0;
                    let y = if rev { 1.0 - x } else { x };
                    let p = c.eval((a + (b - a) * x).min(b)).unwrap();
                    diff(p, input.eval((ia + (ib - ia) * y).min(ib)).unwrap())
                })
                .fold(0.0, f64::max)
        };
        assert!(err(false).min(err(true)) < 1e-12, "curve {k} was changed");
    }
    for (k, (c, l)) in f.curves.iter().zip(&limit).enumerate() {
        let (a, b) = c.domain();
        let (la, lb) = l.domain();
        assert!(
            (a - la).abs() < 1e-12 && (b - lb).abs() < 1e-12,
            "side {k}: domains"
        );
        let b = b.min(lb);
        for s in 0..=60 {
            let t = a + (b - a) * s as f64 / 60.0;
            // (The limit's knots are sums of intervals: its domain may end 1 ulp early.)
            let d = diff(c.eval(t).unwrap(), l.eval(t.min(lb)).unwrap());
            assert!(d < 1e-9 * 4.0, "{n}-sided, side {k}, t = {t}: {d:e}");
        }
        // Corners: the curve's ends are real mesh vertices of the limit boundary.
        assert!(diff(l.points()[0], c.points()[0]) < 1e-12);
    }
}

#[test]
fn a_filled_three_sided_hole_interpolates_its_boundary_curves_and_corners() {
    check_fill_interpolates(3, 3, false);
}

#[test]
fn a_filled_five_sided_hole_interpolates_its_boundary_curves_and_corners() {
    check_fill_interpolates(5, 3, true);
}

#[test]
fn holes_with_four_to_eight_sides_fill() {
    for n in [4, 6, 7, 8] {
        check_fill_interpolates(n, 2, false);
    }
}

#[test]
fn bulge_moves_the_fill_along_the_boundary_normal() {
    let curves = hole_curves(5);
    let mean_z = |bulge: f64| {
        let f = fill(
            &curves,
            2,
            &FillOptions {
                bulge,
                ..Default::default()
            },
        )
        .unwrap();
        let s = f.surface().unwrap();
        s.positions().iter().map(|p| p[2]).sum::<f64>() / s.num_vertices() as f64
    };
    // The loop runs counter-clockwise seen from +z: its normal is +z.
    let (flat, up, down) = (mean_z(0.0), mean_z(0.5), mean_z(-0.5));
    assert!(up > flat + 0.05 && down < flat - 0.05, "{down} {flat} {up}");
}

#[test]
fn fill_errors_name_the_curve() {
    let mut curves = hole_curves(4);
    let mut pts = curves[2].points().to_vec();
    pts[0][2] += 0.5;
    curves[2] = BSplineCurve::new(curves[2].knots().clone(), pts).unwrap();
    let e = fill(&curves, 1, &FillOptions::default()).unwrap_err();
    assert!(
        matches!(
            e,
            BlendError::Corner {
                index: 1,
                next: 2,
                ..
            }
        ),
        "{e}"
    );
    let e = fill(&hole_curves(3)[..2], 1, &FillOptions::default()).unwrap_err();
    assert!(matches!(e, BlendError::Count { found: 2, .. }), "{e}");
}

#[test]
fn a_patch_contributes_its_first_row_boundary_curve() {
    // Unclamped, non-uniform knots: the boundary is S(u_3, v), clamped by knot insertion.
    let s = surface(
        vec![0., 0.5, 1.5, 2., 3.2, 4., 5.5, 6.],
        vec![0., 1., 1.2, 2., 3.5, 4., 4.1, 5., 6.],
        |i, j| [i as f64, j as f64, ((i + 2 * j) as f64).sin()],
    );
    let c = patch_boundary(&s, 0).unwrap();
    let ((u0, _), (v0, v1)) = s.domain();
    assert_eq!(c.domain(), (v0, v1));
    for k in 0..=30 {
        let v = v0 + (v1 - v0) * k as f64 / 30.0;
        assert!(diff(c.eval(v).unwrap(), s.eval(u0, v).unwrap()) < 1e-12);
    }
}

/// Cubic B-spline control points of the quadratic `c0 + c1 t + c2 t²` on `knots` (blossoms:
/// `P_i = c0 + c1 (t_{i+1} + t_{i+2} + t_{i+3}) / 3 + c2 (t_{i+1} t_{i+2} + t_{i+1} t_{i+3} +
/// t_{i+2} t_{i+3}) / 3`), as the three blossom factors `[1, s1, s2]` per point.
fn blossoms(knots: &[f64]) -> Vec<[f64; 3]> {
    (0..knots.len() - 4)
        .map(|i| {
            let (a, b, c) = (knots[i + 1], knots[i + 2], knots[i + 3]);
            [1.0, (a + b + c) / 3.0, (a * b + a * c + b * c) / 3.0]
        })
        .collect()
}

/// `n` bicubic patches around a hole, all exact pieces of the graph `z = q(x, y)` (quadratic):
/// patch `k` maps `(u, v)` affinely to `C_k + v (C_{k+1} − C_k) / v_max + u o_k` (`o_k`
/// outward), so neighbours share corners and tangent planes there.
pub(crate) fn graph_patches(n: usize) -> Vec<BSplineSurface<3>> {
    let q = |x: f64, y: f64| 0.3 * x * x - 0.2 * x * y + 0.15 * y * y + 0.1 * x;
    let corner = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / n as f64 + 0.3;
        [1.5 * a.cos(), 1.5 * a.sin()]
    };
    (0..n)
        .map(|k| {
            let (c0, c1) = (corner(k), corner((k + 1) % n));
            let mid = [(c0[0] + c1[0]) / 2.0, (c0[1] + c1[1]) / 2.0];
            let l = (mid[0] * mid[0] + mid[1] * mid[1]).sqrt();
            let o = [mid[0] / l, mid[1] / l];
            let ku = vec![0., 0., 0., 0., 0.4, 1., 1., 1., 1.];
            let mut kv = vec![0., 0., 0., 0.];
            let vm = 2.0 + 0.3 * k as f64;
            kv.extend([0.7, 1.1 + 0.1 * k as f64]);
            kv.extend([vm; 4]);
            // x(u, v) = c0 + v (c1 − c0) / vm + u o: affine; z = q(x, y) is a quadratic
            // polynomial in (u, v): z = Σ a_{ij} u^i v^j (i + j ≤ 2).
            let d = [(c1[0] - c0[0]) / vm, (c1[1] - c0[1]) / vm];
            let xy = |u: f64, v: f64| [c0[0] + v * d[0] + u * o[0], c0[1] + v * d[1] + u * o[1]];
            // Coefficients by finite differences of the exact quadratic.
            let z = |u: f64, v: f64| {
                let p = xy(u, v);
                q(p[0], p[1])
            };
            let a00 = z(0., 0.);
            let a20 = (z(1., 0.) + z(-1., 0.) - 2.0 * a00) / 2.0;
            let a02 = (z(0., 1.) + z(0., -1.) - 2.0 * a00) / 2.0;
            let a10 = (z(1., 0.) - z(-1., 0.)) / 2.0;
            let a01 = (z(0., 1.) - z(0., -1.)) / 2.0;
            let a11 = z(1., 1.) - a00 - a10 - a01 - a20 - a02;
            let (bu, bv) = (blossoms(&ku), blossoms(&kv));
            let (nu, nv) = (bu.len(), bv.len());
            let mut pts = Vec::with_capacity(nu * nv);
            for &s in &bu {
                for &t in &bv {
                    // Blossoms of x, y (affine) and z (quadratic, tensor blossom).
                    let x = c0[0] + t[1] * d[0] + s[1] * o[0];
                    let y = c0[1] + t[1] * d[1] + s[1] * o[1];
                    let zz =
                        a00 + a10 * s[1] + a01 * t[1] + a20 * s[2] + a02 * t[2] + a11 * s[1] * t[1];
                    pts.push([x, y, zz]);
                }
            }
            let s = BSplineSurface::new(
                KnotVector::new(3, ku).unwrap(),
                KnotVector::new(3, kv).unwrap(),
                pts,
            )
            .unwrap();
            // The construction is exact: the patch is the graph.
            let p = s.eval(0.3, 0.9).unwrap();
            assert!((p[2] - q(p[0], p[1])).abs() < 1e-12);
            s
        })
        .collect()
}

fn check_g1(n: usize, levels: u32) {
    use subsurf::blend::fill_g1;
    let patches = graph_patches(n);
    let f = fill_g1(&patches, levels, &FillOptions::default()).unwrap();
    let rows = f.boundary_rows().unwrap();
    let mut worst_angle: f64 = 0.0;
    for (k, (c, r)) in f.curves.iter().zip(&rows).enumerate() {
        let (a, b) = c.domain();
        let lb = r.boundary.domain().1;
        assert!(
            (b - lb).abs() < 1e-12,
            "side {k}: {:?} vs {:?}; {} vs {} points",
            c.knots().as_slice(),
            r.boundary.knots().as_slice(),
            c.points().len(),
            r.boundary.points().len()
        );
        let p = &patches[k];
        let u0 = p.domain().0 .0;
        for s in 0..=60 {
            let t = (a + (b - a) * s as f64 / 60.0).min(lb);
            let d = diff(c.eval(t).unwrap(), r.boundary.eval(t).unwrap());
            assert!(d < 1e-9 * 4.0, "{n}-sided G1, side {k}, t = {t}: {d:e}");
            if s == 0 || s == 60 {
                continue; // the corners: the normal of a C0 corner is not defined
            }
            let base = p.eval_second(u0, t.min(p.domain().1 .1)).unwrap();
            let nb = cross3(base.du, base.dv);
            let tan = r.boundary.eval_derivs(t, 1).unwrap()[1];
            let nf = cross3(tan, r.cross.eval(t).unwrap());
            let cos = (dot3(nb, nf) / (norm(nb) * norm(nf))).clamp(-1.0, 1.0);
            worst_angle = worst_angle.max(cos.abs().acos());
        }
    }
    eprintln!("{n}-sided G1: worst normal angle {worst_angle:e} rad");
    assert!(
        worst_angle <= 1e-6,
        "{n}-sided G1: normal angle {worst_angle:e} rad"
    );
}

pub(crate) fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[test]
fn a_g1_filled_three_sided_hole_has_the_base_normals_along_the_boundary() {
    check_g1(3, 3);
}

#[test]
fn a_g1_filled_five_sided_hole_has_the_base_normals_along_the_boundary() {
    check_g1(5, 3);
}

#[test]
fn jobs_run_the_methods_on_a_files_items_and_name_the_item_at_fault() {
    use subsurf::blend::{BlendJob, BlendJobOptions, FillJob, FillJobOptions, JobError};
    use subsurf::nurbs::{Curve, Geometry, SourcedGeometry, Surface};
    let item = |k: usize, geometry: Geometry| SourcedGeometry {
        geometry,
        name: (k == 1).then(|| "rim".to_owned()),
        origin: format!("in.json[{k}]"),
    };
    let curves = hole_curves(4);
    let items: Vec<_> = curves
        .iter()
        .enumerate()
        .map(|(k, c)| item(k, Geometry::Curve(Curve::BSpline(c.clone()))))
        .collect();
    let opts = FillJobOptions {
        levels: 2,
        samples: 3,
        ..FillJobOptions::default()
    };
    let job = FillJob::new(&items, "in.json", &opts).unwrap();
    assert_eq!(job.sides(), 4);
    let out = job.run().unwrap();
    // The job's surface is the method's.
    let direct = fill(&curves, 2, &FillOptions::default()).unwrap();
    assert_eq!(out.surface, direct.surface().unwrap());
    assert_eq!(&out.control, job.control());
    let names: Vec<String> = out.groups().into_iter().map(|(n, _)| n).collect();
    assert_eq!(names, ["fill"]);
    let lines: Vec<String> = out.polylines().into_iter().map(|(n, _)| n).collect();
    assert_eq!(lines, ["curve_1", "curve_2", "curve_3", "curve_4"]);
    assert_eq!(
        out.comment,
        "subsurf fill: 4-sided hole, 2 skirt-removal levels, bulge 0"
    );
    // More levels, more memory.
    let deeper = FillJob::new(&items, "in.json", &FillJobOptions { levels: 4, ..opts }).unwrap();
    assert!(deeper.estimate_memory() > job.estimate_memory());
    // Errors name the item (its label) or the input.
    let e = BlendJob::new(&items, "in.json", &BlendJobOptions::default()).unwrap_err();
    assert_eq!(e.to_string(), "in.json[0]: a curve; blending takes patches");
    let g1 = FillJobOptions { g1: true, ..opts };
    let e = FillJob::new(&items, "in.json", &g1).unwrap_err();
    assert!(matches!(e, JobError::CurveToG1 { .. }), "{e}");
    let e = FillJob::new(&items[..2], "in.json", &opts).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("in.json: sides of the hole: got 2"),
        "{e}"
    );
    let mut moved = items.clone();
    if let Geometry::Curve(Curve::BSpline(c)) = &mut moved[1].geometry {
        let mut pts = c.points().to_vec();
        let last = pts.len() - 1;
        pts[last][2] += 0.5;
        *c = BSplineCurve::new(c.knots().clone(), pts).unwrap();
    }
    let e = FillJob::new(&moved, "in.json", &opts).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("in.json[1] (\"rim\"): curve 1 does not share"),
        "{e}"
    );
    let e = FillJob::new(&items, "in.json", &FillJobOptions { levels: 9, ..opts }).unwrap_err();
    assert!(matches!(e, JobError::Option(_)), "{e}");
    let e = FillJob::new(&items, "in.json", &FillJobOptions { samples: 0, ..opts }).unwrap_err();
    assert!(matches!(e, JobError::Option(_)), "{e}");
    // A blend of patches: the base patches tessellated, then the blend surface.
    let patches = ring_of_patches(3);
    let items: Vec<_> = patches
        .iter()
        .enumerate()
        .map(|(k, s)| item(k, Geometry::Surface(Surface::BSpline(s.clone()))))
        .collect();
    let opts = BlendJobOptions {
        levels: 2,
        samples: 2,
    };
    let out = BlendJob::new(&items, "in.json", &opts)
        .unwrap()
        .run()
        .unwrap();
    assert_eq!(out.surface, blend(&patches, 2).unwrap().surface().unwrap());
    let names: Vec<String> = out.groups().into_iter().map(|(n, _)| n).collect();
    assert_eq!(names, ["patch_1", "patch_2", "patch_3", "blend"]);
    assert!(out.curves.is_empty());
    assert_eq!(
        out.control_comment(),
        "subsurf blend: control mesh (outer ring: extension layer)"
    );
}
