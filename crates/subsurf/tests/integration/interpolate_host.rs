//! Curves embedded in a host quad mesh ([JOS 2003], §3 and Fig. 11): the control polygon runs
//! along host edges, rows are inserted along it, and the NURSS refinement of the whole mesh
//! refines the middle polygon exactly as midpoint knot insertion refines the curve, so the
//! limit surface passes through the curve.
//!
//! References are independent of the embedding code: refined control points are blossoms of
//! the curve (de Boor with a different parameter at each level), limit points are compared
//! with de Boor evaluation. Hosts are built here: a grid, a tube, and fans of 5 and 6 quad
//! sectors whose centre (valence 5 or 6) is on the polygon.

use subsurf::curves::{
    embed_curves, refine_polyline, CubicCurve, HostOptions, InterpolateError, Interpolation, Zone,
};
use subsurf::io::{parse_obj, write_obj, WriteOptions};
use subsurf::mesh::{Crease, EdgeInterval, PolyMesh, VertexWeight};
use subsurf::nonuniform::Nurss;
use subsurf::nurbs::{BSplineCurve, Curve, KnotVector, NurbsCurve};

use crate::common::curves;
use curves::{check_middle, dist, eval, knots, middle_knots, size, V3};

/// The faces within `rings` face rings of the polyline `ids`, with their intervals and
/// weights, as a new NURSS level (after the first step, which has no side intervals), and
/// `ids` in it.
///
/// Why this is exact near the polyline: new middle points read the 1-ring of the middle
/// polygon and intervals two edges around its neighbours; one level up, those come from the
/// parent's rings ≤ 2. The trimmed mesh's new boundary (ring 4) changes, through boundary
/// rules, parent vertices of ring ≥ 3 only, whose children are at rings ≥ 5. So rings ≤ 4 of
/// every level are those of the untrimmed refinement, and the level-8 middle polygon is the
/// same as refining the whole mesh 8 times (which is 4^8 times the host's faces). Any error
/// this made would show in the comparison with the blossoms, never hide one.
fn trimmed(s: &Nurss, ids: &[u32], rings: usize) -> (Nurss, Vec<u32>) {
    use std::collections::{HashMap, HashSet};
    let mesh = s.to_mesh(false);
    let mut near: HashSet<u32> = ids.iter().copied().collect();
    let mut keep: Vec<bool> = vec![false; mesh.num_faces()];
    for _ in 0..rings {
        let mut next = near.clone();
        for (f, fv) in mesh.faces().enumerate() {
            if !keep[f] && fv.iter().any(|v| near.contains(v)) {
                keep[f] = true;
                next.extend(fv.iter().copied());
            }
        }
        near = next;
    }
    let mut map: HashMap<u32, u32> = HashMap::new();
    let mut pos = Vec::new();
    let mut faces = Vec::new();
    for (f, fv) in mesh.faces().enumerate() {
        if !keep[f] {
            continue;
        }
        faces.push(
            fv.iter()
                .map(|&v| {
                    *map.entry(v).or_insert_with(|| {
                        pos.push(mesh.positions()[v as usize]);
                        (pos.len() - 1) as u32
                    })
                })
                .collect::<Vec<u32>>(),
        );
    }
    let mut edges: HashSet<(u32, u32)> = HashSet::new();
    for f in &faces {
        for i in 0..f.len() {
            let (a, b) = (f[i], f[(i + 1) % f.len()]);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    let mut out = PolyMesh::from_faces(pos, &faces).unwrap();
    out.knots.intervals = mesh
        .knots
        .intervals
        .iter()
        .filter_map(|t| {
            let (a, b) = (*map.get(&t.v0)?, *map.get(&t.v1)?);
            edges
                .contains(&(a.min(b), a.max(b)))
                .then_some(EdgeInterval {
                    v0: a,
                    v1: b,
                    interval: t.interval,
                })
        })
        .collect();
    out.knots.weights = mesh
        .knots
        .weights
        .iter()
        .filter_map(|w| {
            Some(VertexWeight {
                vertex: *map.get(&w.vertex)?,
                weight: w.weight,
            })
        })
        .collect();
    let ids = ids.iter().map(|v| map[v]).collect();
    (Nurss::new(&out, &Default::default()).unwrap(), ids)
}

/// Checks, at levels 0..=levels, every middle-polygon point that influences the curve's
/// domain against the blossom, and the limit points of the middle polygon at the last level
/// against de Boor. Returns (points checked, worst refined-polygon error, worst limit error),
/// errors relative to the curve's size.
fn check_zone(curve: &Curve, mesh: &PolyMesh, z: &Zone, levels: u32) -> (usize, f64, f64) {
    let kv = knots(curve);
    let (a, b) = kv.domain();
    let period = b - a;
    let sz = size(curve);
    let mut s = Nurss::new(mesh, &Default::default()).unwrap();
    let mut ids = z.middle.clone();
    let (mut checked, mut worst) = (0, 0.0f64);
    for level in 0..=levels {
        if level > 0 {
            ids = refine_polyline(s.topology(), &ids, z.closed).unwrap();
            s.step();
            (s, ids) = trimmed(&s, &ids, 4);
        }
        let (c, w) = check_middle(curve, &s, &ids, z);
        checked += c;
        worst = worst.max(w);
    }
    let limit = s.limit_points();
    let zk = middle_knots(&s, &ids, z);
    let mut worst_limit = 0.0f64;
    // Open: from the refined P_0 to the refined P_{n−1} (the phantom edges beyond them may
    // have zero intervals, clamped ends, so their points share the end knots).
    let step = 1usize << levels;
    let (lo, hi) = if z.closed {
        (0, ids.len() - 1)
    } else {
        (z.first * step, (z.first + z.count - 1) * step)
    };
    for (j, &v) in ids.iter().enumerate().take(hi + 1).skip(lo) {
        let t = zk[j];
        if z.closed || (t >= a && t <= b) {
            let t = if z.closed {
                a + (t - a).rem_euclid(period)
            } else {
                t
            };
            let on_curve = eval(curve, t);
            worst_limit = worst_limit.max(dist(&limit[v as usize], &on_curve) / sz);
        }
    }
    (checked, worst, worst_limit)
}

/// Asserts Theorem 1 for every zone: refined middle polygons within 1e-12, limit within 1e-9.
fn assert_interpolates(curves: &[Curve], out: &Interpolation, levels: u32, min_checked: usize) {
    for (c, z) in curves.iter().zip(&out.zones) {
        let (checked, worst, worst_limit) = check_zone(c, &out.mesh, z, levels);
        assert!(
            checked >= min_checked,
            "{}: only {checked} checked",
            z.label
        );
        assert!(
            worst <= 1e-12,
            "{}: refined polygon off by {worst:e}",
            z.label
        );
        assert!(
            worst_limit <= 1e-9,
            "{}: limit off by {worst_limit:e}",
            z.label
        );
    }
}

fn embed(host: &PolyMesh, curves: &[Curve]) -> Result<Interpolation, InterpolateError> {
    let cc: Vec<CubicCurve> = curves
        .iter()
        .enumerate()
        .map(|(i, c)| CubicCurve::new(c, &format!("curve {i}")).unwrap())
        .collect();
    embed_curves(host, &cc, &HostOptions::default())
}

// ---------------------------------------------------------------------------------------
// Hosts

/// A wavy `(nx + 1) × (ny + 1)` grid; vertex `(i, j)` is `i * (ny + 1) + j`.
fn grid(nx: usize, ny: usize) -> PolyMesh {
    let mut pos = Vec::new();
    for i in 0..=nx {
        for j in 0..=ny {
            let (x, y) = (i as f64, j as f64);
            pos.push([
                x + 0.1 * (0.7 * y).sin(),
                y + 0.3 * (0.9 * x).sin(),
                0.4 * (0.5 * x).cos() * (0.6 * y).sin(),
            ]);
        }
    }
    let id = |i: usize, j: usize| (i * (ny + 1) + j) as u32;
    let mut faces = Vec::new();
    for i in 0..nx {
        for j in 0..ny {
            faces.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    PolyMesh::from_faces(pos, &faces).unwrap()
}

/// A tube of `nk` columns round and `nl + 1` rings, radius varying round and along it; vertex
/// `(k, l)` is `k * (nl + 1) + l`.
fn tube(nk: usize, nl: usize) -> PolyMesh {
    let mut pos = Vec::new();
    for k in 0..nk {
        for l in 0..=nl {
            let a = k as f64 * std::f64::consts::TAU / nk as f64;
            let r = 2.0 + 0.4 * (2.0 * a).cos() + 0.15 * l as f64;
            pos.push([
                r * a.cos(),
                r * a.sin(),
                0.8 * l as f64 + 0.2 * (3.0 * a).sin(),
            ]);
        }
    }
    let id = |k: usize, l: usize| ((k % nk) * (nl + 1) + l) as u32;
    let mut faces = Vec::new();
    for k in 0..nk {
        for l in 0..nl {
            faces.push(vec![id(k, l), id(k + 1, l), id(k + 1, l + 1), id(k, l + 1)]);
        }
    }
    PolyMesh::from_faces(pos, &faces).unwrap()
}

/// A fan of `s` quad sectors (each an `r × r` grid) round a centre of valence `s`, with the
/// position of the vertex at distance `(a, b)` along spokes `k` and `k + 1`; returns the
/// mesh and the vertex at distance `i` on spoke `k` (`i = 0` the centre).
fn fan(s: usize, r: usize) -> (PolyMesh, impl Fn(usize, usize) -> u32) {
    let spoke_dir = |k: usize| {
        let a = (k % s) as f64 * std::f64::consts::TAU / s as f64;
        [a.cos(), a.sin()]
    };
    let height = |x: f64, y: f64| 0.3 * (0.4 * x).sin() + 0.2 * (0.5 * y).cos() * x / 3.0;
    let mut pos: Vec<V3> = vec![[0.0, 0.0, height(0.0, 0.0)]];
    // Spoke vertices 1..=r of spoke k: 1 + k * r + (i - 1).
    for k in 0..s {
        let d = spoke_dir(k);
        for i in 1..=r {
            let (x, y) = (d[0] * i as f64, d[1] * i as f64);
            pos.push([x, y, height(x, y)]);
        }
    }
    let spoke = move |k: usize, i: usize| -> u32 {
        if i == 0 {
            0
        } else {
            (1 + (k % s) * r + (i - 1)) as u32
        }
    };
    // Sector interiors: (a, b) with a, b in 1..=r.
    let base = pos.len();
    for k in 0..s {
        let (d0, d1) = (spoke_dir(k), spoke_dir(k + 1));
        for a in 1..=r {
            for b in 1..=r {
                let (x, y) = (
                    d0[0] * a as f64 + d1[0] * b as f64,
                    d0[1] * a as f64 + d1[1] * b as f64,
                );
                pos.push([x, y, height(x, y)]);
            }
        }
    }
    let at = |k: usize, a: usize, b: usize| -> u32 {
        if b == 0 {
            spoke(k, a)
        } else if a == 0 {
            spoke(k + 1, b)
        } else {
            (base + (k % s) * r * r + (a - 1) * r + (b - 1)) as u32
        }
    };
    let mut faces = Vec::new();
    for k in 0..s {
        for a in 0..r {
            for b in 0..r {
                faces.push(vec![
                    at(k, a, b),
                    at(k, a + 1, b),
                    at(k, a + 1, b + 1),
                    at(k, a, b + 1),
                ]);
            }
        }
    }
    (PolyMesh::from_faces(pos, &faces).unwrap(), spoke)
}

fn points_of(host: &PolyMesh, ids: &[u32]) -> Vec<V3> {
    ids.iter().map(|&v| host.positions()[v as usize]).collect()
}

fn open_curve(knots: Vec<f64>, pts: Vec<V3>) -> Curve {
    Curve::BSpline(BSplineCurve::new(KnotVector::new(3, knots).unwrap(), pts).unwrap())
}

/// Non-uniform, unclamped knots for `n` control points (`d_1 ≠ d_2`, so the interval across
/// the phantom host edge matters).
fn non_uniform_knots(n: usize) -> Vec<f64> {
    let mut t = vec![0.0];
    for i in 0..n + 3 {
        t.push(t[i] + 0.6 + 0.5 * ((i * 7) % 5) as f64 / 4.0);
    }
    t
}

// ---------------------------------------------------------------------------------------
// Interpolation

#[test]
fn open_non_uniform_curve_on_a_host_grid_is_interpolated() {
    let host = grid(12, 8);
    let ids: Vec<u32> = (2..=10).map(|i| (i * 9 + 4) as u32).collect();
    let curve = open_curve(non_uniform_knots(ids.len()), points_of(&host, &ids));
    let out = embed(&host, std::slice::from_ref(&curve)).unwrap();
    // Cut and insert: 2 new vertices per control point, 2 zone faces per polygon edge
    // (8 real, 2 phantom), host faces kept.
    assert_eq!(out.mesh.num_vertices(), host.num_vertices() + 2 * 9);
    assert_eq!(out.mesh.num_faces(), host.num_faces() + 2 * 10);
    assert_eq!(
        out.zones[0].middle.len(),
        11,
        "phantom host vertices at both ends"
    );
    assert_eq!(&out.zones[0].middle[1..10], &ids[..]);
    assert_interpolates(&[curve], &out, 8, 100);
}

#[test]
fn clamped_curve_on_a_host_grid_is_interpolated_and_ends_at_its_end_points() {
    let host = grid(10, 7);
    let ids: Vec<u32> = (2..=8).map(|i| (i * 8 + 3) as u32).collect();
    let pts = points_of(&host, &ids);
    let curve = Curve::BSpline(BSplineCurve::clamped_uniform(3, pts.clone()).unwrap());
    let out = embed(&host, std::slice::from_ref(&curve)).unwrap();
    assert_interpolates(std::slice::from_ref(&curve), &out, 6, 60);
    let limit = Nurss::new(&out.mesh, &Default::default())
        .unwrap()
        .limit_points();
    let z = &out.zones[0];
    for (k, p) in [(z.first, pts[0]), (z.first + 6, pts[6])] {
        assert!(dist(&limit[z.middle[k] as usize], &p) < 1e-12);
    }
}

#[test]
fn closed_curve_round_a_host_tube_is_interpolated() {
    let host = tube(12, 6);
    let ids: Vec<u32> = (0..12).map(|k| (k * 7 + 3) as u32).collect();
    let k = KnotVector::periodic(
        3,
        &[
            0.0, 1.0, 1.4, 2.5, 3.0, 4.2, 5.0, 5.5, 6.8, 7.5, 8.0, 9.1, 10.0,
        ],
    )
    .unwrap();
    let curve = Curve::BSpline(BSplineCurve::new(k, points_of(&host, &ids)).unwrap());
    let out = embed(&host, std::slice::from_ref(&curve)).unwrap();
    assert!(out.zones[0].closed);
    assert_eq!(out.mesh.num_faces(), host.num_faces() + 24);
    assert_interpolates(&[curve], &out, 8, 200);
}

/// A curve through the centre of a fan of `s` sectors: in along spoke 0, out along `out`.
fn fan_curve(s: usize, out: usize) -> (PolyMesh, Curve) {
    let (host, spoke) = fan(s, 5);
    let mut ids: Vec<u32> = (1..=4).rev().map(|i| spoke(0, i)).collect();
    ids.extend((0..=4).map(|i| spoke(out, i)));
    let curve = open_curve(non_uniform_knots(ids.len()), points_of(&host, &ids));
    (host, curve)
}

#[test]
fn polygon_through_a_valence_5_vertex_is_interpolated_with_fig_11_side_intervals() {
    // One host edge on one side of the centre, two on the other: the inserted side vertex
    // there has valence 5 and gets auxiliary intervals.
    let (host, curve) = fan_curve(5, 2);
    let out = embed(&host, std::slice::from_ref(&curve)).unwrap();
    assert_eq!(out.mesh.knots.side_intervals.len(), 4);
    assert_interpolates(&[curve], &out, 8, 100);
}

#[test]
fn polygon_through_valence_6_vertices_is_interpolated() {
    // Two host edges on each side (straight through), and one against three.
    for out_spoke in [3, 2] {
        let (host, curve) = fan_curve(6, out_spoke);
        let out = embed(&host, std::slice::from_ref(&curve)).unwrap();
        assert!(!out.mesh.knots.side_intervals.is_empty());
        assert_interpolates(&[curve], &out, 8, 100);
    }
}

#[test]
fn without_the_fig_11_side_intervals_the_curve_is_missed() {
    // The same mesh with the auxiliary intervals dropped: the rules at the valence-5 side
    // vertex read the host's intervals, the zone is no longer symmetric on the first step.
    let (host, curve) = fan_curve(5, 2);
    let mut out = embed(&host, std::slice::from_ref(&curve)).unwrap();
    out.mesh.knots.side_intervals.clear();
    let (_, worst, _) = check_zone(&curve, &out.mesh, &out.zones[0], 3);
    assert!(worst > 1e-5, "expected a visible error, got {worst:e}");
}

#[test]
fn rational_curve_on_a_host_grid_is_interpolated() {
    // Weights on the polygon; the inserted side points carry their middle point's weight.
    let host = grid(12, 8);
    let ids: Vec<u32> = (2..=10).map(|i| (i * 9 + 4) as u32).collect();
    let w: Vec<f64> = (0..ids.len())
        .map(|i| 1.0 + 0.6 * ((i * 3) % 4) as f64 / 3.0)
        .collect();
    let curve = Curve::Nurbs(
        NurbsCurve::new(
            KnotVector::new(3, non_uniform_knots(ids.len())).unwrap(),
            points_of(&host, &ids),
            w,
        )
        .unwrap(),
    );
    let out = embed(&host, std::slice::from_ref(&curve)).unwrap();
    assert!(!out.mesh.knots.weights.is_empty());
    assert_interpolates(&[curve], &out, 8, 100);
}

#[test]
fn two_curves_in_one_host_are_both_interpolated() {
    // A row and a column of a grid that do not meet, the column through non-uniform knots.
    let host = grid(14, 12);
    let row: Vec<u32> = (2..=7).map(|i| (i * 13 + 3) as u32).collect();
    let col: Vec<u32> = (4..=10).map(|j| (11 * 13 + j) as u32).collect();
    let a = Curve::BSpline(BSplineCurve::clamped_uniform(3, points_of(&host, &row)).unwrap());
    let b = open_curve(non_uniform_knots(col.len()), points_of(&host, &col));
    let out = embed(&host, &[a.clone(), b.clone()]).unwrap();
    assert_eq!(out.zones.len(), 2);
    assert_interpolates(&[a, b], &out, 6, 40);
}

#[test]
fn curves_sharing_host_faces_are_refused() {
    // Rows 3 and 4 of a grid: the faces between them would belong to both zones.
    let host = grid(12, 8);
    let r3: Vec<u32> = (2..=8).map(|i| (i * 9 + 3) as u32).collect();
    let r4: Vec<u32> = (2..=8).map(|i| (i * 9 + 4) as u32).collect();
    let a = Curve::BSpline(BSplineCurve::clamped_uniform(3, points_of(&host, &r3)).unwrap());
    let b = Curve::BSpline(BSplineCurve::clamped_uniform(3, points_of(&host, &r4)).unwrap());
    let err = embed(&host, &[a, b]).unwrap_err();
    assert!(matches!(err, InterpolateError::Host { .. }), "{err}");
    assert!(err.to_string().contains("curve 0 and this one"), "{err}");
}

#[test]
fn inserted_rows_are_symmetric_about_the_polygon_and_the_host_is_kept() {
    let host = grid(12, 8);
    let ids: Vec<u32> = (2..=10).map(|i| (i * 9 + 4) as u32).collect();
    let curve = open_curve(non_uniform_knots(ids.len()), points_of(&host, &ids));
    let out = embed(&host, &[curve]).unwrap();
    let p = out.mesh.positions();
    // Every host vertex stays where it was.
    for (a, b) in host.positions().iter().zip(p) {
        assert!(dist(a, b) < 1e-15);
    }
    // New vertices come in pairs T_j, B_j with T_j + B_j = 2 P_j, at a third of the shortest
    // host edge (grid edges here are about 1 long).
    for (j, &v) in ids.iter().enumerate() {
        let (t, b) = (
            p[host.num_vertices() + 2 * j],
            p[host.num_vertices() + 2 * j + 1],
        );
        let m = [0, 1, 2].map(|k| 0.5 * (t[k] + b[k]));
        assert!(dist(&m, &p[v as usize]) < 1e-14);
        let h = dist(&t, &p[v as usize]);
        assert!(h > 0.2 && h < 0.4, "half width {h}");
    }
}

#[test]
fn embedded_mesh_survives_obj_round_trip_with_its_side_intervals() {
    let (host, curve) = fan_curve(5, 2);
    let out = embed(&host, std::slice::from_ref(&curve)).unwrap();
    let mut bytes = Vec::new();
    write_obj(
        &mut bytes,
        &out.mesh,
        &WriteOptions {
            normals: None,
            scheme: None,
            comment: None,
        },
    )
    .unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    assert_eq!(text.matches("t sideinterval").count(), 4);
    let back = parse_obj(&bytes, "embedded.obj").unwrap().mesh;
    assert_eq!(back.knots.side_intervals.len(), 4);
    let (_, worst, worst_limit) = check_zone(&curve, &back, &out.zones[0], 6);
    assert!(
        worst <= 1e-12 && worst_limit <= 1e-9,
        "{worst:e} {worst_limit:e}"
    );
}

// ---------------------------------------------------------------------------------------
// Errors

#[test]
fn control_point_off_the_host_is_refused_naming_curve_and_point() {
    let host = grid(10, 6);
    let ids: Vec<u32> = (2..=7).map(|i| (i * 7 + 3) as u32).collect();
    let mut pts = points_of(&host, &ids);
    pts[3][2] += 0.01;
    let curve = Curve::BSpline(BSplineCurve::clamped_uniform(3, pts).unwrap());
    let err = embed(&host, &[curve]).unwrap_err();
    assert!(
        matches!(err, InterpolateError::HostVertex { index: 3, .. }),
        "{err}"
    );
    assert!(
        err.to_string().starts_with("curve 0, control point 3 at ("),
        "{err}"
    );
}

#[test]
fn control_points_not_joined_by_a_host_edge_are_refused() {
    let host = grid(10, 6);
    // Points 2 and 3 are two grid steps apart.
    let ids: Vec<u32> = [2, 3, 4, 6, 7, 8]
        .iter()
        .map(|i| (i * 7 + 3) as u32)
        .collect();
    let curve = Curve::BSpline(BSplineCurve::clamped_uniform(3, points_of(&host, &ids)).unwrap());
    let err = embed(&host, &[curve]).unwrap_err();
    assert!(
        matches!(err, InterpolateError::Host { index: 2, .. }),
        "{err}"
    );
    assert!(
        err.to_string()
            .contains("no host edge joins it to control point 3"),
        "{err}"
    );
}

#[test]
fn curve_ending_on_the_host_boundary_is_refused() {
    let host = grid(10, 6);
    let ids: Vec<u32> = (0..=6).map(|i| (i * 7 + 3) as u32).collect();
    let curve = Curve::BSpline(BSplineCurve::clamped_uniform(3, points_of(&host, &ids)).unwrap());
    let err = embed(&host, &[curve]).unwrap_err();
    assert!(
        matches!(err, InterpolateError::Host { index: 0, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("boundary"), "{err}");
}

#[test]
fn polygon_along_the_host_boundary_is_refused() {
    let host = grid(10, 6);
    let ids: Vec<u32> = (2..=7).map(|i| (i * 7) as u32).collect();
    let curve = Curve::BSpline(BSplineCurve::clamped_uniform(3, points_of(&host, &ids)).unwrap());
    let err = embed(&host, &[curve]).unwrap_err();
    assert!(err.to_string().contains("boundary"), "{err}");
}

/// Along row 3 of a grid, then up column 6: the turn at (6, 3), control point 4, is a
/// corner of one host face (the side vertex inside the turn gets valence 3).
fn turning_polygon(host: &PolyMesh) -> Vec<V3> {
    let mut ids: Vec<u32> = (2..=6).map(|i| (i * 7 + 3) as u32).collect();
    ids.extend([4, 5].iter().map(|j| (6 * 7 + j) as u32));
    points_of(host, &ids)
}

#[test]
fn polygon_turning_90_degrees_at_a_grid_vertex_is_interpolated() {
    // Beyond the paper: with equal intervals on the two edges at the turn, made the zone's
    // column interval, Theorem 1 holds at the valence-3 side vertex (host module docs).
    let host = grid(10, 6);
    let pts = turning_polygon(&host);
    for curve in [
        Curve::BSpline(BSplineCurve::clamped_uniform(3, pts.clone()).unwrap()),
        open_curve((0..11).map(|i| 0.7 * i as f64).collect(), pts),
    ] {
        let out = embed(&host, std::slice::from_ref(&curve)).unwrap();
        assert_interpolates(&[curve], &out, 8, 100);
    }
}

#[test]
fn polygon_through_a_valence_3_host_vertex_is_interpolated() {
    // A fan of 3 sectors: in along spoke 0, out along spoke 1; one side of the centre has no
    // host edge (one sector face), the other one (spoke 2).
    let (host, spoke) = fan(3, 5);
    let mut ids: Vec<u32> = (1..=4).rev().map(|i| spoke(0, i)).collect();
    ids.extend((1..=4).map(|i| spoke(1, i)));
    ids.insert(4, spoke(0, 0));
    let curve = open_curve((0..13).map(|i| i as f64).collect(), points_of(&host, &ids));
    let out = embed(&host, std::slice::from_ref(&curve)).unwrap();
    assert_interpolates(&[curve], &out, 8, 100);
}

#[test]
fn turn_inside_one_host_face_with_unequal_intervals_is_refused() {
    let host = grid(10, 6);
    let knots = non_uniform_knots(7);
    let curve = open_curve(knots, turning_polygon(&host));
    let err = embed(&host, &[curve]).unwrap_err();
    assert!(
        matches!(err, InterpolateError::Host { index: 4, .. }),
        "{err}"
    );
    assert!(
        err.to_string().contains("turns inside one host face"),
        "{err}"
    );
}

#[test]
fn crease_at_a_control_point_is_refused() {
    let mut host = grid(10, 6);
    let ids: Vec<u32> = (2..=7).map(|i| (i * 7 + 3) as u32).collect();
    host.tags.creases.push(Crease {
        v0: ids[2],
        v1: ids[2] + 1,
        sharpness: 10.0,
    });
    let curve = Curve::BSpline(BSplineCurve::clamped_uniform(3, points_of(&host, &ids)).unwrap());
    let err = embed(&host, &[curve]).unwrap_err();
    assert!(
        matches!(err, InterpolateError::Host { index: 2, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("crease"), "{err}");
}

#[test]
fn bad_width_is_refused() {
    let host = grid(10, 6);
    let ids: Vec<u32> = (2..=7).map(|i| (i * 7 + 3) as u32).collect();
    let curve = Curve::BSpline(BSplineCurve::clamped_uniform(3, points_of(&host, &ids)).unwrap());
    let c = CubicCurve::new(&curve, "c").unwrap();
    for w in [0.0, 1.0, f64::NAN, -0.2] {
        let err = embed_curves(&host, std::slice::from_ref(&c), &HostOptions { width: w });
        assert!(matches!(err, Err(InterpolateError::BadOption(_))), "{w}");
    }
}
