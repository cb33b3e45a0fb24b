//! Curve interpolation by symmetric zonal meshes ([JOS 2003]): the middle polygon of every
//! zone refines exactly as knot insertion refines the curve, and the NURSS limit surface passes
//! through the curve.
//!
//! References are independent of the zone code: control points after knot insertion are
//! blossoms of the curve (a cubic control point with knots `(a, b, c)` is the blossom
//! `B(a, b, c)` of any polynomial piece it influences; de Boor's algorithm with a different
//! parameter at each level computes it), cross-checked against `insert_midpoints` (Boehm);
//! points on the curve come from de Boor evaluation.

use subsurf::curves::{
    interpolate_curves, refine_polyline, CubicCurve, InterpolateError, InterpolateOptions,
    Interpolation,
};
use subsurf::nonuniform::Nurss;
use subsurf::nurbs::{BSplineCurve, Curve, KnotVector, NurbsCurve};

use crate::common::curves;
use curves::{check_middle, dist, eval, knots, middle_knots, size, V3};

/// Checks, at levels 0..=levels, every middle-polygon point that influences the curve's
/// domain against the blossom; returns the number of points checked and the largest error
/// relative to the curve's size. Then checks limit points at the last level against de Boor.
fn check_zone(curve: &Curve, out: &Interpolation, zone: usize, levels: u32) -> (usize, f64, f64) {
    let z = &out.zones[zone];
    let kv = knots(curve);
    let (a, b) = kv.domain();
    let period = b - a;
    let sz = size(curve);
    let mut s = Nurss::new(&out.mesh, &Default::default()).unwrap();
    let mut ids = z.middle.clone();
    let (mut checked, mut worst) = (0, 0.0f64);
    for level in 0..=levels {
        if level > 0 {
            ids = refine_polyline(s.topology(), &ids, z.closed).unwrap();
            s.step();
        }
        let (c, w) = check_middle(curve, &s, &ids, z);
        checked += c;
        worst = worst.max(w);
    }
    // Limit points of the middle polygon at the last level lie on the curve.
    let limit = s.limit_points();
    let zk = middle_knots(&s, &ids, z);
    let mut worst_limit = 0.0f64;
    for (j, &v) in ids.iter().enumerate() {
        let t = zk[j];
        let inside = if z.closed { true } else { t >= a && t <= b };
        if inside {
            let t = if z.closed {
                a + (t - a).rem_euclid(period)
            } else {
                t
            };
            worst_limit = worst_limit.max(dist(&limit[v as usize], &eval(curve, t)) / sz);
        }
    }
    (checked, worst, worst_limit)
}

fn zone_of(curve: &Curve, opts: &InterpolateOptions) -> Interpolation {
    let c = CubicCurve::new(curve, "test curve").unwrap();
    interpolate_curves(&[c], opts).unwrap()
}

fn assert_interpolates(curve: &Curve, levels: u32) {
    let out = zone_of(curve, &InterpolateOptions::default());
    let (checked, worst, worst_limit) = check_zone(curve, &out, 0, levels);
    assert!(checked > 20, "only {checked} points checked");
    assert!(
        worst <= 1e-12,
        "middle polygon off the refined control polygon by {worst:e}"
    );
    assert!(
        worst_limit <= 1e-9,
        "limit off the curve by {worst_limit:e}"
    );
}

/// A cubic B-spline curve with these knots and control points.
pub(crate) fn bspline(knots: Vec<f64>, pts: Vec<V3>) -> Curve {
    Curve::BSpline(BSplineCurve::new(KnotVector::new(3, knots).unwrap(), pts).unwrap())
}

fn wavy(n: usize) -> Vec<V3> {
    (0..n)
        .map(|i| {
            let t = i as f64;
            [t, (0.9 * t).sin() * 1.5, 0.3 * (0.5 * t).cos()]
        })
        .collect()
}

#[test]
fn clamped_uniform_curve_is_interpolated_at_every_level() {
    let c = Curve::BSpline(BSplineCurve::clamped_uniform(3, wavy(7)).unwrap());
    assert_interpolates(&c, 4);
}

#[test]
fn middle_polygon_equals_insert_midpoints_on_the_domain() {
    // Boehm knot insertion (the library's insert_midpoints) as a second reference: inside the
    // domain the middle polygon after k steps contains the refined control polygon's points.
    let pts = wavy(7);
    let spline = BSplineCurve::new(
        KnotVector::new(
            3,
            vec![0.0, 0.5, 1.0, 2.0, 3.5, 4.0, 5.5, 6.0, 7.5, 8.0, 9.0],
        )
        .unwrap(),
        pts,
    )
    .unwrap();
    let out = zone_of(
        &Curve::BSpline(spline.clone()),
        &InterpolateOptions::default(),
    );
    let z = &out.zones[0];
    let mut s = Nurss::new(&out.mesh, &Default::default()).unwrap();
    let mut ids = z.middle.clone();
    let mut reference = spline.clone();
    for level in 1..=4u32 {
        ids = refine_polyline(s.topology(), &ids, false).unwrap();
        s.step();
        reference.insert_midpoints().unwrap();
        let pos = s.positions();
        let r = reference.points();
        // R[2] has knots (t_3, ., .): in the zone it is point 2^level · (first + 1) + 1.
        let offset = (1usize << level) * (z.first + 1) + 1;
        let mut worst = 0.0f64;
        for i in 2..r.len() - 2 {
            worst = worst.max(dist(&pos[ids[offset + i - 2] as usize], &r[i]));
        }
        assert!(worst <= 1e-12, "level {level}: off by {worst:e}");
    }
}

#[test]
fn unclamped_non_uniform_curve_uses_phantom_end_points() {
    // d_1 ≠ d_2 at both ends: phantoms are needed, and the curve is still exact.
    let c = bspline(
        vec![0.0, 0.5, 1.0, 2.0, 3.5, 4.0, 5.5, 6.0, 7.5, 8.0, 9.0],
        wavy(7),
    );
    let out = zone_of(&c, &InterpolateOptions::default());
    assert_eq!(out.zones[0].first, 1);
    assert_eq!(out.zones[0].middle.len(), 9);
    assert_interpolates(&c, 4);
}

#[test]
fn double_knot_c1_point_is_interpolated() {
    let c = bspline(
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 3.0, 4.0, 4.0, 4.0, 4.0],
        wavy(8),
    );
    assert_interpolates(&c, 4);
}

#[test]
fn triple_knot_c0_corner_is_interpolated() {
    let c = bspline(
        vec![
            0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0, 3.0, 4.0, 4.0, 4.0, 4.0,
        ],
        wavy(9),
    );
    assert_interpolates(&c, 4);
}

#[test]
fn closed_non_uniform_curve_is_interpolated() {
    let pts: Vec<V3> = (0..7)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 7.0;
            [2.0 * a.cos(), 1.3 * a.sin(), 0.4 * (3.0 * a).sin()]
        })
        .collect();
    let k = KnotVector::periodic(3, &[0.0, 1.0, 1.5, 3.0, 4.0, 4.2, 5.0, 6.5]).unwrap();
    let c = Curve::BSpline(BSplineCurve::new(k, pts).unwrap());
    assert_interpolates(&c, 4);
}

/// A full circle of radius `r` as a clamped rational cubic: four quarter arcs (quadratic
/// `w = 1, √½, 1`) raised to degree 3 in homogeneous coordinates, joined with triple knots.
fn cubic_circle(r: f64) -> Curve {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let quad = [
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 1.0],
        [-1.0, 1.0],
        [-1.0, 0.0],
        [-1.0, -1.0],
        [0.0, -1.0],
        [1.0, -1.0],
    ];
    let mut hom: Vec<[f64; 4]> = Vec::new();
    for q in 0..4 {
        let p = |i: usize, w: f64| {
            let v = quad[(2 * q + i) % 8];
            [w * r * v[0], w * r * v[1], 0.0, w]
        };
        let (a, b, c) = (p(0, 1.0), p(1, s), p(2, 1.0));
        let mix = |x: &[f64; 4], y: &[f64; 4], t: f64| -> [f64; 4] {
            [0, 1, 2, 3].map(|k| (1.0 - t) * x[k] + t * y[k])
        };
        if q == 0 {
            hom.push(a);
        }
        hom.push(mix(&a, &b, 2.0 / 3.0));
        hom.push(mix(&b, &c, 1.0 / 3.0));
        hom.push(c);
    }
    let pts = hom
        .iter()
        .map(|h| [h[0] / h[3], h[1] / h[3], h[2] / h[3]])
        .collect();
    let w = hom.iter().map(|h| h[3]).collect();
    let knots = vec![
        0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0, 4.0, 4.0, 4.0, 4.0,
    ];
    Curve::Nurbs(NurbsCurve::new(KnotVector::new(3, knots).unwrap(), pts, w).unwrap())
}

#[test]
fn a_circle_stays_a_circle() {
    let c = cubic_circle(2.0);
    // The reference really is a circle.
    for i in 0..=40 {
        let p = eval(&c, 4.0 * i as f64 / 40.0);
        assert!(((p[0] * p[0] + p[1] * p[1]).sqrt() - 2.0).abs() < 1e-14);
    }
    assert_interpolates(&c, 4);
    // Limit points along the middle polygon at level 3 are on the circle.
    let out = zone_of(&c, &InterpolateOptions::default());
    let z = &out.zones[0];
    let mut s = Nurss::new(&out.mesh, &Default::default()).unwrap();
    let mut ids = z.middle.clone();
    for _ in 0..3 {
        ids = refine_polyline(s.topology(), &ids, false).unwrap();
        s.step();
    }
    let lp = s.limit_points();
    for &v in &ids {
        let p = lp[v as usize];
        assert!(
            ((p[0] * p[0] + p[1] * p[1]).sqrt() - 2.0).abs() < 1e-12,
            "{p:?}"
        );
        assert!(p[2].abs() < 1e-12);
    }
}

#[test]
fn zone_is_symmetric_with_side_points_weighted_like_their_middle_point() {
    let c = cubic_circle(1.0);
    let out = zone_of(
        &c,
        &InterpolateOptions {
            width: 0.2,
            side: None,
        },
    );
    let m = &out.mesh;
    let weight = |v: u32| {
        m.knots
            .weights
            .iter()
            .find(|w| w.vertex == v)
            .map_or(1.0, |w| w.weight)
    };
    // Each middle point has two column neighbours, symmetric about it, with its weight.
    let p = m.positions();
    for &v in &out.zones[0].middle {
        let mut col = Vec::new();
        for f in m.faces() {
            for i in 0..4 {
                if f[i] == v {
                    for n in [f[(i + 1) % 4], f[(i + 3) % 4]] {
                        if !out.zones[0].middle.contains(&n) && !col.contains(&n) {
                            col.push(n);
                        }
                    }
                }
            }
        }
        assert_eq!(col.len(), 2);
        let (t, b) = (p[col[0] as usize], p[col[1] as usize]);
        let q = p[v as usize];
        assert!(
            dist(
                &[t[0] + b[0], t[1] + b[1], t[2] + b[2]],
                &[2.0 * q[0], 2.0 * q[1], 2.0 * q[2]]
            ) < 1e-15
        );
        // A planar curve's zone stands perpendicular to its plane, width 0.2 × size.
        assert!((dist(&t, &q) - 0.2 * size(&c)).abs() < 1e-12);
        assert!((t[2] - q[2]).abs() > 0.99 * dist(&t, &q));
        assert_eq!(weight(col[0]), weight(v));
        assert_eq!(weight(col[1]), weight(v));
    }
}

#[test]
fn side_vector_and_width_place_the_side_points() {
    let c = Curve::BSpline(BSplineCurve::clamped_uniform(3, wavy(6)).unwrap());
    let out = zone_of(
        &c,
        &InterpolateOptions {
            width: 0.05,
            side: Some([0.0, 0.0, 3.0]),
        },
    );
    assert_interpolates(&c, 3);
    let z = &out.zones[0];
    let p = out.mesh.positions();
    let w = 0.05 * size(&c);
    // Every non-middle vertex is at distance w from some middle point, offset mostly along z.
    for (v, q) in p.iter().enumerate() {
        if z.middle.contains(&(v as u32)) {
            continue;
        }
        let best = z
            .middle
            .iter()
            .map(|&m| (dist(q, &p[m as usize]), q[2] - p[m as usize][2]))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap();
        assert!((best.0 - w).abs() < 1e-12);
        assert!(best.1.abs() > 0.5 * w);
    }
}

// ---------------------------------------------------------------------------------------
// Crossings

/// Two curves crossing at X = (0, 0, 0): `a` along x (symmetric neighbours ±(1,0,0)), `b`
/// along y (±(0, 1.2, 0)), each with equal intervals around X.
pub(crate) fn crossing_pair() -> (Curve, Curve) {
    let a = bspline(
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0, 4.0, 4.0],
        vec![
            [-3.0, 0.5, 0.8],
            [-2.0, -0.4, 0.2],
            [-1.0, 0.0, 0.1],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, -0.1],
            [2.0, 0.6, 0.3],
            [3.2, 0.0, 0.9],
        ],
    );
    let b = bspline(
        vec![0.0, 0.0, 0.0, 0.0, 0.8, 1.6, 2.4, 3.2, 3.2, 3.2, 3.2],
        vec![
            [0.3, -3.5, 0.5],
            [-0.5, -2.4, 0.0],
            [0.0, -1.2, 0.1],
            [0.0, 0.0, 0.0],
            [0.0, 1.2, -0.1],
            [0.4, 2.4, 0.2],
            [0.0, 3.6, 0.7],
        ],
    );
    (a, b)
}

fn build_pair(a: &Curve, b: &Curve) -> Result<Interpolation, InterpolateError> {
    interpolate_curves(
        &[
            CubicCurve::new(a, "a").unwrap(),
            CubicCurve::new(b, "b").unwrap(),
        ],
        &InterpolateOptions::default(),
    )
}

#[test]
fn two_crossing_curves_share_a_joint_polygon_group_and_both_are_interpolated() {
    let (a, b) = crossing_pair();
    let out = build_pair(&a, &b).unwrap();
    // The four quads around X appear once: 2 zones × 12 quads − 4 shared.
    assert_eq!(out.mesh.num_faces(), 2 * 12 - 4);
    let x = out.zones[0].middle[3];
    assert_eq!(out.zones[1].middle[3], x);
    for (i, c) in [a, b].iter().enumerate() {
        let (checked, worst, worst_limit) = check_zone(c, &out, i, 4);
        assert!(checked > 20);
        assert!(worst <= 1e-12, "curve {i}: {worst:e}");
        assert!(worst_limit <= 1e-9, "curve {i}: {worst_limit:e}");
    }
}

/// Curvature vector of the polyline through three points spaced by `h` in parameter.
fn second_difference(p0: &V3, p1: &V3, p2: &V3, h: f64) -> V3 {
    [0, 1, 2].map(|k| (p0[k] - 2.0 * p1[k] + p2[k]) / (h * h))
}

#[test]
fn opposite_branches_join_g2_and_the_group_centre_is_fixed() {
    let (a, b) = crossing_pair();
    let out = build_pair(&a, &b).unwrap();
    let mut s = Nurss::new(&out.mesh, &Default::default()).unwrap();
    let x = out.zones[0].middle[3];
    let mut ids: Vec<Vec<u32>> = out.zones.iter().map(|z| z.middle.clone()).collect();
    let levels = 5;
    for _ in 0..levels {
        for (z, id) in out.zones.iter().zip(ids.iter_mut()) {
            *id = refine_polyline(s.topology(), id, z.closed).unwrap();
        }
        s.step();
        // Corollary 1: the centre stays put.
        assert!(dist(&s.positions()[x as usize], &[0.0; 3]) < 1e-15);
    }
    let lp = s.limit_points();
    for (i, (z, c)) in out.zones.iter().zip([&a, &b]).enumerate() {
        let j = ids[i].iter().position(|&v| v == x).unwrap();
        let h = middle_knots(&s, &ids[i], z)[j + 1] - middle_knots(&s, &ids[i], z)[j];
        // Limit points on both sides of X, 1..3 samples away: curvature from the left and
        // from the right branch agree with each other and with the curve (de Boor).
        let at = |k: isize| lp[ids[i][(j as isize + k) as usize] as usize];
        let left = second_difference(&at(-2), &at(-1), &at(0), h);
        let right = second_difference(&at(0), &at(1), &at(2), h);
        let tx = middle_knots(&s, &ids[i], z)[j];
        let exact = eval(c, tx);
        assert!(dist(&at(0), &exact) < 1e-12);
        // O(h) one-sided differences: compare the two sides with each other at O(h).
        let scale = dist(&left, &[0.0; 3]).max(dist(&right, &[0.0; 3])).max(1.0);
        assert!(
            dist(&left, &right) / scale < 0.2,
            "curve {i}: {left:?} vs {right:?}"
        );
        // Tangents agree (G1) to O(h²).
        let tl = [0, 1, 2].map(|k| (at(0)[k] - at(-1)[k]) / h);
        let tr = [0, 1, 2].map(|k| (at(1)[k] - at(0)[k]) / h);
        assert!(dist(&tl, &tr) / dist(&tl, &[0.0; 3]) < 0.1);
    }
    // Adjacent branches (a's +x arm and b's +y arm) meet at an angle: G0 only.
    let ja = ids[0].iter().position(|&v| v == x).unwrap();
    let jb = ids[1].iter().position(|&v| v == x).unwrap();
    let ta = [0, 1, 2].map(|k| lp[ids[0][ja + 1] as usize][k] - lp[x as usize][k]);
    let tb = [0, 1, 2].map(|k| lp[ids[1][jb + 1] as usize][k] - lp[x as usize][k]);
    let cos = (ta[0] * tb[0] + ta[1] * tb[1] + ta[2] * tb[2])
        / (dist(&ta, &[0.0; 3]) * dist(&tb, &[0.0; 3]));
    assert!(cos.abs() < 0.2, "branches meet at an angle, cos = {cos}");
}

#[test]
fn crossing_with_non_uniform_intervals_away_from_the_joint_is_interpolated() {
    // Intervals 1, 1, 1, 1 on the four edges around X (the group needs them equal), others
    // differ: 0.4 before, 2.5 after.
    let (_, b) = crossing_pair();
    let a = bspline(
        vec![
            0.0, 0.0, 0.0, 0.0, 0.4, 1.4, 2.4, 3.4, 4.4, 6.9, 6.9, 6.9, 6.9,
        ],
        vec![
            [-4.0, 0.2, 0.3],
            [-3.0, 0.5, 0.8],
            [-2.0, -0.4, 0.2],
            [-1.0, 0.0, 0.1],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, -0.1],
            [2.0, 0.6, 0.3],
            [3.2, 0.0, 0.9],
            [4.0, 0.3, 1.0],
        ],
    );
    let out = build_pair(&a, &b).unwrap();
    for (i, c) in [a, b].iter().enumerate() {
        let (checked, worst, worst_limit) = check_zone(c, &out, i, 4);
        assert!(checked > 20);
        assert!(worst <= 1e-12, "curve {i}: {worst:e}");
        assert!(worst_limit <= 1e-9, "curve {i}: {worst_limit:e}");
    }
}

// ---------------------------------------------------------------------------------------
// Errors

#[test]
fn degree_other_than_three_is_refused_naming_the_curve() {
    let c = Curve::BSpline(BSplineCurve::clamped_uniform(2, wavy(5)).unwrap());
    let err = CubicCurve::new(&c, "rim").unwrap_err();
    assert!(matches!(err, InterpolateError::Degree { degree: 2, .. }));
    assert!(err.to_string().contains("rim"), "{err}");
}

/// Three curves crossing at one point make six branches there, more than a joint polygon
/// group takes (at most four: the paper's Corollary 1).
#[test]
fn six_branches_at_one_point_are_refused() {
    let (a, b) = crossing_pair();
    let c = bspline(
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0, 2.0],
        vec![
            [-1.0, -1.0, 0.5],
            [-0.5, -0.5, 0.2],
            [0.0, 0.0, 0.0],
            [0.5, 0.5, -0.2],
            [1.0, 1.0, -0.5],
        ],
    );
    let curves = [
        CubicCurve::new(&a, "a").unwrap(),
        CubicCurve::new(&b, "b").unwrap(),
        CubicCurve::new(&c, "diagonal").unwrap(),
    ];
    let err = interpolate_curves(&curves, &InterpolateOptions::default()).unwrap_err();
    assert!(
        matches!(err, InterpolateError::TooManyCurves { branches: 6, .. }),
        "{err}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains("diagonal point 2") && msg.contains("(0, 0, 0)"),
        "{msg}"
    );
}

#[test]
fn crossing_without_a_shared_control_point_is_refused() {
    let (a, _) = crossing_pair();
    let b = bspline(
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0, 2.0],
        vec![
            [0.5, -2.0, -0.05],
            [0.5, -1.0, -0.05],
            [0.5, 0.3, -0.05],
            [0.5, 1.0, -0.05],
            [0.5, 2.0, -0.05],
        ],
    );
    let err = build_pair(&a, &b).unwrap_err();
    assert!(
        matches!(err, InterpolateError::UnsharedCrossing { edge_a: 3, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("without a shared control point"));
}

#[test]
fn asymmetric_crossing_is_refused_naming_curve_and_point() {
    let (a, _) = crossing_pair();
    let b = bspline(
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0, 3.0],
        vec![
            [0.0, -3.0, 0.0],
            [0.0, -2.0, 0.0],
            [0.0, 0.0, 0.0],
            [0.3, 1.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 3.0, 0.0],
        ],
    );
    let err = build_pair(&a, &b).unwrap_err();
    assert!(
        matches!(err, InterpolateError::Crossing { index: 2, .. }),
        "{err}"
    );
    assert!(err.to_string().starts_with("b, control point 2"), "{err}");
}

#[test]
fn curve_with_a_clamped_end_at_a_crossing_is_refused() {
    // A clamped end has zero intervals at its end point: no joint polygon group fits.
    let (a, _) = crossing_pair();
    let b = bspline(
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
        vec![
            [0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 3.0, 0.0],
        ],
    );
    let err = build_pair(&a, &b).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("b, control point 0 at (0, 0, 0)"),
        "{err}"
    );
    assert!(
        err.to_string().contains("equal non-zero knot intervals"),
        "{err}"
    );
}

/// An open uniform (unclamped) curve starting at the origin and leaving it along `d`.
fn ending_at_origin(d: V3, bend: f64) -> Curve {
    bspline(
        (0..9).map(|i| i as f64).collect(),
        (0..5)
            .map(|i| {
                let t = i as f64;
                [t * d[0], t * d[1], bend * t * t]
            })
            .collect(),
    )
}

#[test]
fn two_curves_ending_at_one_point_are_both_interpolated_and_meet_g0_at_the_fixed_centre() {
    // Both start at X = (0, 0, 0) (an L-shaped corner): each gets a phantom point opposite its
    // first edge, and the two extended polygons cross at X (a joint polygon group).
    let a = ending_at_origin([1.0, 0.0, 0.0], 0.1);
    let b = ending_at_origin([0.0, 1.2, 0.0], -0.05);
    let out = build_pair(&a, &b).unwrap();
    assert_eq!((out.zones[0].first, out.zones[1].first), (1, 1));
    let x = out.zones[0].middle[1];
    assert_eq!(
        out.zones[1].middle[1], x,
        "both polygons pass through one vertex"
    );
    for (i, c) in [&a, &b].iter().enumerate() {
        let (checked, worst, worst_limit) = check_zone(c, &out, i, 4);
        assert!(checked > 10);
        assert!(worst <= 1e-12, "curve {i}: {worst:e}");
        assert!(worst_limit <= 1e-9, "curve {i}: {worst_limit:e}");
    }
    let mut s = Nurss::new(&out.mesh, &Default::default()).unwrap();
    let mut ids: Vec<Vec<u32>> = out.zones.iter().map(|z| z.middle.clone()).collect();
    for _ in 0..4 {
        for id in ids.iter_mut() {
            *id = refine_polyline(s.topology(), id, false).unwrap();
        }
        s.step();
        assert!(
            dist(&s.positions()[x as usize], &[0.0; 3]) < 1e-15,
            "centre fixed"
        );
    }
    let lp = s.limit_points();
    assert!(dist(&lp[x as usize], &[0.0; 3]) < 1e-14);
    let j = |i: usize| ids[i].iter().position(|&v| v == x).unwrap();
    let ta = lp[ids[0][j(0) + 1] as usize];
    let tb = lp[ids[1][j(1) + 1] as usize];
    let cos = (ta[0] * tb[0] + ta[1] * tb[1] + ta[2] * tb[2])
        / (dist(&ta, &[0.0; 3]) * dist(&tb, &[0.0; 3]));
    assert!(
        cos.abs() < 0.2,
        "the branches meet at an angle (G0), cos = {cos}"
    );
}

#[test]
fn two_curves_ending_at_one_point_in_one_line_are_joined_and_both_interpolated() {
    // `b`'s first edge continues `a`'s straight through X (`b`'s point 1 is `a`'s phantom):
    // one zone runs through X, and each curve is exact on its domain.
    let a = ending_at_origin([1.0, 0.0, 0.0], 0.1);
    let b = ending_at_origin([-1.0, 0.0, 0.0], -0.1);
    let out = build_pair(&a, &b).unwrap();
    for (i, c) in [&a, &b].iter().enumerate() {
        let (checked, worst, worst_limit) = check_zone(c, &out, i, 4);
        assert!(checked > 10);
        assert!(worst <= 1e-12, "curve {i}: {worst:e}");
        assert!(worst_limit <= 1e-9, "curve {i}: {worst_limit:e}");
    }
}

#[test]
fn three_curves_ending_at_one_point_are_refused_naming_each() {
    let curves = [
        CubicCurve::new(&ending_at_origin([1.0, 0.0, 0.0], 0.1), "east").unwrap(),
        CubicCurve::new(&ending_at_origin([0.0, 1.0, 0.0], 0.1), "north").unwrap(),
        CubicCurve::new(&ending_at_origin([-0.7, -0.7, 0.0], 0.1), "south-west").unwrap(),
    ];
    let err = interpolate_curves(&curves, &InterpolateOptions::default()).unwrap_err();
    assert!(
        matches!(err, InterpolateError::SharedPoint { count: 3, .. }),
        "{err}"
    );
    let msg = err.to_string();
    for name in ["east ends at its point 0", "north ends", "south-west ends"] {
        assert!(msg.contains(name), "{msg}");
    }
    assert!(msg.contains("(0, 0, 0)"), "{msg}");
}

#[test]
fn t_junction_curve_ending_on_a_crossing_curve_is_interpolated_and_meets_it_g0() {
    // `c` ends at X = (0, 0, 0), a control point of `a`, with an unclamped uniform end
    // (d_1 = d_2): three branches at X. Its zone reaches X along the curve's extension.
    let (a, _) = crossing_pair();
    let c = bspline(
        (0..9).map(|i| i as f64).collect(),
        vec![
            [0.0, 0.0, 0.0],
            [0.0, 1.0, 0.1],
            [0.2, 2.0, 0.3],
            [0.0, 3.0, 0.2],
            [-0.3, 4.0, 0.0],
        ],
    );
    let out = build_pair(&a, &c).unwrap();
    assert_eq!(out.zones[1].first, 1, "phantom at the end on the group");
    for (i, cv) in [&a, &c].iter().enumerate() {
        let (checked, worst, worst_limit) = check_zone(cv, &out, i, 4);
        assert!(checked > 10);
        assert!(worst <= 1e-12, "curve {i}: {worst:e}");
        assert!(worst_limit <= 1e-9, "curve {i}: {worst_limit:e}");
    }
    // The group's centre is on the limit surface, and the branches meet at an angle.
    let mut s = Nurss::new(&out.mesh, &Default::default()).unwrap();
    let x = out.zones[0].middle[3];
    let mut ids: Vec<Vec<u32>> = out.zones.iter().map(|z| z.middle.clone()).collect();
    for _ in 0..4 {
        for id in ids.iter_mut() {
            *id = refine_polyline(s.topology(), id, false).unwrap();
        }
        s.step();
    }
    let lp = s.limit_points();
    assert!(dist(&lp[x as usize], &[0.0; 3]) < 1e-14);
    let ja = ids[0].iter().position(|&v| v == x).unwrap();
    let jc = ids[1].iter().position(|&v| v == x).unwrap();
    let ta = [0, 1, 2].map(|k| lp[ids[0][ja + 1] as usize][k]);
    let tc = [0, 1, 2].map(|k| lp[ids[1][jc + 1] as usize][k]);
    let cos = (ta[0] * tc[0] + ta[1] * tc[1] + ta[2] * tc[2])
        / (dist(&ta, &[0.0; 3]) * dist(&tc, &[0.0; 3]));
    assert!(cos.abs() < 0.2, "cos = {cos}");
}

#[test]
fn crossing_with_unequal_intervals_beyond_the_joint_is_refused() {
    // Intervals 0.6, 1, 1, 0.6 around X: symmetric, but the second-edge condition fails (the
    // other curve would be missed by 2e-3 of its size).
    let (_, b) = crossing_pair();
    let a = bspline(
        vec![0.0, 0.0, 0.0, 0.0, 0.6, 1.6, 2.6, 3.2, 5.1, 5.1, 5.1, 5.1],
        vec![
            [-3.0, 0.5, 0.8],
            [-2.0, -0.4, 0.2],
            [-1.0, 0.0, 0.1],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, -0.1],
            [2.0, 0.6, 0.3],
            [3.2, 0.0, 0.9],
            [4.0, 0.3, 1.0],
        ],
    );
    let err = build_pair(&a, &b).unwrap_err();
    assert!(
        matches!(err, InterpolateError::Crossing { index: 3, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("second-edge condition"), "{err}");
}

#[test]
fn bad_options_are_refused() {
    let c = CubicCurve::new(
        &Curve::BSpline(BSplineCurve::clamped_uniform(3, wavy(5)).unwrap()),
        "c",
    )
    .unwrap();
    for width in [0.0, -1.0, f64::NAN] {
        let err = interpolate_curves(
            std::slice::from_ref(&c),
            &InterpolateOptions { width, side: None },
        );
        assert!(matches!(err, Err(InterpolateError::BadOption(_))));
    }
    let err = interpolate_curves(
        std::slice::from_ref(&c),
        &InterpolateOptions {
            width: 0.1,
            side: Some([0.0; 3]),
        },
    );
    assert!(matches!(err, Err(InterpolateError::BadOption(_))));
    assert!(matches!(
        interpolate_curves(&[], &InterpolateOptions::default()),
        Err(InterpolateError::NoCurves)
    ));
}

#[test]
fn rational_curve_crossing_a_polynomial_one_is_interpolated() {
    // Weights 1 at the crossing and its neighbours (the group is symmetric in homogeneous
    // coordinates only then), other weights free.
    let (a, b) = crossing_pair();
    let Curve::BSpline(sa) = &a else {
        unreachable!()
    };
    let w = vec![1.0, 2.5, 1.0, 1.0, 1.0, 0.4, 1.7];
    let ra = Curve::Nurbs(NurbsCurve::new(sa.knots().clone(), sa.points().to_vec(), w).unwrap());
    let out = build_pair(&ra, &b).unwrap();
    for (i, c) in [ra, b].iter().enumerate() {
        let (checked, worst, worst_limit) = check_zone(c, &out, i, 4);
        assert!(checked > 20);
        assert!(worst <= 1e-12, "curve {i}: {worst:e}");
        assert!(worst_limit <= 1e-9, "curve {i}: {worst_limit:e}");
    }
    // A different weight next to the crossing is refused.
    let Curve::Nurbs(na) = &out_curve_with_weight(sa, 2, 1.3) else {
        unreachable!()
    };
    let err = build_pair(&Curve::Nurbs(na.clone()), &crossing_pair().1).unwrap_err();
    assert!(err.to_string().contains("weights"), "{err}");
}

fn out_curve_with_weight(s: &BSplineCurve<3>, i: usize, w: f64) -> Curve {
    let mut ws = vec![1.0; s.points().len()];
    ws[i] = w;
    Curve::Nurbs(NurbsCurve::new(s.knots().clone(), s.points().to_vec(), ws).unwrap())
}

#[test]
fn frame_of_a_closed_space_curve_is_perpendicular_and_closes_smoothly() {
    use subsurf::curves::{side_directions, tangents};
    // A trefoil knot: its rotation-minimising frame does not close by itself (holonomy).
    let n = 90;
    let pts: Vec<V3> = (0..n)
        .map(|i| {
            let t = i as f64 * std::f64::consts::TAU / n as f64;
            [
                t.sin() + 2.0 * (2.0 * t).sin(),
                t.cos() - 2.0 * (2.0 * t).cos(),
                -(3.0 * t).sin(),
            ]
        })
        .collect();
    let tan = tangents(&pts, true).unwrap();
    let u = side_directions(&pts, &tan, true, None).unwrap();
    let dot = |a: &V3, b: &V3| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut worst = 0.0f64;
    for i in 0..n {
        assert!(dot(&u[i], &tan[i]).abs() < 1e-12);
        assert!((dot(&u[i], &u[i]) - 1.0).abs() < 1e-12);
        let j = (i + 1) % n;
        worst = worst.max(dot(&u[i], &u[j]).clamp(-1.0, 1.0).acos());
    }
    // Consecutive frames (the closing pair included) turn by a small angle only.
    assert!(worst < 0.25, "largest turn between neighbours: {worst} rad");
    // A side vector parallel to the tangent somewhere is reported with the point.
    let line = Curve::BSpline(
        BSplineCurve::clamped_uniform(3, (0..5).map(|i| [i as f64, 0.0, 0.0]).collect()).unwrap(),
    );
    let c = CubicCurve::new(&line, "axis").unwrap();
    let err = interpolate_curves(
        &[c],
        &InterpolateOptions {
            width: 0.1,
            side: Some([1.0, 0.0, 0.0]),
        },
    )
    .unwrap_err();
    assert!(
        err.to_string().contains(
            "axis: the side vector is parallel to the curve's tangent at control point 0"
        ),
        "{err}"
    );
}

#[test]
fn bundled_examples_interpolate_every_curve() {
    for (name, text) in [
        (
            "vase",
            include_str!("../../../../examples/curves/vase.json"),
        ),
        (
            "dolphin",
            include_str!("../../../../examples/curves/dolphin.json"),
        ),
    ] {
        let curves: Vec<Curve> = subsurf::nurbs::from_json_str_all(text)
            .unwrap()
            .into_iter()
            .map(|g| match g {
                subsurf::nurbs::Geometry::Curve(c) => c,
                _ => panic!("{name}: a surface"),
            })
            .collect();
        let cubic: Vec<CubicCurve> = curves
            .iter()
            .enumerate()
            .map(|(i, c)| CubicCurve::new(c, &format!("{name}[{i}]")).unwrap())
            .collect();
        let out = interpolate_curves(&cubic, &InterpolateOptions::default()).unwrap();
        for (i, c) in curves.iter().enumerate() {
            let (checked, worst, worst_limit) = check_zone(c, &out, i, 3);
            assert!(checked > 10, "{name}[{i}]");
            assert!(worst <= 1e-12, "{name}[{i}]: {worst:e}");
            assert!(worst_limit <= 1e-9, "{name}[{i}]: {worst_limit:e}");
        }
    }
}
