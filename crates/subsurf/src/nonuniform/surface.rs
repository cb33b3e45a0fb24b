//! [`NurssSurface`]: exact evaluation of the non-uniform (NURSS) limit surface.

use super::{Nurss, NurssError};
use crate::limit::{Derivatives, EvalError, LimitSurface, Order, Parameterization, SurfacePoint};
use crate::mesh::{Options, PolyMesh, Rule, Topology};
use crate::nurbs::{BSplineSurface, KnotVector, NurbsSurface};

/// Errors of [`NurssSurface`] evaluation.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NurssEvalError {
    /// As for a Catmull-Clark surface: no such face or sub-face, a bad parameter, a hole.
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// The face's NURSS surface has no exact evaluation (see [`NurssSurface`]).
    #[error(
        "face {face}: the non-uniform (NURSS) surface has no exact evaluation with \
         derivatives here ({reason}); it is evaluated exactly only on quads whose 4 × 4 \
         net is a regular grid with tensor-product knot intervals and on faces whose \
         1-ring has equal intervals and weights (tessellate --scheme nurss samples it \
         through refinement, without derivatives)"
    )]
    NotExact {
        /// The face.
        face: u32,
        /// Why.
        reason: &'static str,
    },
}

/// Bytes a face's patch takes at most: its rational bicubic span (16 homogeneous and 16
/// Cartesian points, two knot vectors) and its entry.
pub(crate) const PATCH_BYTES: u64 = 2 << 10;

/// What a face is, for [`NurssSurface`].
#[derive(Clone, Debug)]
enum Face {
    /// A hole: no surface.
    Hole,
    /// One rational bicubic span, on `[0, t₄] × [0, s₄]` (`t₃ = s₃ = 0`).
    Patch(Box<NurbsSurface>),
    /// The Catmull-Clark limit surface.
    CatmullClark,
    /// No exact evaluation, and why.
    NotExact(&'static str),
}

/// The exact NURSS limit surface where it has a closed form, with derivatives, and a
/// clear refusal elsewhere.
///
///
/// Non-uniform Catmull-Clark (Sederberg, Zheng, Sewell & Sabin, "Non-uniform recursive
/// subdivision surfaces", SIGGRAPH 1998) has no exact evaluator at extraordinary vertices
/// with unequal knot intervals: there its limit is known only at the vertices of refined
/// levels ([`Nurss::limit_points`]), without derivatives. Two kinds of faces do have one:
///
/// - **Regular tensor-product faces.** Where one NURSS step is midpoint knot insertion into
///   a tensor-product cubic B-spline (Sederberg et al. 1998, §3; the `refine::nurss`
///   rules, which read the intervals of the edges at the vertices they refine), the limit is
///   that B-spline. A quad qualifies when the 16 vertices of its 4 × 4 net are interior
///   vertices of four quads each, with no sharp edge or vertex, and the knot intervals are
///   those of a tensor product there: along each of the net's four rows (and columns) the
///   five intervals read, the three of the net's edges and the two of the edges that
///   continue the row beyond its ends, are the same, and no face side carries an interval
///   of its own ([`crate::mesh::KnotTags`] side intervals). With the control polygon edge
///   `P_i P_{i+1}` carrying the knot span `[t_{i+2}, t_{i+3}]` (the convention of
///   [`ControlMesh`](crate::nurbs::ControlMesh)), the face is the span `[t₃, t₄]` of the cubic B-spline whose
///   control points are the net's four points and whose knots are `t₁ … t₆` from those five
///   intervals (padded at both ends). Rational weights make it the NURBS surface of the
///   homogeneous points `(w x, w y, w z, w)`, evaluated with derivatives by the quotient rule
///   ([`NurbsSurface::eval_derivs`]). The face's `(u, v)` is linear in the knots, as
///   refinement splits each span at its middle: `t = t₃ + u (t₄ − t₃)`, so `∂/∂u =
///   (t₄ − t₃) ∂/∂t`.
/// - **Faces with equal intervals and weights around them.** The rules are homogeneous of
///   degree 0 in the intervals, and with all intervals equal they are Catmull-Clark's
///   (boundaries, infinitely sharp creases and corners included, see
///   `refine::nurss`). The surface over a face depends on the points of its 1-ring
///   and on the intervals the rules read when refining it, those of the edges at the
///   vertices of the 1-ring; a refinement keeps them equal. So where those are all equal
///   (and the 1-ring's weights too, which then cancel) the surface is the Catmull-Clark limit
///   surface ([`LimitSurface`]), exact anywhere, extraordinary vertices and `n`-gons
///   included.
///
/// Any other face (an extraordinary vertex, a crease or a boundary near unequal intervals, a
/// face whose own span is a zero interval) is [`NurssEvalError::NotExact`], naming the face
/// and the reason: sample it through refinement instead ([`tessellate`](super::tessellate())).
///
/// ```
/// use subsurf::limit::SurfacePoint;
/// use subsurf::mesh::{EdgeInterval, Options, PolyMesh};
/// use subsurf::nonuniform::NurssSurface;
/// // A 7 × 7 torus of quads whose ring of edges 2–3 has interval 3.
/// let (n, m) = (7u32, 7u32);
/// let mut p = Vec::new();
/// for j in 0..m {
///     for i in 0..n {
///         let (a, b) = (6.283 * i as f64 / n as f64, 6.283 * j as f64 / m as f64);
///         p.push([(2.0 + b.cos()) * a.cos(), (2.0 + b.cos()) * a.sin(), b.sin()]);
///     }
/// }
/// let id = |i: u32, j: u32| (j % m) * n + i % n;
/// let faces: Vec<[u32; 4]> = (0..m)
///     .flat_map(|j| (0..n).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]))
///     .collect();
/// let mut torus = PolyMesh::from_faces(p, &faces)?;
/// for j in 0..m {
///     torus.knots.intervals.push(EdgeInterval { v0: id(2, j), v1: id(3, j), interval: 3.0 });
/// }
/// let s = NurssSurface::new(&torus, &Options::default())?;
/// let d = s.eval_point(SurfacePoint { face: 2, subface: 0, u: 0.5, v: 0.5 })?;
/// assert!(d.normal().iter().all(|x| x.is_finite()));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct NurssSurface {
    faces: Vec<Face>,
    /// Face sizes (for sub-face checks).
    sizes: Vec<u32>,
    /// The Catmull-Clark surface of the mesh, when some face takes it.
    cc: Option<LimitSurface>,
}

impl NurssSurface {
    /// The surface of `mesh` with its knot tags ([`PolyMesh::knots`]) and `options`.
    ///
    /// # Errors
    /// The errors of [`Nurss::new`] (bad knot tags, semi-sharp creases, invalid meshes).
    pub fn new(mesh: &PolyMesh, options: &Options) -> Result<Self, NurssError> {
        Self::build(mesh, options, |m| Ok(LimitSurface::new(m, *options)?))
    }

    /// [`new`](Self::new) with the Catmull-Clark surface of the mesh (needed when a face
    /// takes it) made by `limit_surface`, e.g. within a memory limit
    /// ([`LimitSurface::builder`]).
    ///
    /// # Errors
    /// As [`new`](Self::new), and those of `limit_surface`.
    pub fn build<E: From<NurssError>>(
        mesh: &PolyMesh,
        options: &Options,
        limit_surface: impl FnOnce(&PolyMesh) -> Result<LimitSurface, E>,
    ) -> Result<Self, E> {
        let nurss = Nurss::vertices_only(mesh, options)?;
        Self::from_level(&nurss, mesh, limit_surface)
    }

    /// The surface of `nurss`, a base level, whose mesh is `mesh` (its points the level's
    /// projected, for the Catmull-Clark surface made by `limit_surface` when a face takes
    /// it): [`build`](Self::build) for a level made otherwise (a face-varying channel's
    /// value mesh).
    pub(crate) fn from_level<E>(
        nurss: &Nurss,
        mesh: &PolyMesh,
        limit_surface: impl FnOnce(&PolyMesh) -> Result<LimitSurface, E>,
    ) -> Result<Self, E> {
        let t = nurss.topology();
        let faces: Vec<Face> = (0..t.num_faces()).map(|f| classify(nurss, f)).collect();
        let cc = if faces.iter().any(|f| matches!(f, Face::CatmullClark)) {
            Some(limit_surface(mesh)?)
        } else {
            None
        };
        Ok(Self {
            faces,
            sizes: mesh.faces().map(|f| f.len() as u32).collect(),
            cc,
        })
    }

    /// Bytes of the patches of `mesh`'s surface, at most: `PATCH_BYTES` per face (the
    /// Catmull-Clark surface that faces with equal intervals around them take is
    /// [`LimitSurface`]'s to estimate: [`LimitSurface::estimate_build_memory`]).
    pub fn estimate_patch_memory(mesh: &PolyMesh) -> u64 {
        (mesh.num_faces() as u64).saturating_mul(PATCH_BYTES)
    }

    /// Whether face `f` has an exact evaluation: `Ok` for a face with a surface,
    /// [`NurssEvalError::NotExact`] (naming the reason) or an [`EvalError`] for a face
    /// without one or with none at all.
    ///
    /// # Errors
    /// As described.
    pub fn check_face(&self, f: usize) -> Result<(), NurssEvalError> {
        let face = f as u32;
        match self.faces.get(f) {
            None => Err(EvalError::NoSuchFace {
                face,
                count: self.faces.len(),
            }
            .into()),
            Some(Face::Hole) => Err(EvalError::Hole { face }.into()),
            Some(Face::NotExact(reason)) => Err(NurssEvalError::NotExact { face, reason }),
            Some(_) => Ok(()),
        }
    }

    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.faces.len()
    }

    /// Number of sub-faces of face `f` (1 for a quad, `n` for an `n`-gon, 0 if there is no
    /// such face), as [`LimitSurface::num_subfaces`].
    pub fn num_subfaces(&self, f: usize) -> usize {
        self.sizes
            .get(f)
            .map_or(0, |&n| Parameterization::new(n as usize).num_subfaces())
    }

    /// Whether face `f` exists and is not a hole.
    pub fn has_surface(&self, f: usize) -> bool {
        match self.faces.get(f) {
            None | Some(Face::Hole) => false,
            Some(Face::CatmullClark) => self.cc.as_ref().is_some_and(|s| s.has_surface(f)),
            Some(_) => true,
        }
    }

    /// The Catmull-Clark surface the faces with equal intervals and weights around them
    /// take, if any does.
    pub fn limit_surface(&self) -> Option<&LimitSurface> {
        self.cc.as_ref()
    }

    /// Position and first and second derivatives at `p`, with respect to the face's (or
    /// sub-face's) `(u, v)` as in [`LimitSurface`].
    ///
    /// # Errors
    /// [`NurssEvalError::NotExact`] on a face without a closed form (module docs);
    /// [`EvalError`]s as [`LimitSurface::eval_point`].
    pub fn eval_point(&self, p: SurfacePoint) -> Result<Derivatives, NurssEvalError> {
        self.eval_point_order(p, Order::Second)
    }

    /// [`eval_point`](Self::eval_point) computing the derivatives of `order` only.
    ///
    /// # Errors
    /// As [`eval_point`](Self::eval_point).
    pub fn eval_point_order(
        &self,
        p: SurfacePoint,
        order: Order,
    ) -> Result<Derivatives, NurssEvalError> {
        let f = p.face as usize;
        let face = self.faces.get(f).ok_or(EvalError::NoSuchFace {
            face: p.face,
            count: self.faces.len(),
        })?;
        let subs = self.num_subfaces(f);
        if p.subface as usize >= subs {
            return Err(EvalError::NoSuchSubface {
                face: p.face,
                subface: p.subface,
                size: subs,
            }
            .into());
        }
        if !(0.0..=1.0).contains(&p.u) || !(0.0..=1.0).contains(&p.v) {
            return Err(EvalError::BadParameter { u: p.u, v: p.v }.into());
        }
        match face {
            Face::Hole => Err(EvalError::Hole { face: p.face }.into()),
            Face::NotExact(reason) => Err(NurssEvalError::NotExact {
                face: p.face,
                reason,
            }),
            Face::CatmullClark => match &self.cc {
                Some(cc) => Ok(cc.eval_point_order(p, order)?),
                None => unreachable!("a surface with Catmull-Clark faces keeps their surface"),
            },
            Face::Patch(s) => Ok(eval_patch(s, p.u, p.v, order)),
        }
    }
}

/// The patch `s` (one span `[0, t₄] × [0, s₄]`) at the face's `(u, v)`.
fn eval_patch(s: &NurbsSurface, u: f64, v: f64, order: Order) -> Derivatives {
    let ((_, du), (_, dv)) = s.domain();
    let k = if order == Order::Second { 2 } else { 1 };
    // The parameters are inside the domain (checked), so evaluation succeeds.
    let Ok(d) = s.eval_derivs(u * du, v * dv, k) else {
        unreachable!("a parameter in [0, 1]² is inside the patch's domain")
    };
    let scale = |x: [f64; 3], a: f64| x.map(|c| c * a);
    let mut out = Derivatives {
        p: d[0][0],
        du: scale(d[1][0], du),
        dv: scale(d[0][1], dv),
        ..Derivatives::default()
    };
    if k == 2 {
        out.duu = scale(d[2][0], du * du);
        out.duv = scale(d[1][1], du * dv);
        out.dvv = scale(d[0][2], dv * dv);
    }
    out
}

/// What face `f` of `nurss`'s level is.
fn classify(nurss: &Nurss, f: usize) -> Face {
    let t = nurss.topology();
    if t.is_hole(f) {
        return Face::Hole;
    }
    let patch = match tensor_patch(nurss, f) {
        Ok(p) => return Face::Patch(Box::new(p)),
        Err(reason) => reason,
    };
    if uniform_around(nurss, f) {
        Face::CatmullClark
    } else {
        Face::NotExact(patch)
    }
}

/// Whether vertex `v` is an interior vertex of four quads with no sharp edge or vertex
/// (nor a hole around it).
fn is_regular(t: &Topology, v: usize) -> bool {
    let tag = t.vertex_tag(v);
    let faces = t.vertex_faces(v);
    tag.rule == Rule::Smooth
        && !tag.boundary
        && !tag.non_manifold
        && !tag.inf_sharp_edges
        && !tag.semi_sharp_edges
        && faces.len() == 4
        && t.vertex_edges(v).len() == 4
        && faces.iter().all(|&g| {
            let g = g as usize;
            t.face_vertices(g).len() == 4 && !t.is_hole(g)
        })
}

/// The rational bicubic span of quad `f`, if its 4 × 4 net is a regular grid with
/// tensor-product intervals (module docs); else why not.
fn tensor_patch(nurss: &Nurss, f: usize) -> Result<NurbsSurface, &'static str> {
    let t = nurss.topology();
    if t.face_vertices(f).len() != 4 {
        return Err("the face is not a quad, and its 1-ring has unequal knot intervals");
    }
    let cells = crate::refine::patch::regular_patch_cells(t, f)
        .ok_or("a corner of the face is extraordinary, or on a boundary or crease")?;
    let mut net = [0u32; 16];
    for (slot, c) in net.iter_mut().zip(cells.as_flattened()) {
        if c.len != 1 {
            return Err("the face is next to a boundary or an infinitely sharp crease");
        }
        *slot = c.verts[0];
    }
    if !net.iter().all(|&v| is_regular(t, v as usize)) {
        return Err("a vertex of the face's 4 × 4 net is extraordinary, sharp or on a boundary");
    }
    if side_intervals_differ(nurss, &net) {
        return Err("a face side near it carries a side interval of its own");
    }
    // `net[4 i + j]` with `i` along `u`: rows along `u` are fixed `j`.
    let along_u = |j: usize| [0, 1, 2, 3].map(|i| net[4 * i + j]);
    let along_v = |i: usize| [0, 1, 2, 3].map(|j| net[4 * i + j]);
    let du = tensor_intervals(nurss, (0..4).map(along_u))?;
    let dv = tensor_intervals(nurss, (0..4).map(along_v))?;
    if du[2] <= 0.0 || dv[2] <= 0.0 {
        return Err("the face spans a zero knot interval");
    }
    let (ku, kv) = (span_knots(&du)?, span_knots(&dv)?);
    let h = nurss.homogeneous();
    let points = net.iter().map(|&v| h[v as usize]).collect();
    let bad = |_| "the face's knots do not make a B-spline span";
    let s = BSplineSurface::new(ku, kv, points).map_err(bad)?;
    NurbsSurface::from_homogeneous(s).map_err(bad)
}

/// Whether any side of a face around the net's vertices carries an interval other than
/// its edge's ([`crate::mesh::SideInterval`]).
fn side_intervals_differ(nurss: &Nurss, net: &[u32; 16]) -> bool {
    let t = nurss.topology();
    let k = nurss.knots();
    if k.sides.is_none() {
        return false;
    }
    net.iter().any(|&v| {
        t.vertex_faces(v as usize).iter().any(|&g| {
            let g = g as usize;
            let edges = t.face_edge_list(g);
            (0..edges.len()).any(|j| k.side(t, g, j) != k.intervals[edges[j] as usize])
        })
    })
}

/// The five intervals read along each of four parallel rows of a net (module docs): the
/// edge before the row's first point, its three edges, the edge after its last point; the
/// same for every row, or an error.
fn tensor_intervals(
    nurss: &Nurss,
    rows: impl Iterator<Item = [u32; 4]>,
) -> Result<[f64; 5], &'static str> {
    let t = nurss.topology();
    let interval = |e: u32| nurss.knots().own(t, e as usize);
    let edge = |a: u32, b: u32| t.find_edge(a, b).ok_or("the net's rows are not edges");
    // The edge at regular vertex `v` opposite its edge to `w`.
    let beyond = |v: u32, w: u32| -> Result<u32, &'static str> {
        let e = edge(v, w)?;
        let edges = t.vertex_edges(v as usize);
        let k = edges
            .iter()
            .position(|&x| x == e)
            .ok_or("broken adjacency")?;
        Ok(edges[(k + 2) % 4])
    };
    let mut first: Option<[f64; 5]> = None;
    for r in rows {
        let d = [
            interval(beyond(r[0], r[1])?),
            interval(edge(r[0], r[1])?),
            interval(edge(r[1], r[2])?),
            interval(edge(r[2], r[3])?),
            interval(beyond(r[3], r[2])?),
        ];
        match first {
            None => first = Some(d),
            Some(f) if f.iter().zip(&d).all(|(a, b)| same(*a, *b)) => {}
            Some(_) => {
                return Err("the knot intervals around the face are not a tensor product");
            }
        }
    }
    first.ok_or("empty net")
}

/// Equal to `1e-12` relative (intervals read from decimal tags are equal exactly).
fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs())
}

/// The knot vector of the span `[0, d₂]` from the five intervals `d` (`[t₁, t₂]` … `[t₅,
/// t₆]`), padded by one knot at each end (which the span does not read).
fn span_knots(d: &[f64; 5]) -> Result<KnotVector, &'static str> {
    let t2 = -d[1];
    let t1 = t2 - d[0];
    let t4 = d[2];
    let t5 = t4 + d[3];
    let t6 = t5 + d[4];
    let knots = vec![t1 - d[0], t1, t2, 0.0, t4, t5, t6, t6 + d[4]];
    KnotVector::new(3, knots).map_err(|_| "the face's knots do not make a B-spline span")
}

/// Whether every edge at a vertex of face `f`'s 1-ring has the same interval, no face side
/// there carries one of its own, and the 1-ring's weights are equal (module docs).
fn uniform_around(nurss: &Nurss, f: usize) -> bool {
    let t = nurss.topology();
    let k = nurss.knots();
    let h = nurss.homogeneous();
    let mut ring: Vec<u32> = Vec::new();
    for &c in t.face_vertices(f) {
        for &g in t.vertex_faces(c as usize) {
            ring.extend_from_slice(t.face_vertices(g as usize));
        }
    }
    ring.sort_unstable();
    ring.dedup();
    let w0 = h[ring[0] as usize][3];
    let d0 = t
        .vertex_edges(ring[0] as usize)
        .first()
        .map(|&e| k.own(t, e as usize));
    ring.iter().all(|&v| {
        let v = v as usize;
        h[v][3] == w0
            && t.vertex_edges(v)
                .iter()
                .all(|&e| Some(k.own(t, e as usize)) == d0)
            && (k.sides.is_none()
                || t.vertex_faces(v).iter().all(|&g| {
                    let g = g as usize;
                    let edges = t.face_edge_list(g);
                    (0..edges.len()).all(|j| k.side(t, g, j) == k.intervals[edges[j] as usize])
                }))
    })
}

/// The NURSS surface in the vocabulary of every surface; a face without an exact evaluation
/// is [`EvalError::NotExact`] (sample it through refinement: [`super::tessellate()`]).
impl crate::limit::Surface for NurssSurface {
    fn num_faces(&self) -> usize {
        NurssSurface::num_faces(self)
    }

    fn num_subfaces(&self, f: usize) -> usize {
        NurssSurface::num_subfaces(self, f)
    }

    fn has_surface(&self, f: usize) -> bool {
        NurssSurface::has_surface(self, f)
    }

    fn evaluate(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        self.eval_point(p).map_err(|e| match e {
            NurssEvalError::Eval(e) => e,
            NurssEvalError::NotExact { face, reason } => EvalError::NotExact { face, reason },
        })
    }
}
