//! Embedding the zones in a user-given host mesh whose edges contain the curves' control
//! polygons ([JOS 2003], §3 "embedded in a polygonal mesh", Fig. 11).

use super::grid::{lower_corner, Grid};
use super::{CubicCurve, InterpolateError, Interpolation, MiddlePolygon, Zone};
use crate::geom::{dot, norm, sub, V3};
use crate::mesh::{EdgeInterval, KnotTags, PolyMesh, SideInterval, VertexWeight};
use std::collections::HashMap;

/// Control points match host vertices within this fraction of the host's bounding-box
/// diagonal.
pub(crate) const HOST_TOLERANCE: f64 = 1e-6;

/// Default [`HostOptions::width`].
pub const DEFAULT_HOST_WIDTH: f64 = 1.0 / 3.0;

/// How zones are embedded in a host mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct HostOptions {
    /// Distance of the inserted side rows from the polygon, as a fraction of the shortest host
    /// edge leaving each control point; in `(0, 1)`. Default [`DEFAULT_HOST_WIDTH`].
    pub width: f64,
}

impl Default for HostOptions {
    fn default() -> Self {
        Self {
            width: DEFAULT_HOST_WIDTH,
        }
    }
}

/// One side of a polygon vertex: host faces `W_0 … W_k` from the row edge towards the next
/// point to the one towards the previous point, and the host edges `X_1 … X_k` between them.
#[derive(Clone, Debug, Default)]
struct SideWalk {
    faces: Vec<u32>,
    outward: Vec<u32>,
}

/// A curve's polygon in the host.
struct HostPath {
    /// Host vertices: phantom `Q`, control points, phantom `Q'` (open), or control points
    /// (closed).
    verts: Vec<u32>,
    closed: bool,
    /// For every split vertex (all but the phantoms): `(top, bottom)` walks.
    walks: Vec<Option<(SideWalk, SideWalk)>>,
}

/// Embeds the zones of `curves` in `host`.
///
/// # What the host must be
/// Every control point of a curve is a host vertex (matched by position within
/// `HOST_TOLERANCE` × the host's bounding-box diagonal; the vertex is then moved exactly
/// onto the control point), consecutive control points are joined by host edges, and the host
/// is an oriented manifold around the polygon with at least one host edge on each side of the
/// polygon at every control point. An open curve's ends must be interior host vertices of
/// valence ≥ 4. Curves must not share host faces (no crossings inside a host).
///
/// # How the zone is embedded: rows inserted along the polygon
/// The host is cut open along the polygon and a symmetric zonal mesh is inserted: each
/// control point `P_j` stays (the middle polygon), and two new vertices `T_j = P_j + h u_j`,
/// `B_j = P_j − h u_j` take over its host connections on either side; the quads
/// `P_j P_{j+1} T_{j+1} T_j` and `P_j B_j B_{j+1} P_{j+1}` fill the cut. With valence-4
/// polygon vertices this is exactly splitting every host face along the polygon in two.
/// The alternative — making the host faces on both sides the zone — needs the host's
/// neighbours of the polygon to be symmetric about it (`T_j + B_j = 2 P_j`, Lemma 1), and has
/// no single column edge at a polygon vertex of valence ≠ 4; inserting rows meets Lemma 1's
/// symmetry by construction, keeps every host vertex where it was and every host face (with
/// its index, so hole tags stay valid), and makes every middle-polygon vertex regular. The
/// host's extraordinary polygon vertices become extraordinary *side* vertices `T_j` (or
/// `B_j`) — Fig. 11's `P_2`, the valence-5 end of the column edge `P_0 P_2` (numbered as in
/// Fig. 9, where `P_0` is on the middle polygon and `P_2`, `P_4` are the column ends).
///
/// `u_j` is the direction from the mean of the host neighbours on the `B` side to the mean
/// of those on the `T` side, made perpendicular to the polygon's tangent `P_{j+1} − P_{j−1}`;
/// `h` is [`HostOptions::width`] times the shortest host edge leaving `P_j`.
///
/// # Open ends: a phantom host edge
/// An open curve's middle polygon gets a phantom point at each end (as in `super::curve`):
/// here the host vertex `Q` across `P_0` from `P_1` (the host edge half-way round `P_0`; for
/// valence 4 the one continuing straight on), with the interval `d_1`. The cut runs on to `Q`,
/// which is not split: the zone's faces on `Q P_0` are the triangles `Q P_0 T_0`, `Q B_0 P_0`.
/// `Q`'s position does not matter (the curve on its domain depends on `P_0 … P_{n−1}` and
/// `t_1 … t_{n+2}` alone), only the interval `d_1` that `P_0`'s rules read across it.
///
/// # Intervals: Theorem 1 on the first step (Fig. 11)
/// Polygon edges and the row edges `T_j T_{j+1}`, `B_j B_{j+1}` carry the curve's intervals
/// `d_j`, column edges one interval `e`. The first step's rules for the new middle points
/// and the new side row read, beyond the zone, only `d±` at the side vertices `T_j`, `B_j`
/// (midpoints and face points of zone faces). Walk round `T_j` from the host face on the row
/// edge towards `T_{j+1}` (`W_0`) across its host edges `X_1 … X_k` to the face on the row edge
/// towards `T_{j−1}` (`W_k`). Derived from the face-point and midpoint weights (and checked in
/// `tests/integration/interpolate_host.rs`), the new middle points are the curve's and the new zone
/// is symmetric when
/// - `d±` of the column edge at `T_j` is the same `2 ê` at every side vertex: the side of
///   `X_1` in `W_0` and of `X_k` in `W_k` are `ê` (the second edge met rotating from the column
///   edge, Theorem 1's condition);
/// - `d±` of the row edge towards `T_{j+1}` is `2 d_{j−1}` (as at a regular vertex, where the
///   row continues straight on) and towards `T_{j−1}` is `2 d_j`: the zone supplies one half;
///   the other half is read two edges away from the row edge on the host side — for `k = 1`
///   the other row edge on its host face (it carries `d`), for `k ≥ 2` the side of `X_2` in
///   `W_1` must be `d_{j−1}` and the side of `X_{k−1}` in `W_{k−1}` must be `d_j`.
///
/// For `k = 1` (a valence-4 polygon vertex) the first condition is the outward edge's interval
/// `ê`; for `k ≥ 2` (valence ≥ 5, Fig. 11) the four sides are auxiliary intervals
/// (`t sideinterval`), used on the first step only. After it, every vertex of the new zone's
/// side row has valence 4 and reads only the zone and its halved intervals, so Lemma 1 holds at
/// every later step (`k = 0`, the polygon turning inside one host face, would need the row
/// edge's zone side to read `e` and `d` at once: refused).
///
/// The seed states these conditions for Fig. 11 in a formula that is damaged in our copy
/// (only the names `d^{0±}_{25}`, `d^{0±}_{26}`, `d^{0±}_{20}`, `d^{0±}_{40}`, `d^{0±}_{2,10}`,
/// `d_{29}` survive: the sides of the row, column and outward edges at the valence-5 column end
/// `P_2`); the list above is derived from the rules of `crate::scheme::nurss` and
/// `refine::nurss` (which side a rotation reads) and verified numerically: with the
/// side intervals dropped, a curve through a valence-5 host vertex is missed by 4e-4 of its
/// size on the first levels, with them the refined polygon is the knot-inserted one to 1e-13.
///
/// Scale: a cubic B-spline does not change when all its knots are scaled, so the curve's
/// intervals are scaled by [`Zone::knot_scale`] to the mean `ê` of the host's intervals on the
/// edges leaving the polygon (1 for an untagged host), and `e = ê · w / (1 − w)` (`w` the row
/// width fraction: the same parameter speed in the inserted row as in the rest of the host
/// face it was cut from).
///
/// # Errors
/// [`InterpolateError::NoCurves`], [`InterpolateError::BadOption`] for a width outside
/// `(0, 1)`, [`InterpolateError::HostVertex`] for a control point that is not a host vertex,
/// [`InterpolateError::Host`] (naming the curve and control point) when the host does not
/// have the shape the embedding needs, [`InterpolateError::HostMesh`] for host-wide problems.
pub fn embed_curves(
    host: &PolyMesh,
    curves: &[CubicCurve],
    opts: &HostOptions,
) -> Result<Interpolation, InterpolateError> {
    if curves.is_empty() {
        return Err(InterpolateError::NoCurves);
    }
    let w = opts.width;
    if !(w.is_finite() && w > 0.0 && w < 1.0) {
        return Err(InterpolateError::BadOption(format!(
            "the host row width must be a fraction in (0, 1) of the host's edges, got {w}"
        )));
    }
    if !host.knots.side_intervals.is_empty() {
        return Err(InterpolateError::HostMesh(
            "the host already has auxiliary (side) intervals; the embedding sets its own".into(),
        ));
    }
    let index = HostIndex::new(host)?;
    // 1. Paths and side walks of every curve, on the unchanged host.
    let paths = host_paths(host, &index, curves)?;
    check_smooth_at_polygons(host, curves, &paths)?;
    check_shared_faces(curves, &paths)?;
    // 2. Host intervals on the edges leaving the polygons: their mean is ê.
    let e_hat = mean_outward_interval(&paths, &index.intervals);
    let speed_column = e_hat * w / (1.0 - w);
    // 3. Cut and insert.
    let mut cut = Cut::new(host, index.faces, &index.intervals, &paths, w, e_hat);
    let mut zones = Vec::with_capacity(curves.len());
    for (curve, path) in curves.iter().zip(&paths) {
        zones.push(cut.insert_zone(curve, path, speed_column)?);
    }
    cut.into_interpolation(host, zones)
}

/// The unchanged host, indexed for the embedding: its faces, the face running along each
/// directed edge, its knot intervals by edge and its vertices in a hash grid.
struct HostIndex {
    /// Matching tolerance for control points ([`HOST_TOLERANCE`] × the bounding-box diagonal).
    tol: f64,
    faces: Vec<Vec<u32>>,
    /// The face running along each directed edge `(a, b)`.
    directed: HashMap<(u32, u32), u32>,
    /// The host's knot interval tags, by undirected edge.
    intervals: HashMap<(u32, u32), f64>,
    /// Host vertices in a hash grid of cells `2 tol` wide.
    grid: Grid,
}

impl HostIndex {
    /// Indexes `host`; fails when two faces run along one edge the same way (the host is not
    /// an oriented manifold).
    fn new(host: &PolyMesh) -> Result<Self, InterpolateError> {
        let size = super::zone::curve_size(host.positions());
        let tol = HOST_TOLERANCE * size;
        let faces: Vec<Vec<u32>> = host.faces().map(<[u32]>::to_vec).collect();
        let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
        for (f, fv) in faces.iter().enumerate() {
            let n = fv.len();
            for i in 0..n {
                let (a, b) = (fv[i], fv[(i + 1) % n]);
                if directed.insert((a, b), f as u32).is_some() {
                    return Err(InterpolateError::HostMesh(format!(
                        "the host is not an oriented manifold at its edge from vertex {} to {} (two faces run along it the same way)",
                        a + 1,
                        b + 1
                    )));
                }
            }
        }
        let mut intervals: HashMap<(u32, u32), f64> = HashMap::new();
        for t in &host.knots.intervals {
            intervals.insert(key(t.v0, t.v1), t.interval);
        }
        // Host vertices in a hash grid of cells 2 tol wide: a control point's match is in the
        // cells around it (linear time in the control points, not their product with the host's
        // vertices).
        let mut grid = Grid::new(
            (2.0 * tol).max(f64::MIN_POSITIVE),
            lower_corner(host.positions().iter()),
        );
        for (v, p) in host.positions().iter().enumerate() {
            grid.insert_point(p, v as u32);
        }
        Ok(Self {
            tol,
            faces,
            directed,
            intervals,
            grid,
        })
    }
}

/// The host paths of all `curves` ([`host_path`]), refusing a host vertex on two curves'
/// polygons.
fn host_paths(
    host: &PolyMesh,
    index: &HostIndex,
    curves: &[CubicCurve],
) -> Result<Vec<HostPath>, InterpolateError> {
    let mut used_vertex: HashMap<u32, usize> = HashMap::new();
    let mut paths = Vec::with_capacity(curves.len());
    for (c, curve) in curves.iter().enumerate() {
        let path = host_path(host, index, curve)?;
        for &v in &path.verts {
            if let Some(&other) = used_vertex.get(&v) {
                if other != c {
                    return Err(host_error(
                        curve,
                        path.verts.iter().position(|&x| x == v).unwrap_or(0),
                        &path,
                        format!(
                            "host vertex {} is on the polygon of {} too; curves must not cross or touch inside a host",
                            v + 1,
                            curves[other].label
                        ),
                    ));
                }
            }
            used_vertex.insert(v, c);
        }
        paths.push(path);
    }
    Ok(paths)
}

/// Refuses a crease or corner tag at a split control point: sharpness there would override
/// the smooth rules Theorem 1 of [JOS 2003] needs.
fn check_smooth_at_polygons(
    host: &PolyMesh,
    curves: &[CubicCurve],
    paths: &[HostPath],
) -> Result<(), InterpolateError> {
    for (c, path) in paths.iter().enumerate() {
        for (j, &v) in path.verts.iter().enumerate() {
            if path.walks[j].is_none() {
                continue;
            }
            let crease = host
                .tags
                .creases
                .iter()
                .any(|t| t.sharpness > 0.0 && (t.v0 == v || t.v1 == v));
            let corner = host
                .tags
                .corners
                .iter()
                .any(|t| t.sharpness > 0.0 && t.vertex == v);
            if crease || corner {
                return Err(host_error(
                    &curves[c],
                    j,
                    path,
                    format!(
                        "the host has a {} tag at this control point; the zone needs the smooth rules there (remove the tag)",
                        if crease { "crease" } else { "corner" }
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Refuses host faces touched by two side walks: only the face on a polygon edge, shared by
/// its two end points on the same side (and the face of a turn inside one host face, shared
/// by the turn's vertex and both its neighbours on that side), may be.
fn check_shared_faces(curves: &[CubicCurve], paths: &[HostPath]) -> Result<(), InterpolateError> {
    let mut touched: HashMap<u32, (usize, usize, bool)> = HashMap::new();
    for (c, path) in paths.iter().enumerate() {
        for (j, walks) in path.walks.iter().enumerate() {
            let Some((top, bot)) = walks else { continue };
            for (side, walk) in [(true, top), (false, bot)] {
                for &f in &walk.faces {
                    match touched.get(&f) {
                        None => {
                            touched.insert(f, (c, j, side));
                        }
                        Some(&(c2, j2, s2)) => {
                            if c2 != c || s2 != side || !walks_near(path, side, j, j2) {
                                return Err(host_error(
                                    &curves[c],
                                    j,
                                    path,
                                    format!(
                                        "host face {} touches the polygon{} at two places; refine the host so that the zones get faces of their own",
                                        f + 1,
                                        if c2 == c {
                                            String::new()
                                        } else {
                                            format!(" of {} and this one", curves[c2].label)
                                        }
                                    ),
                                ));
                            }
                        }
                    }
                }
            }
        }
    }
    Ok(())
}

/// Whether path vertices `j` and `j2` may share a host face on `side` (top when true):
/// neighbours share the face on their edge; the face of a turn inside one host face is shared
/// by the turn's vertex and both its neighbours on that side.
fn walks_near(path: &HostPath, side: bool, j: usize, j2: usize) -> bool {
    let n = path.verts.len();
    // Steps forward along the path (cyclic when closed).
    let ahead = |a: usize, b: usize| {
        if b >= a {
            Some(b - a)
        } else if path.closed {
            Some(b + n - a)
        } else {
            None
        }
    };
    let turn = |mid: usize| {
        path.walks[mid]
            .as_ref()
            .is_some_and(|(t, b)| (if side { t } else { b }).outward.is_empty())
    };
    match (ahead(j2, j), ahead(j, j2)) {
        (Some(1), _) | (_, Some(1)) => true,
        (Some(2), _) => turn((j2 + 1) % n),
        (_, Some(2)) => turn((j + 1) % n),
        _ => false,
    }
}

/// ê: the mean host interval on the host edges leaving the polygons (1 when there are none
/// or their sum is not positive).
fn mean_outward_interval(paths: &[HostPath], host_interval: &HashMap<(u32, u32), f64>) -> f64 {
    let own = |a: u32, b: u32| host_interval.get(&key(a, b)).copied().unwrap_or(1.0);
    let (mut sum, mut count) = (0.0, 0usize);
    for path in paths {
        for (j, walks) in path.walks.iter().enumerate() {
            let Some((top, bot)) = walks else { continue };
            for &x in top.outward.iter().chain(&bot.outward) {
                sum += own(path.verts[j], x);
                count += 1;
            }
        }
    }
    if count > 0 && sum > 0.0 {
        sum / count as f64
    } else {
        1.0
    }
}

/// The host being cut open along the polygons, with the zones' rows inserted: the mesh data
/// and knot tags of the result.
struct Cut<'a> {
    /// The host's knot interval tags, by undirected edge.
    host_interval: &'a HashMap<(u32, u32), f64>,
    /// Row width fraction `w` ([`HostOptions::width`]).
    width: f64,
    /// ê, the mean host interval on the edges leaving the polygons.
    e_hat: f64,
    positions: Vec<V3>,
    weights: Vec<f64>,
    faces: Vec<Vec<u32>>,
    intervals: HashMap<(u32, u32), f64>,
    sides: Vec<SideInterval>,
}

/// One curve's zone while it is inserted: its middle polygon and scaled intervals.
struct ZonePlan<'c> {
    curve: &'c CubicCurve,
    path: &'c HostPath,
    m: MiddlePolygon,
    /// The middle polygon's intervals times `scale`.
    d: Vec<f64>,
    /// [`Zone::knot_scale`].
    scale: f64,
    /// The column interval `e`.
    column: f64,
}

impl<'a> Cut<'a> {
    /// The uncut host: its positions, weights and faces, and its intervals on the edges that
    /// touch no split vertex (those at split vertices move to their side copies).
    fn new(
        host: &PolyMesh,
        faces: Vec<Vec<u32>>,
        host_interval: &'a HashMap<(u32, u32), f64>,
        paths: &[HostPath],
        width: f64,
        e_hat: f64,
    ) -> Self {
        let positions = host.positions().to_vec();
        let mut weights = vec![1.0; host.num_vertices()];
        for t in &host.knots.weights {
            if let Some(x) = weights.get_mut(t.vertex as usize) {
                *x = t.weight;
            }
        }
        let mut intervals: HashMap<(u32, u32), f64> = HashMap::new();
        // Host intervals at split vertices move to their side copies in `hand_over_side`.
        let split: HashMap<u32, ()> = paths
            .iter()
            .flat_map(|p| {
                p.verts
                    .iter()
                    .zip(&p.walks)
                    .filter(|(_, w)| w.is_some())
                    .map(|(&v, _)| (v, ()))
            })
            .collect();
        for (&(a, b), &d) in host_interval {
            if !split.contains_key(&a) && !split.contains_key(&b) {
                intervals.insert((a, b), d);
            }
        }
        Self {
            host_interval,
            width,
            e_hat,
            positions,
            weights,
            faces,
            intervals,
            sides: Vec::new(),
        }
    }

    /// Inserts the zone of `curve` along `path` ([JOS 2003] §3, Fig. 11): splits every
    /// control point into `P_j`, `T_j`, `B_j`, adds the zone's faces and sets its intervals.
    fn insert_zone(
        &mut self,
        curve: &CubicCurve,
        path: &HostPath,
        speed_column: f64,
    ) -> Result<Zone, InterpolateError> {
        let z = self.plan_zone(curve, path, speed_column)?;
        let mut top = path.verts.clone();
        let mut bot = path.verts.clone();
        for (j, walks) in path.walks.iter().enumerate() {
            let Some((tw, bw)) = walks else { continue };
            (top[j], bot[j]) = self.split_vertex(&z, j, tw, bw)?;
        }
        self.add_zone_faces(&z, &top, &bot);
        Ok(Zone {
            label: curve.label.clone(),
            middle: path.verts.clone(),
            closed: path.closed,
            start_knot: z.m.start_knot,
            first: z.m.first,
            count: curve.len(),
            knot_scale: z.scale,
        })
    }

    /// The curve's middle polygon (with phantom ends when open) and the knot scale and column
    /// interval: the curve's mean interval scaled to ê and `e = ê · w / (1 − w)`, or both ê at
    /// a turn inside one host face (see [`embed_curves`]).
    fn plan_zone<'c>(
        &self,
        curve: &'c CubicCurve,
        path: &'c HostPath,
        speed_column: f64,
    ) -> Result<ZonePlan<'c>, InterpolateError> {
        let e_hat = self.e_hat;
        let m = if path.closed {
            curve.middle_polygon()
        } else {
            curve.middle_polygon_with(true, true)
        };
        let real: Vec<f64> = (m.first..m.first + curve.len() - usize::from(!curve.closed))
            .map(|i| m.intervals[i])
            .filter(|&d| d > 0.0)
            .collect();
        let (scale, column) = match turn_interval(curve, path, &m)? {
            // A turn inside one host face: its edges' interval becomes ê, and so does the
            // column interval (see `embed_curves`).
            Some(d) => (e_hat / d, e_hat),
            None if real.is_empty() => (1.0, speed_column),
            None => (
                e_hat * real.len() as f64 / real.iter().sum::<f64>(),
                speed_column,
            ),
        };
        let d: Vec<f64> = m.intervals.iter().map(|x| x * scale).collect();
        Ok(ZonePlan {
            curve,
            path,
            m,
            d,
            scale,
            column,
        })
    }

    /// Splits path vertex `j` (with side walks `tw`, `bw`): moves it onto its control point
    /// and adds `T_j = P_j + h u_j`, `B_j = P_j − h u_j`, which take over its host faces and
    /// intervals on their sides; returns `(T_j, B_j)`.
    fn split_vertex(
        &mut self,
        z: &ZonePlan,
        j: usize,
        tw: &SideWalk,
        bw: &SideWalk,
    ) -> Result<(u32, u32), InterpolateError> {
        let (curve, path, m) = (z.curve, z.path, &z.m);
        let n = path.verts.len();
        let v = path.verts[j];
        let ci = j - m.first.min(j);
        let p = curve.points[ci.min(curve.len() - 1)];
        let wt = m.weights[j];
        self.positions[v as usize] = p;
        self.weights[v as usize] = wt;
        let prev = path.verts[(j + n - 1) % n];
        let next = path.verts[(j + 1) % n];
        let positions = &self.positions;
        let tangent = sub(&positions[next as usize], &positions[prev as usize]);
        let u = side_direction(positions, &p, &tangent, tw, bw);
        let shortest = tw
            .outward
            .iter()
            .chain(&bw.outward)
            .map(|&x| norm(&sub(&positions[x as usize], &p)))
            .fold(f64::INFINITY, f64::min);
        let ul = norm(&u);
        let apart = shortest > 0.0 && ul > 1e-9 * shortest;
        if !apart {
            return Err(host_error(
                curve,
                j,
                path,
                "the host's neighbours on the two sides of the polygon are not apart across it (a fold or a degenerate host); no side direction".into(),
            ));
        }
        let h = self.width * shortest / ul;
        let t_id = self.positions.len() as u32;
        self.positions
            .push([p[0] + h * u[0], p[1] + h * u[1], p[2] + h * u[2]]);
        self.weights.push(wt);
        let b_id = self.positions.len() as u32;
        self.positions
            .push([p[0] - h * u[0], p[1] - h * u[1], p[2] - h * u[2]]);
        self.weights.push(wt);
        // Intervals of the path edges towards the previous and the next point.
        let (dp, dn) = (z.d[(j + n - 1) % n], z.d[j]);
        for (walk, id) in [(tw, t_id), (bw, b_id)] {
            self.hand_over_side(walk, v, id, dp, dn);
        }
        self.intervals.insert(key(v, t_id), z.column);
        self.intervals.insert(key(v, b_id), z.column);
        Ok((t_id, b_id))
    }

    /// Hands the faces and host edges of `walk` round split vertex `v` over to its side copy
    /// `id`, and sets the intervals the first step reads at `id` (Theorem 1 of [JOS 2003] on
    /// the first step, Fig. 11; see [`embed_curves`]): `ê` on the outward edge for one
    /// host edge, else the four auxiliary side intervals `ê`, `ê`, `d_{j−1}` (`dp`), `d_j`
    /// (`dn`).
    fn hand_over_side(&mut self, walk: &SideWalk, v: u32, id: u32, dp: f64, dn: f64) {
        let e_hat = self.e_hat;
        for &f in &walk.faces {
            for x in self.faces[f as usize].iter_mut() {
                if *x == v {
                    *x = id;
                }
            }
        }
        let k = walk.outward.len();
        for &x in &walk.outward {
            if let Some(&dh) = self.host_interval.get(&key(v, x)) {
                self.intervals.insert(key(id, x), dh);
            }
        }
        let mut side = |f: u32, x: u32, d: f64| {
            self.sides.push(SideInterval {
                face: f,
                v0: id,
                v1: x,
                interval: d,
            })
        };
        if k == 0 {
            // A turn inside one host face: every interval the first step reads at
            // the valence-3 side vertex is ê already (see `embed_curves`).
        } else if k == 1 {
            self.intervals.insert(key(id, walk.outward[0]), e_hat);
        } else {
            side(walk.faces[0], walk.outward[0], e_hat);
            side(walk.faces[k], walk.outward[k - 1], e_hat);
            side(walk.faces[1], walk.outward[1], dp);
            side(walk.faces[k - 1], walk.outward[k - 2], dn);
        }
    }

    /// The zone's faces `P_j P_{j+1} T_{j+1} T_j` and `P_j B_j B_{j+1} P_{j+1}` (triangles at
    /// a phantom end) and the intervals `d_j` along the polygon and its two side rows.
    fn add_zone_faces(&mut self, z: &ZonePlan, top: &[u32], bot: &[u32]) {
        let path = z.path;
        let n = path.verts.len();
        let edges = if path.closed { n } else { n - 1 };
        for j in 0..edges {
            let k = (j + 1) % n;
            let (p0, p1) = (path.verts[j], path.verts[k]);
            let (t0, t1, b0, b1) = (top[j], top[k], bot[j], bot[k]);
            self.intervals.insert(key(p0, p1), z.d[j]);
            if t0 == p0 {
                // Phantom start Q = p0.
                self.faces.push(vec![p0, p1, t1]);
                self.faces.push(vec![p0, b1, p1]);
            } else if t1 == p1 {
                // Phantom end Q' = p1.
                self.faces.push(vec![p0, p1, t0]);
                self.faces.push(vec![p0, b0, p1]);
            } else {
                self.faces.push(vec![p0, p1, t1, t0]);
                self.faces.push(vec![p0, b0, b1, p1]);
            }
            self.intervals.insert(key(t0, t1), z.d[j]);
            self.intervals.insert(key(b0, b1), z.d[j]);
        }
    }

    /// The cut host as a validated mesh with the host's sharpness tags and the new knot tags
    /// (intervals other than 1, sorted by edge), with its `zones`.
    fn into_interpolation(
        self,
        host: &PolyMesh,
        zones: Vec<Zone>,
    ) -> Result<Interpolation, InterpolateError> {
        let mut mesh = PolyMesh::from_faces(self.positions, &self.faces)?;
        mesh.tags = host.tags.clone();
        let mut iv: Vec<EdgeInterval> = self
            .intervals
            .into_iter()
            .filter(|&(_, d)| d != 1.0)
            .map(|((v0, v1), interval)| EdgeInterval { v0, v1, interval })
            .collect();
        iv.sort_by_key(|t| (t.v0, t.v1));
        let weights = VertexWeight::tags(&self.weights);
        mesh.knots = KnotTags {
            intervals: iv,
            side_intervals: self.sides,
            weights,
        };
        mesh.validate()?;
        Ok(Interpolation { mesh, zones })
    }
}

/// The side direction `u_j` at control point `p`: from the mean of the host neighbours on the
/// `B` side to the mean of those on the `T` side (from or to `p` where a side has none, a turn
/// inside one host face), made perpendicular to the polygon's `tangent`.
fn side_direction(positions: &[V3], p: &V3, tangent: &V3, tw: &SideWalk, bw: &SideWalk) -> V3 {
    let mean = |xs: &[u32]| -> V3 {
        let mut s = [0.0; 3];
        for &x in xs {
            for k in 0..3 {
                s[k] += positions[x as usize][k] / xs.len() as f64;
            }
        }
        s
    };
    let mut u = match (tw.outward.is_empty(), bw.outward.is_empty()) {
        (false, false) => sub(&mean(&tw.outward), &mean(&bw.outward)),
        (false, true) => sub(&mean(&tw.outward), p),
        _ => sub(p, &mean(&bw.outward)),
    };
    let tl = norm(tangent);
    if tl > 0.0 {
        let k = dot(&u, tangent) / (tl * tl);
        u = [
            u[0] - k * tangent[0],
            u[1] - k * tangent[1],
            u[2] - k * tangent[2],
        ];
    }
    u
}

/// The knot interval of the polygon edges at the curve's turns inside one host face (a side
/// without host edges: a 90° turn at a grid vertex, a control point of valence 3), or `None`
/// when it has none. Theorem 1 holds on the first step there only when the two edges at every
/// such point have one interval (see [`embed_curves`]).
fn turn_interval(
    curve: &CubicCurve,
    path: &HostPath,
    m: &MiddlePolygon,
) -> Result<Option<f64>, InterpolateError> {
    let n = path.verts.len();
    let mut found: Option<f64> = None;
    for (j, walks) in path.walks.iter().enumerate() {
        let Some((t, b)) = walks else { continue };
        if !(t.outward.is_empty() || b.outward.is_empty()) {
            continue;
        }
        let (dp, dn) = (m.intervals[(j + n - 1) % n], m.intervals[j]);
        let same = |a: f64, b: f64| (a - b).abs() <= 1e-12 * a.abs().max(b.abs());
        let ok = dp > 0.0 && same(dp, dn) && found.is_none_or(|d| same(d, dp));
        if !ok {
            return Err(host_error(
                curve,
                j,
                path,
                format!(
                    "the polygon turns inside one host face here (a 90° turn at a grid vertex, or a control point of valence 3); the zone's side vertex there has valence 3, and Theorem 1 holds on the first step only when the two polygon edges at every such point have one non-zero knot interval (it becomes the zone's column interval): got {dp} and {dn}{}",
                    found.map_or(String::new(), |d| format!(", and {d} at another turn"))
                ),
            ));
        }
        found = Some(dp);
    }
    Ok(found)
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

fn host_error(curve: &CubicCurve, j: usize, path: &HostPath, reason: String) -> InterpolateError {
    let first = usize::from(!path.closed);
    let index = j.saturating_sub(first).min(curve.len() - 1);
    let p = curve.points[index];
    InterpolateError::Host {
        curve: curve.label.clone(),
        index,
        x: p[0],
        y: p[1],
        z: p[2],
        reason,
    }
}

/// The host vertices of the curve's polygon (phantom ends included) and the side walks.
fn host_path(
    host: &PolyMesh,
    index: &HostIndex,
    curve: &CubicCurve,
) -> Result<HostPath, InterpolateError> {
    let mut verts = match_control_points(host, index, curve)?;
    check_polygon_edges(index, curve, &verts)?;
    if !curve.closed {
        add_phantom_ends(index, curve, &mut verts)?;
    }
    let walks = side_walks(index, curve, &verts)?;
    Ok(HostPath {
        verts,
        closed: curve.closed,
        walks,
    })
}

/// The host vertex of each control point: the nearest within [`HostIndex::tol`] (the lowest
/// index among equally near ones).
fn match_control_points(
    host: &PolyMesh,
    index: &HostIndex,
    curve: &CubicCurve,
) -> Result<Vec<u32>, InterpolateError> {
    let pos = host.positions();
    let tol = index.tol;
    let mut verts = Vec::with_capacity(curve.len() + 2);
    for (i, p) in curve.points.iter().enumerate() {
        // The nearest host vertex within `tol` (the lowest index among equally near ones).
        let mut best: Option<(u32, f64)> = None;
        index.grid.near(p, |v| {
            let d = norm(&sub(p, &pos[v as usize]));
            if d <= tol && best.is_none_or(|(bv, bd)| d < bd || (d == bd && v < bv)) {
                best = Some((v, d));
            }
        });
        match best {
            Some((v, _)) => verts.push(v),
            None => {
                return Err(InterpolateError::HostVertex {
                    curve: curve.label.clone(),
                    index: i,
                    x: p[0],
                    y: p[1],
                    z: p[2],
                    tol,
                })
            }
        }
    }
    Ok(verts)
}

/// [`InterpolateError::Host`] naming control point `i` of `curve`.
fn point_error(curve: &CubicCurve, i: usize, reason: String) -> InterpolateError {
    let p = curve.points[i];
    InterpolateError::Host {
        curve: curve.label.clone(),
        index: i,
        x: p[0],
        y: p[1],
        z: p[2],
        reason,
    }
}

/// Refuses a polygon that revisits a host vertex or whose consecutive control points are not
/// joined by an interior host edge (faces on both sides).
fn check_polygon_edges(
    index: &HostIndex,
    curve: &CubicCurve,
    verts: &[u32],
) -> Result<(), InterpolateError> {
    let n = curve.len();
    let mut seen: HashMap<u32, usize> = HashMap::with_capacity(n);
    for (i, &v) in verts.iter().enumerate() {
        if let Some(&j) = seen.get(&v) {
            return Err(point_error(
                curve,
                i,
                format!("it is the same host vertex as control point {j}; the polygon must not revisit a vertex"),
            ));
        }
        seen.insert(v, i);
    }
    let edges = if curve.closed { n } else { n - 1 };
    for i in 0..edges {
        let (a, b) = (verts[i], verts[(i + 1) % n]);
        let (ab, ba) = (
            index.directed.contains_key(&(a, b)),
            index.directed.contains_key(&(b, a)),
        );
        if !ab && !ba {
            return Err(point_error(
                curve,
                i,
                format!(
                    "no host edge joins it to control point {}; the control polygon must run along host edges",
                    (i + 1) % n
                ),
            ));
        }
        if !(ab && ba) {
            return Err(point_error(
                curve,
                i,
                format!(
                    "the host edge to control point {} is on the host's boundary; the zone needs host faces on both sides",
                    (i + 1) % n
                ),
            ));
        }
    }
    Ok(())
}

/// Adds an open polygon's phantom ends: the host vertex across each end from its neighbour
/// on the polygon ([`across`]), which must be off the polygon and distinct.
fn add_phantom_ends(
    index: &HostIndex,
    curve: &CubicCurve,
    verts: &mut Vec<u32>,
) -> Result<(), InterpolateError> {
    let n = curve.len();
    let (directed, faces) = (&index.directed, &index.faces);
    let err = |i: usize, reason: String| point_error(curve, i, reason);
    let q0 = across(directed, faces, verts[0], verts[1]).map_err(|r| err(0, r))?;
    let q1 = across(directed, faces, verts[n - 1], verts[n - 2]).map_err(|r| err(n - 1, r))?;
    for (q, i) in [(q0, 0), (q1, n - 1)] {
        if let Some(j) = verts.iter().position(|&v| v == q) {
            return Err(err(
                i,
                format!("the host edge continuing the polygon beyond this end leads to control point {j}; the zone needs a host edge of its own there"),
            ));
        }
    }
    if q0 == q1 {
        return Err(err(
            0,
            "the host edges continuing both ends of the polygon meet at one vertex; use a finer host".into(),
        ));
    }
    verts.insert(0, q0);
    verts.push(q1);
    Ok(())
}

/// The `(top, bottom)` side walks ([`walk`]) of every path vertex but the phantom ends; a
/// control point needs a host edge on at least one side.
fn side_walks(
    index: &HostIndex,
    curve: &CubicCurve,
    verts: &[u32],
) -> Result<Vec<Option<(SideWalk, SideWalk)>>, InterpolateError> {
    let (directed, faces) = (&index.directed, &index.faces);
    let closed = curve.closed;
    let m = verts.len();
    let mut walks = Vec::with_capacity(m);
    for j in 0..m {
        if !closed && (j == 0 || j == m - 1) {
            walks.push(None);
            continue;
        }
        let (u, v, w) = (verts[(j + m - 1) % m], verts[j], verts[(j + 1) % m]);
        let ci = if closed { j } else { j - 1 };
        let err = |r: String| point_error(curve, ci, r);
        let top = walk(directed, faces, v, w, u, true).map_err(err)?;
        let bot = walk(directed, faces, v, w, u, false).map_err(err)?;
        if top.outward.is_empty() && bot.outward.is_empty() {
            return Err(err(
                "the control point has no host edge but the polygon's two (valence 2); the zone needs a host edge on at least one side".into(),
            ));
        }
        walks.push(Some((top, bot)));
    }
    Ok(walks)
}

/// Faces and edges around `v` from the face on edge `v → next` (`top`: the face running
/// `v → next`; else the face running `next → v`) round to the edge to `prev`.
fn walk(
    directed: &HashMap<(u32, u32), u32>,
    faces: &[Vec<u32>],
    v: u32,
    next: u32,
    prev: u32,
    top: bool,
) -> Result<SideWalk, String> {
    let boundary = || {
        "it is on the host's boundary (or the host is not manifold there); the zone needs host faces all round each control point".to_string()
    };
    let mut s = SideWalk::default();
    let mut f = *directed
        .get(&if top { (v, next) } else { (next, v) })
        .ok_or_else(boundary)?;
    for _ in 0..=faces.len().min(1 << 16) {
        s.faces.push(f);
        let fv = &faces[f as usize];
        let n = fv.len();
        let p = fv.iter().position(|&x| x == v).ok_or_else(boundary)?;
        let x = if top {
            fv[(p + n - 1) % n]
        } else {
            fv[(p + 1) % n]
        };
        if x == prev {
            return Ok(s);
        }
        if x == next {
            return Err(boundary());
        }
        s.outward.push(x);
        f = *directed
            .get(&if top { (v, x) } else { (x, v) })
            .ok_or_else(boundary)?;
    }
    Err(boundary())
}

/// The host vertex across `v` from `from`: the neighbour half-way round `v` (valence ≥ 4).
fn across(
    directed: &HashMap<(u32, u32), u32>,
    faces: &[Vec<u32>],
    v: u32,
    from: u32,
) -> Result<u32, String> {
    let end = || {
        "the curve ends here, at a vertex on the host's boundary or of valence < 4; an open curve's end needs an interior host vertex of valence ≥ 4 (the zone runs on along the host edge across it)".to_string()
    };
    let mut ring = vec![from];
    let mut f = *directed.get(&(v, from)).ok_or_else(end)?;
    loop {
        let fv = &faces[f as usize];
        let n = fv.len();
        let p = fv.iter().position(|&x| x == v).ok_or_else(end)?;
        let x = fv[(p + n - 1) % n];
        if x == from {
            break;
        }
        if ring.len() > faces.len() {
            return Err(end());
        }
        ring.push(x);
        f = *directed.get(&(v, x)).ok_or_else(end)?;
    }
    if ring.len() < 4 {
        return Err(end());
    }
    Ok(ring[ring.len() / 2])
}
