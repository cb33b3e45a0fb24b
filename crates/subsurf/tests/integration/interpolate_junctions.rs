//! Curve interpolation ([JOS 2003]) where curves meet or close: closed curves given in the
//! unwrapped form CAD tools export, clamped curves whose ends coincide, curves ending at one
//! point, three and four curves through one point (Corollary 1, Fig. 13 b, c), and the
//! shape of the zones there (no folds at level 4).
//!
//! Exactness is checked as in `interpolate.rs`: refined middle polygons against blossoms,
//! limit points against de Boor evaluation. A fold is a pair of faces sharing an edge whose
//! normals point apart (negative dot product), counted on the limit mesh at level 4.

use std::collections::HashMap;

use subsurf::curves::{
    interpolate_curves, refine_polyline, CubicCurve, InterpolateError, InterpolateOptions,
    Interpolation,
};
use subsurf::io::parse_obj_freeform;
use subsurf::io::{geometry_to_string, parse_geometry, GeometryFormat};
use subsurf::mesh::PolyMesh;
use subsurf::nonuniform::Nurss;
use subsurf::nurbs::{BSplineCurve, Curve, Geometry, KnotVector, NurbsCurve};

use crate::common::curves;
use crate::interpolate::{bspline, crossing_pair};
use curves::{blossom, check_middle, dist, eval, knots, middle_knots, size, V3};

/// Refined middle polygons (levels 0..=levels) against the blossoms and limit points against
/// de Boor, for every curve; returns the worst errors relative to each curve's size.
fn worst_errors(curves: &[Curve], out: &Interpolation, levels: u32) -> (usize, f64, f64) {
    let mut s = Nurss::new(&out.mesh, &Default::default()).unwrap();
    let mut ids: Vec<Vec<u32>> = out.zones.iter().map(|z| z.middle.clone()).collect();
    let (mut checked, mut worst) = (0, 0.0f64);
    for level in 0..=levels {
        if level > 0 {
            for (z, id) in out.zones.iter().zip(ids.iter_mut()) {
                *id = refine_polyline(s.topology(), id, z.closed).unwrap();
            }
            s.step();
        }
        for ((c, z), id) in curves.iter().zip(&out.zones).zip(&ids) {
            let (n, w) = check_middle(c, &s, id, z);
            checked += n;
            worst = worst.max(w);
        }
    }
    let limit = s.limit_points();
    let mut worst_limit = 0.0f64;
    for ((c, z), id) in curves.iter().zip(&out.zones).zip(&ids) {
        let (a, b) = knots(c).domain();
        let zk = middle_knots(&s, id, z);
        for (j, &t) in zk.iter().enumerate().take(id.len()) {
            let t = if z.closed {
                a + (t - a).rem_euclid(b - a)
            } else if t >= a && t <= b {
                t
            } else {
                continue;
            };
            let e = dist(&limit[id[j] as usize], &eval(c, t)) / size(c);
            worst_limit = worst_limit.max(e);
        }
    }
    (checked, worst, worst_limit)
}

fn assert_exact(curves: &[Curve], out: &Interpolation, levels: u32) {
    let (checked, worst, worst_limit) = worst_errors(curves, out, levels);
    assert!(checked > 10 * curves.len(), "only {checked} points checked");
    assert!(worst <= 1e-12, "refined middle polygon off by {worst:e}");
    assert!(
        worst_limit <= 1e-9,
        "limit off the curve by {worst_limit:e}"
    );
}

fn build(curves: &[Curve], names: &[&str]) -> Result<Interpolation, InterpolateError> {
    let cc: Vec<CubicCurve> = curves
        .iter()
        .zip(names)
        .map(|(c, n)| CubicCurve::new(c, n).unwrap())
        .collect();
    interpolate_curves(&cc, &InterpolateOptions::default())
}

/// Uniform unclamped knots `0, 1, 2, …` for `n` control points (an end with `d_1 = d_2`).
fn uniform(n: usize, step: f64) -> Vec<f64> {
    (0..n + 4).map(|i| i as f64 * step).collect()
}

/// Pairs of faces sharing an edge whose Newell normals point apart.
fn flipped_pairs(m: &PolyMesh) -> usize {
    let p = m.positions();
    let normal = |f: &[u32]| {
        let mut n = [0.0; 3];
        for i in 0..f.len() {
            let (a, b) = (p[f[i] as usize], p[f[(i + 1) % f.len()] as usize]);
            n[0] += (a[1] - b[1]) * (a[2] + b[2]);
            n[1] += (a[2] - b[2]) * (a[0] + b[0]);
            n[2] += (a[0] - b[0]) * (a[1] + b[1]);
        }
        n
    };
    let normals: Vec<V3> = m.faces().map(normal).collect();
    let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (i, f) in m.faces().enumerate() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            edges.entry((a.min(b), a.max(b))).or_default().push(i);
        }
    }
    edges
        .values()
        .filter(|fs| fs.len() == 2)
        .filter(|fs| {
            let (a, b) = (normals[fs[0]], normals[fs[1]]);
            a[0] * b[0] + a[1] * b[1] + a[2] * b[2] < 0.0
        })
        .count()
}

fn folds_at_level_4(out: &Interpolation) -> usize {
    flipped_pairs(&out.limit_mesh(4).unwrap())
}

// ---------------------------------------------------------------------------------------
// Item 2: closed curves written the way CAD tools export them

/// A closed non-uniform cubic (period knots `u`), polynomial or rational.
fn closed_curve(rational: bool) -> Curve {
    let pts: Vec<V3> = (0..7)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 7.0;
            [2.0 * a.cos(), 1.3 * a.sin(), 0.4 * (3.0 * a).sin()]
        })
        .collect();
    let k = KnotVector::periodic(3, &[0.0, 1.0, 1.5, 3.0, 4.0, 4.2, 5.0, 6.5]).unwrap();
    if rational {
        let w = vec![1.0, 1.4, 0.8, 1.1, 1.0, 0.7, 1.3];
        Curve::Nurbs(NurbsCurve::new(k, pts, w).unwrap())
    } else {
        Curve::BSpline(BSplineCurve::new(k, pts).unwrap())
    }
}

/// The closed curve as a CAD tool writes it to OBJ: its first 3 control points repeated at
/// the end and the knot vector unwrapped, in openNURBS's form without the two outermost
/// knots (`N + p − 1` values).
fn cad_obj(c: &Curve) -> String {
    let (k, pts, w) = match c {
        Curve::BSpline(b) => (b.knots(), b.points().to_vec(), vec![1.0; b.points().len()]),
        Curve::Nurbs(b) => (b.knots(), b.points().to_vec(), b.weights()),
    };
    let n = pts.len();
    let mut s = String::from("o rim\n");
    for i in 0..n + 3 {
        let p = pts[i % n];
        s += &format!("v {} {} {} {}\n", p[0], p[1], p[2], w[i % n]);
    }
    let rat = if matches!(c, Curve::Nurbs(_)) {
        "rat "
    } else {
        ""
    };
    let (a, b) = k.domain();
    s += &format!("cstype {rat}bspline\ndeg 3\ncurv {a} {b}");
    for i in 0..n + 3 {
        s += &format!(" {}", i + 1);
    }
    s += "\nparm u";
    let t = k.as_slice();
    for x in &t[1..t.len() - 1] {
        s += &format!(" {x}");
    }
    s + "\nend\n"
}

#[test]
fn a_closed_curve_in_cad_obj_form_is_read_closed() {
    for rational in [false, true] {
        let c = closed_curve(rational);
        let e = parse_obj_freeform(cad_obj(&c).as_bytes(), "cad.obj").unwrap();
        assert_eq!(
            e[0].geometry,
            Geometry::Curve(c.clone()),
            "rational {rational}"
        );
    }
}

#[test]
fn json_closed_to_obj_to_json_keeps_closed() {
    for rational in [false, true] {
        let items = vec![Geometry::Curve(closed_curve(rational))];
        let json = geometry_to_string(&items, GeometryFormat::Json);
        assert!(json.contains("\"closed\":true"), "{json}");
        let obj = geometry_to_string(&items, GeometryFormat::Obj);
        let back = parse_geometry(obj.as_bytes(), "c.obj").unwrap();
        let again: Vec<Geometry> = back.into_iter().map(|g| g.geometry).collect();
        assert_eq!(geometry_to_string(&again, GeometryFormat::Json), json);
    }
}

#[test]
fn a_closed_curve_from_cad_obj_gets_one_closed_zone_and_is_interpolated() {
    for rational in [false, true] {
        let c = closed_curve(rational);
        let e = parse_obj_freeform(cad_obj(&c).as_bytes(), "cad.obj").unwrap();
        let Geometry::Curve(read) = &e[0].geometry else {
            panic!("not a curve")
        };
        let out = build(std::slice::from_ref(read), &["rim"]).unwrap();
        let z = &out.zones[0];
        assert!(z.closed, "the zone must close");
        // Two quads per edge of the 7 distinct control points: no zone past the seam.
        assert_eq!(out.mesh.num_faces(), 2 * 7);
        assert_exact(&[c], &out, 4);
    }
}

// ---------------------------------------------------------------------------------------
// Item 3: clamped curves whose ends coincide

fn clamped_loop(weights: Option<Vec<f64>>) -> Curve {
    let mut pts: Vec<V3> = (0..8)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 8.0;
            [
                1.5 * a.cos(),
                a.sin() + 0.2 * (2.0 * a).cos(),
                0.3 * a.sin(),
            ]
        })
        .collect();
    pts.push(pts[0]);
    let k = KnotVector::new(
        3,
        vec![
            0.0, 0.0, 0.0, 0.0, 1.0, 1.7, 2.5, 3.0, 4.2, 5.0, 5.0, 5.0, 5.0,
        ],
    )
    .unwrap();
    match weights {
        None => Curve::BSpline(BSplineCurve::new(k, pts).unwrap()),
        Some(w) => Curve::Nurbs(NurbsCurve::new(k, pts, w).unwrap()),
    }
}

#[test]
fn a_clamped_curve_with_coinciding_ends_gets_one_seamless_zone() {
    for w in [
        None,
        Some(vec![1.2, 1.0, 0.7, 1.3, 1.0, 0.9, 1.5, 1.0, 1.2]),
    ] {
        let c = clamped_loop(w);
        let out = build(std::slice::from_ref(&c), &["loop"]).unwrap();
        let z = &out.zones[0];
        assert!(z.closed, "the two ends are joined");
        assert_eq!(z.middle.len(), 8);
        assert_eq!(out.mesh.num_faces(), 2 * 8);
        // Every middle point, the seam included, has one column: two side neighbours.
        let mut columns: HashMap<u32, Vec<u32>> = HashMap::new();
        for f in out.mesh.faces() {
            for i in 0..4 {
                if z.middle.contains(&f[i]) {
                    for nb in [f[(i + 1) % 4], f[(i + 3) % 4]] {
                        if !z.middle.contains(&nb) {
                            let col = columns.entry(f[i]).or_default();
                            if !col.contains(&nb) {
                                col.push(nb);
                            }
                        }
                    }
                }
            }
        }
        assert!(columns.values().all(|c| c.len() == 2), "{columns:?}");
        assert_exact(std::slice::from_ref(&c), &out, 4);
        // The seam point is on the surface: C(t_3) = P_0.
        let limit = Nurss::new(&out.mesh, &Default::default())
            .unwrap()
            .limit_points();
        assert!(dist(&limit[z.middle[0] as usize], &eval(&c, 0.0)) < 1e-12);
    }
}

#[test]
fn a_clamped_loop_whose_end_weights_differ_is_refused() {
    let c = clamped_loop(Some(vec![1.2, 1.0, 0.7, 1.3, 1.0, 0.9, 1.5, 1.0, 2.0]));
    let err = CubicCurve::new(&c, "loop").unwrap_err().to_string();
    assert!(
        err.starts_with("loop: ") && err.contains("weights differ"),
        "{err}"
    );
}

// ---------------------------------------------------------------------------------------
// Item 4: two curves ending at one point from nearly opposite directions

/// An unclamped curve of 6 points leaving the origin along `dir` in the plane `z = 0`,
/// bending to the side, its points `step` apart along `dir`.
fn leaving(dir: [f64; 2], bend: f64, step: f64, knot_step: f64) -> Curve {
    let side = [-dir[1], dir[0]];
    let pts = (0..6)
        .map(|i| {
            let t = i as f64 * step;
            let b = bend * t * t;
            [t * dir[0] + b * side[0], t * dir[1] + b * side[1], 0.0]
        })
        .collect();
    bspline(uniform(6, knot_step), pts)
}

fn dir(deg: f64) -> [f64; 2] {
    let r = deg.to_radians();
    [r.cos(), r.sin()]
}

#[test]
fn ends_from_nearly_opposite_directions_are_interpolated_without_folds() {
    // The case, 170°–179° apart in one plane, folded the surface (22–58 flipped face
    // pairs at level 4); they are joined into one zone through the point.
    for deg in [170.0, 172.0, 175.0, 177.0, 179.0] {
        for (bend, step) in [(0.05, 1.0), (-0.05, 1.0), (0.05, 0.5)] {
            let a = leaving([1.0, 0.0], bend, 1.0, 1.0);
            let b = leaving(dir(deg), bend, step, 1.0);
            let out = build(&[a.clone(), b.clone()], &["a", "b"]).unwrap();
            assert_eq!(
                folds_at_level_4(&out),
                0,
                "{deg}°, bend {bend}, step {step}"
            );
            assert_exact(&[a, b], &out, 3);
        }
    }
}

#[test]
fn nearly_opposite_ends_whose_intervals_do_not_continue_are_refused_with_the_angle() {
    let a = leaving([1.0, 0.0], 0.05, 1.0, 1.0);
    let b = leaving(dir(174.0), 0.05, 1.0, 0.5);
    let err = build(&[a, b], &["east", "west"]).unwrap_err().to_string();
    assert!(
        err.contains("east ends at its point 0")
            && err.contains("west ends at its point 0")
            && err.contains("174.0°"),
        "{err}"
    );
}

#[test]
fn ends_and_crossings_at_40_to_145_degrees_do_not_fold() {
    // Unequal edge lengths and bends: a side point jumping from along a line of the group to
    // across its own polygon folded ends 60°–175° apart and crossings at 45°.
    for deg in [40.0, 45.0, 60.0, 90.0, 120.0, 135.0, 145.0] {
        for (bend, step) in [(0.05, 1.0), (0.05, 0.5), (0.05, 2.0), (-0.05, 1.0)] {
            let a = leaving([1.0, 0.0], bend, 1.0, 1.0);
            let b = leaving(dir(deg), -bend, step, 1.0);
            let out = build(&[a.clone(), b.clone()], &["a", "b"]).unwrap();
            assert_eq!(folds_at_level_4(&out), 0, "ends {deg}°, {bend}, {step}");
        }
    }
    for deg in [30.0, 45.0, 60.0, 75.0] {
        let line = |d: [f64; 2], lift: f64| {
            let pts = (-3i32..=3)
                .map(|i| {
                    let t = i as f64;
                    let z = if i.abs() >= 2 { lift * t * t } else { 0.0 };
                    [t * d[0], t * d[1], z]
                })
                .collect();
            bspline(uniform(7, 1.0), pts)
        };
        for lift in [0.0, 0.1] {
            let out = build(&[line([1.0, 0.0], lift), line(dir(deg), lift)], &["a", "b"]).unwrap();
            assert_eq!(folds_at_level_4(&out), 0, "crossing at {deg}°, lift {lift}");
        }
    }
}

#[test]
fn lines_closer_than_30_degrees_are_refused_naming_the_curves_and_the_angle() {
    let line = |d: [f64; 2]| {
        let pts = (-3i32..=3)
            .map(|i| [i as f64 * d[0], i as f64 * d[1], 0.0])
            .collect();
        bspline(uniform(7, 1.0), pts)
    };
    let err = build(&[line([1.0, 0.0]), line(dir(20.0))], &["x", "y"])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("x passes at its point 3")
            && err.contains("y passes at its point 3")
            && err.contains("20.0°"),
        "{err}"
    );
    // Ends 20° apart (their zones would overlap): refused with both angles.
    let a = leaving([1.0, 0.0], 0.0, 1.0, 1.0);
    let b = leaving(dir(20.0), 0.0, 1.0, 1.0);
    let err = build(&[a, b], &["a", "b"]).unwrap_err().to_string();
    assert!(
        err.contains("a ends at its point 0") && err.contains("20.0°"),
        "{err}"
    );
}

// ---------------------------------------------------------------------------------------
// Item 5: no unused vertices

fn unused_vertices(m: &PolyMesh) -> usize {
    let mut used = vec![false; m.num_vertices()];
    for f in m.faces() {
        for &v in f {
            used[v as usize] = true;
        }
    }
    used.iter().filter(|u| !**u).count()
}

#[test]
fn crossings_leave_no_unused_vertex() {
    let (a, b) = crossing_pair();
    let out = build(&[a, b], &["a", "b"]).unwrap();
    assert_eq!(unused_vertices(&out.mesh), 0);
    // 2 zones × 7 columns × 3 points, less the shared centre, its 4 neighbours (each also a
    // side point of the other zone) and the 4 corners counted twice.
    assert_eq!(out.mesh.num_vertices(), 2 * 21 - 9);
}

// ---------------------------------------------------------------------------------------
// Item 6: where a junction's zone runs beyond the curve's end

#[test]
fn an_ending_zone_runs_on_along_the_spline_extended_by_the_phantom_point() {
    // `c` ends at X = (0, 0, 0) on `a` (a T-junction). Beyond its domain [t_3, t_n] the zone's
    // limit follows the cubic B-spline of c's polygon extended by 2X − P_1 (its reversal
    // here: c starts at X), not c's own first polynomial piece continued.
    let (a, _) = crossing_pair();
    let pts: Vec<V3> = vec![
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.1],
        [0.2, 2.0, 0.3],
        [0.0, 3.0, 0.2],
        [-0.3, 4.0, 0.0],
    ];
    let c = bspline(uniform(5, 1.0), pts.clone());
    let out = build(&[a, c.clone()], &["a", "c"]).unwrap();
    // The extended curve: phantom P_{−1} = 2 P_0 − P_1 with knot −1 in front.
    let mut ext_pts = vec![[0.0, -1.0, -0.1]];
    ext_pts.extend(pts);
    let ext = bspline((-1..9).map(|i| i as f64).collect(), ext_pts);
    let z = &out.zones[1];
    let mut s = Nurss::new(&out.mesh, &Default::default()).unwrap();
    let mut ids = z.middle.clone();
    for _ in 0..4 {
        ids = refine_polyline(s.topology(), &ids, false).unwrap();
        s.step();
    }
    let limit = s.limit_points();
    let zk = middle_knots(&s, &ids, z);
    let (mut checked, mut worst, mut natural_gap) = (0, 0.0f64, 0.0f64);
    for (j, &t) in zk.iter().enumerate() {
        // Between X (knot 2) and the start of c's domain (knot 3).
        if !(2.0..3.0).contains(&t) {
            continue;
        }
        let p = limit[ids[j] as usize];
        worst = worst.max(dist(&p, &eval(&ext, t)));
        // c's first piece (span [3, 4]) continued to t.
        natural_gap = natural_gap.max(dist(&p, &blossom(&c, 3, [t, t, t])));
        checked += 1;
    }
    assert!(checked >= 8, "{checked}");
    assert!(worst < 1e-12, "off the extended spline by {worst:e}");
    assert!(
        natural_gap > 1e-3,
        "the natural extension is not it: {natural_gap:e}"
    );
    // The limit reaches X, the group's fixed centre.
    assert!(
        dist(
            &limit[ids[zk.iter().position(|&t| t == 2.0).unwrap()] as usize],
            &[0.0; 3]
        ) < 1e-14
    );
}

#[test]
fn the_docs_say_where_an_ending_zone_runs() {
    let readme = include_str!("../../../../README.md");
    let page = include_str!("../../../../docs/curve-interpolation.md");
    let crossing = include_str!("../../src/curves/crossing.rs");
    assert!(!readme.contains("natural extension"), "README.md");
    for (name, text) in [
        ("docs/curve-interpolation.md", page),
        ("crossing.rs", crossing),
    ] {
        assert!(!text.contains("natural extension"), "{name}");
        assert!(
            text.contains("2 X − P_{n−2}") || text.contains("2X − P_{n−2}"),
            "{name}"
        );
    }
}

// ---------------------------------------------------------------------------------------
// Item 7: three and four curves through one point (Corollary 1, Fig. 13 b, c)

/// Uniform curves on the line through the origin along `d`: the whole line (points
/// −3..=3), or the half ending at the origin from −d (points −3..=0) or leaving it along +d
/// (0..=3), bent off the line away from the origin.
fn on_line(d: V3, part: i32, bend: V3) -> Curve {
    let range: Vec<i32> = match part {
        0 => (-3..=3).collect(),
        -1 => (-3..=0).collect(),
        _ => (0..=3).collect(),
    };
    let pts: Vec<V3> = range
        .iter()
        .map(|&i| {
            let t = i as f64;
            let b = if i.abs() >= 2 { t * t * t / 8.0 } else { 0.0 };
            [0, 1, 2].map(|k| t * d[k] + b * bend[k])
        })
        .collect();
    let n = pts.len();
    bspline(uniform(n, 1.0), pts)
}

fn assert_through_centre(curves: &[Curve], names: &[&str]) {
    let out = build(curves, names).unwrap();
    assert_eq!(unused_vertices(&out.mesh), 0);
    assert_exact(curves, &out, 4);
    // The group's centre is one vertex of every zone and stays fixed: on the limit surface.
    let x = out.zones[0]
        .middle
        .iter()
        .copied()
        .find(|&v| out.mesh.positions()[v as usize] == [0.0; 3])
        .unwrap();
    assert!(out.zones.iter().all(|z| z.middle.contains(&x)));
    let limit = Nurss::new(&out.mesh, &Default::default())
        .unwrap()
        .limit_points();
    assert!(dist(&limit[x as usize], &[0.0; 3]) < 1e-14);
    assert_eq!(folds_at_level_4(&out), 0);
}

#[test]
fn three_curves_through_one_point_are_interpolated() {
    let (u, v) = ([1.0, 0.0, 0.0], [0.2, 1.1, 0.0]);
    let up = [0.0, 0.0, 1.0];
    // One passing, two ending from opposite sides (the crossing's second curve in two).
    assert_through_centre(
        &[on_line(u, 0, up), on_line(v, -1, up), on_line(v, 1, up)],
        &["a", "b1", "b2"],
    );
    // Three ending: a pair on one line, one alone on the other (with its phantom).
    assert_through_centre(
        &[on_line(u, -1, up), on_line(u, 1, up), on_line(v, 1, up)],
        &["a1", "a2", "b"],
    );
}

#[test]
fn four_curves_ending_at_one_point_are_interpolated() {
    let (u, v) = ([1.0, 0.1, 0.0], [-0.3, 1.0, 0.2]);
    let up = [0.1, 0.0, 1.0];
    assert_through_centre(
        &[
            on_line(u, -1, up),
            on_line(v, 1, up),
            on_line(u, 1, up),
            on_line(v, -1, up),
        ],
        &["west", "north", "east", "south"],
    );
}

#[test]
fn opposite_curves_through_a_group_join_g2() {
    // a1 and a2 end at the centre from opposite sides, b passes: a1 ∪ a2 is one cubic
    // B-spline through the centre, so its limit points across the centre are those of the
    // one curve on the whole line.
    let (u, v) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let up = [0.0, 0.3, 1.0];
    let whole = on_line(u, 0, up);
    let out = build(
        &[on_line(u, -1, up), on_line(u, 1, up), on_line(v, 0, up)],
        &["a1", "a2", "b"],
    )
    .unwrap();
    let single = build(&[whole.clone(), on_line(v, 0, up)], &["a", "b"]).unwrap();
    let limit = |o: &Interpolation| {
        Nurss::new(&o.mesh, &Default::default())
            .unwrap()
            .limit_points()
    };
    let (l3, l2) = (limit(&out), limit(&single));
    // a1's middle polygon (phantom included) runs from -3 to 1 on the line; the single
    // curve's from -3 to 3: the same points on the line, the same limit points.
    for k in 0..5 {
        let p = l3[out.zones[0].middle[k] as usize];
        let q = l2[single.zones[0].middle[k] as usize];
        assert!(dist(&p, &q) < 1e-12, "{k}: {p:?} {q:?}");
    }
}
