//! [`LimitSurface`]: exact evaluation of the Catmull-Clark limit surface at any
//! `(face, u, v)`, with first and second derivatives.
//!
//! # Method
//! The limit surface over a *regular* quad is one bicubic B-spline patch
//! ([`super::patch`]), evaluated in closed form. Any other face (next to an extraordinary
//! vertex, a dart, a semi-sharp feature, an n-gon, a non-manifold or irregular boundary
//! vertex) is refined locally: its 1-ring is cut out ([`super::local`]) and refined one
//! level with the full OpenSubdiv rules; each of its four children is again either regular
//! (a patch) or refined further. Irregularities stay at the corners of sub-faces, so each
//! level leaves at most one irregular child per irregular corner, and a point at distance
//! `d` from an irregular corner is reached after about `log₂(1/d)` levels. Levels are
//! refined on demand, the first time a point needs them, and kept for later points
//! (thread-safely, so batched parallel evaluation shares them). A point exactly at an
//! irregular corner (or
//! closer than `2^-MAX_DEPTH`) takes its position and normal from OpenSubdiv's limit masks
//! at that corner.
//!
//! This is exact, not an approximation: the only truncation is at `2^-MAX_DEPTH ≈ 4e-15`
//! of a face, far below `f64` resolution of typical coordinates.
//!
//! # Parametrisation
//! A quad `[v0 v1 v2 v3]` has `(0, 0)` at `v0`, `u` toward `v1`, `v` toward `v3` (as
//! OpenSubdiv's `Bfr`). An `n`-gon (`n ≠ 4`) is split into `n` quad sub-faces, the children
//! of one Catmull-Clark step: sub-face `j` has `(0, 0)` at the face's vertex `j`, `u` toward
//! the midpoint of edge `j` (toward vertex `j + 1`), `v` toward the midpoint of edge `j - 1`,
//! and `(1, 1)` at the face's centre.
//!
//! # At an irregular corner
//! The parametric derivatives of the limit surface are degenerate (zero or unbounded) at
//! an extraordinary vertex. There, [`LimitSurface::eval`] returns the exact limit
//! position, and as `du`, `dv` the limit *tangent vectors* of OpenSubdiv's tangent masks
//! oriented along the face's `u` and `v` edges: they span the exact tangent plane (their
//! cross product is the exact limit normal) but their lengths are not parametric
//! derivatives; second derivatives are zero.

use super::bspline::{self, Derivatives};
use super::local::{cut, LevelRef, Local, Region, RegionCache, HIGH_VALENCE};
use super::patch::{regular_corner, regular_patch};
use crate::geom::{self, V3};
use crate::mesh::{MeshError, Options, PolyMesh, Topology};
use crate::refine::interpolate;
use crate::scheme::catmark::{self, VertexMask};
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};

/// Deepest local refinement; a sub-face is then `2^-48` of its face.
pub const MAX_DEPTH: u32 = 48;

/// Where to evaluate: a face (and, for a non-quad, a sub-face) and a parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Base face.
    pub face: u32,
    /// Sub-face of an `n`-gon (0 for quads).
    pub subface: u32,
    /// Parameter along `u`, in `[0, 1]`.
    pub u: f64,
    /// Parameter along `v`, in `[0, 1]`.
    pub v: f64,
}

/// Errors of [`LimitSurface`] evaluation.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// The face index is out of range.
    #[error("face {face} does not exist (the mesh has {count} faces)")]
    NoSuchFace {
        /// Requested face.
        face: u32,
        /// Number of faces.
        count: usize,
    },
    /// The sub-face index is out of range for the face's size.
    #[error("face {face} has {size} sub-faces; sub-face {subface} does not exist")]
    NoSuchSubface {
        /// Face.
        face: u32,
        /// Requested sub-face.
        subface: u32,
        /// Face size (number of sub-faces; 1 for quads).
        size: usize,
    },
    /// The face is a hole (or excluded by `BoundaryInterpolation::None`): no surface.
    #[error("face {face} is a hole: it has no limit surface")]
    Hole {
        /// Face.
        face: u32,
    },
    /// A parameter outside `[0, 1]` or not finite.
    #[error("parameter ({u}, {v}) is outside [0, 1]²")]
    BadParameter {
        /// `u`.
        u: f64,
        /// `v`.
        v: f64,
    },
}

/// The limit surface of one face (or sub-face).
#[derive(Clone, Debug)]
pub(super) enum Node {
    Hole,
    Regular(Box<[[[f64; 3]; 4]; 4]>),
    /// An irregular (sub-)face: its cut-out, refined into four children the first time a
    /// point needs them.
    Lazy(Box<Lazy>),
}

/// An irregular node: the cut-out around it and, once built, its children at the corners
/// 0, 1, 2, 3 (quadrants `[0,½]×[0,½]`, `[½,1]×[0,½]`, `[½,1]²`, `[0,½]×[½,1]`).
#[derive(Clone, Debug)]
pub(super) struct Lazy {
    local: Local,
    kids: OnceLock<Box<[Node; 4]>>,
}

impl Node {
    fn lazy(local: Local) -> Node {
        Node::Lazy(Box::new(Lazy {
            local,
            kids: OnceLock::new(),
        }))
    }
}

/// The exact Catmull-Clark limit surface of a mesh, evaluable anywhere. See the module
/// docs for the method and parametrisation.
///
/// ```
/// use subsurf::limit::LimitSurface;
/// use subsurf::mesh::{Options, PolyMesh};
/// // A cube: every vertex is extraordinary (valence 3).
/// let p = vec![
///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
/// ];
/// let f = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
/// let cube = PolyMesh::from_faces(p, &f).unwrap();
/// let s = LimitSurface::new(&cube, Options::default()).unwrap();
/// // By symmetry the centre of the top face lies above the cube's centre.
/// let d = s.eval(1, 0.5, 0.5).unwrap();
/// assert!((d.p[0] - 0.5).abs() < 1e-12 && (d.p[1] - 0.5).abs() < 1e-12);
/// // Its normal points up, out of the cube.
/// assert!(d.normal()[2] > 0.999_999);
/// ```
#[derive(Clone, Debug)]
pub struct LimitSurface {
    options: Options,
    /// Per base face, its nodes (one per sub-face; one for quads).
    nodes: Vec<Vec<Node>>,
}

impl LimitSurface {
    /// Builds the surface of `mesh` with scheme `options`.
    ///
    /// # Errors
    /// [`MeshError`] if the mesh is invalid.
    pub fn new(mesh: &PolyMesh, options: Options) -> Result<Self, MeshError> {
        Self::with_high_valence(mesh, options, HIGH_VALENCE)
    }

    /// [`LimitSurface::new`] with faces sharing regions around vertices of more than
    /// `high_valence` faces (`usize::MAX`: every face on its own, as tests compare).
    fn with_high_valence(
        mesh: &PolyMesh,
        options: Options,
        high_valence: usize,
    ) -> Result<Self, MeshError> {
        mesh.validate()?;
        let (base, _) = Topology::from_mesh(mesh, &options)?;
        let pos = mesh.positions();
        let cache = RegionCache::default();
        let level = LevelRef {
            high_valence,
            ..LevelRef::new(&base, pos, &cache)
        };
        let nodes = (0..base.num_faces())
            .into_par_iter()
            .map(|f| build_face(level, f, &options))
            .collect();
        Ok(Self { options, nodes })
    }

    /// Number of base faces.
    pub fn num_faces(&self) -> usize {
        self.nodes.len()
    }

    /// Number of sub-faces of face `f` (1 for a quad, `n` for an `n`-gon).
    pub fn num_subfaces(&self, f: usize) -> usize {
        self.nodes.get(f).map_or(0, Vec::len)
    }

    /// Whether face `f` has a surface (it is not a hole).
    pub fn has_surface(&self, f: usize) -> bool {
        self.nodes
            .get(f)
            .is_some_and(|n| !matches!(n.first(), Some(Node::Hole) | None))
    }

    /// Position and first and second derivatives at `(u, v)` of quad `face` (sub-face 0
    /// of a non-quad).
    pub fn eval(&self, face: u32, u: f64, v: f64) -> Result<Derivatives, EvalError> {
        self.eval_point(SurfacePoint {
            face,
            subface: 0,
            u,
            v,
        })
    }

    /// Evaluates at a [`SurfacePoint`].
    pub fn eval_point(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        let nodes = self
            .nodes
            .get(p.face as usize)
            .ok_or(EvalError::NoSuchFace {
                face: p.face,
                count: self.nodes.len(),
            })?;
        let node = nodes
            .get(p.subface as usize)
            .ok_or(EvalError::NoSuchSubface {
                face: p.face,
                subface: p.subface,
                size: nodes.len(),
            })?;
        if !(0.0..=1.0).contains(&p.u) || !(0.0..=1.0).contains(&p.v) {
            return Err(EvalError::BadParameter { u: p.u, v: p.v });
        }
        eval_node(node, p.u, p.v, 0, &self.options).ok_or(EvalError::Hole { face: p.face })
    }

    /// Evaluates many points in parallel; results in the same order.
    pub fn eval_many(&self, points: &[SurfacePoint]) -> Vec<Result<Derivatives, EvalError>> {
        points.par_iter().map(|&p| self.eval_point(p)).collect()
    }
}

/// The nodes of face `f` of `level` (one per sub-face).
pub(super) fn build_face(level: LevelRef<'_>, f: usize, options: &Options) -> Vec<Node> {
    let base = level.topo;
    let n = base.face_vertices(f).len();
    if base.is_hole(f) {
        return vec![Node::Hole; if n == 4 { 1 } else { n }];
    }
    if n == 4 {
        return vec![node_for(level, f)];
    }
    // Sub-faces: the children of the face after one step, unrotated for n ≠ 4.
    let local = cut(level, f);
    let child = local.region.refined(options);
    let first = child_face(&local, 0);
    (0..n).map(|j| node_for(child.level(), first + j)).collect()
}

/// Index of the child of `l.face` at its corner `j`.
fn child_face(l: &Local, j: usize) -> usize {
    l.topo().face_offsets()[l.face] as usize + j
}

/// The face's child at corner `k` in the refined region.
fn child_local(l: &Local, k: usize, options: &Options) -> Local {
    Local {
        face: child_face(l, k),
        region: l.region.refined(options),
    }
}

/// The node of face `f` of a level or refined cut-out.
fn node_for(level: LevelRef<'_>, f: usize) -> Node {
    if level.topo.is_hole(f) {
        return Node::Hole;
    }
    match regular_patch(level.topo, level.pos, f) {
        Some(cp) => Node::Regular(Box::new(cp)),
        None => Node::lazy(cut(level, f)),
    }
}

/// The four children of an irregular node.
fn split(l: &Local, options: &Options) -> Box<[Node; 4]> {
    let child = l.region.refined(options);
    let first = child_face(l, 0);
    Box::new([0, 1, 2, 3].map(|j| node_for(child.level(), first + j)))
}

/// Quadrant of `(u, v)` and the parameter within it.
#[inline]
fn quadrant(u: f64, v: f64) -> (usize, f64, f64) {
    match (u >= 0.5, v >= 0.5) {
        (false, false) => (0, 2.0 * u, 2.0 * v),
        (true, false) => (1, 2.0 * u - 1.0, 2.0 * v),
        (true, true) => (2, 2.0 * u - 1.0, 2.0 * v - 1.0),
        (false, true) => (3, 2.0 * u, 2.0 * v - 1.0),
    }
}

pub(super) fn eval_node(
    node: &Node,
    u: f64,
    v: f64,
    depth: u32,
    options: &Options,
) -> Option<Derivatives> {
    let (mut node, mut u, mut v, mut depth) = (node, u, v, depth);
    loop {
        match node {
            Node::Hole => return None,
            Node::Regular(cp) => {
                return Some(bspline::eval(cp, u, v).scaled(2f64.powi(depth as i32)))
            }
            Node::Lazy(lz) => {
                let corner = match (u, v) {
                    (0.0, 0.0) => Some(0),
                    (1.0, 0.0) => Some(1),
                    (1.0, 1.0) => Some(2),
                    (0.0, 1.0) => Some(3),
                    _ if depth >= MAX_DEPTH => Some(quadrant(u, v).0),
                    _ => None,
                };
                // Limit masks give the limit only once no semi-sharp feature is left at
                // the corner (sharpness still to decay changes the rules of later levels).
                // A regular corner (one that only an irregularity elsewhere on the face keeps
                // from being a patch corner) is reached by refining further, where the
                // patch gives exact parametric derivatives.
                let irregular = |k: usize| {
                    settled(&lz.local, k)
                        && regular_corner(lz.local.topo(), lz.local.face, k).is_none()
                };
                if let Some(k) = corner.filter(|&k| depth >= MAX_DEPTH || irregular(k)) {
                    return Some(corner_limit(&lz.local, k, options));
                }
                let kids = lz.kids.get_or_init(|| split(&lz.local, options));
                let (q, s, t) = quadrant(u, v);
                node = &kids[q];
                (u, v) = (s, t);
                depth += 1;
            }
        }
    }
}

/// Whether corner `k` of the cut-out's face has no semi-sharp vertex or edge sharpness
/// left, so that its rule no longer changes under refinement.
fn settled(l: &Local, k: usize) -> bool {
    let t = l.topo();
    let c = t.face_vertices(l.face)[k] as usize;
    !t.vertex_tag(c).semi_sharp
        && t.vertex_edges(c)
            .iter()
            .all(|&e| !t.edge_tag(e as usize).semi_sharp)
}

/// Limit position and tangents at corner `k` of the cut-out's face (see the module docs).
///
/// A smooth interior vertex whose faces are quads has exact limit masks (Halstead et al.
/// 1993), used as they are. Any other vertex (crease, corner, dart, valence 2,
/// non-manifold) is analysed numerically: with `R` the control points of the vertex's
/// sector (the faces around it between infinitely sharp edges, containing the face), one
/// step maps `R` to the same configuration one level down, `R' = S R`. The limit position
/// is `l₀ · R` with `l₀` the left eigenvector of `S` for eigenvalue 1 (`l₀ · 1 = 1`); the
/// tangent plane is spanned by `L · R` for `L` the invariant subspace of the two
/// subdominant left eigenvectors, found by subspace iteration on sum-free vectors (where
/// `Sᵀ` leaves out eigenvalue 1). The tangents are returned along the face's edges
/// projected onto that plane.
fn corner_limit(l: &Local, k: usize, options: &Options) -> Derivatives {
    let t = l.topo();
    let pos = l.pos();
    let c = t.face_vertices(l.face)[k] as usize;
    let tag = t.vertex_tag(c);
    let all_quads = t
        .vertex_faces(c)
        .iter()
        .all(|&g| t.face_vertices(g as usize).len() == 4);
    let n_e = t.vertex_edges(c).len();
    let smooth = tag.rule == crate::mesh::Rule::Smooth
        && !tag.non_manifold
        && !tag.boundary
        && all_quads
        && n_e == t.vertex_faces(c).len()
        && n_e >= 3;
    if smooth {
        return smooth_corner(l, k);
    }
    if !all_quads {
        // One step makes every face a quad; the corner's child has the same limit.
        let n = t.face_vertices(l.face).len();
        let next = child_local(l, k, options);
        return corner_limit(&next, if n == 4 { k } else { 0 }, options);
    }
    let along = face_edge_dirs(l, k);
    match tag.rule {
        crate::mesh::Rule::Corner => {
            // The vertex stays put; the limit curves along the face's sides leave it toward
            // the neighbouring vertices (cubic B-spline end condition).
            let (du, dv) = uv_from_corner_frame(k, along.0, along.1);
            Derivatives {
                p: pos[c],
                du,
                dv,
                ..Derivatives::default()
            }
        }
        crate::mesh::Rule::Crease => {
            // The crease curve is the cubic B-spline of the crease polygon: its limit point is
            // ⅔ c + ⅙ (a + b) whatever lies around it. The tangent plane of the face's side
            // comes from the sector's eigen-analysis.
            let ends = crease_neighbours(t, c);
            let p = match ends {
                Some((a, b)) => {
                    let (pa, pb, pc) = (pos[a], pos[b], pos[c]);
                    [0, 1, 2].map(|i| (4.0 * pc[i] + pa[i] + pb[i]) / 6.0)
                }
                None => pos[c],
            };
            let mut d = eigen_corner_settled(l, k, options).unwrap_or_else(|| {
                let (du, dv) = uv_from_corner_frame(k, along.0, along.1);
                Derivatives {
                    du,
                    dv,
                    ..Derivatives::default()
                }
            });
            d.p = p;
            d
        }
        _ => eigen_corner_settled(l, k, options).unwrap_or_else(|| smooth_corner(l, k)),
    }
}

/// [`eigen_corner`] at corner `k`, refining up to three levels first if the corner's
/// neighbourhood only becomes self-similar further down (faces that share several
/// vertices, as around valence-2 vertices, separate after a step).
fn eigen_corner_settled(l: &Local, k: usize, options: &Options) -> Option<Derivatives> {
    let mut owned: Option<Local> = None;
    for _ in 0..4 {
        let cur = owned.as_ref().unwrap_or(l);
        if let Some(d) = eigen_corner(cur, k, options) {
            return Some(d);
        }
        owned = Some(child_local(cur, k, options));
    }
    None
}

/// The far ends of the two sharp edges of a crease vertex.
fn crease_neighbours(t: &Topology, c: usize) -> Option<(usize, usize)> {
    let sharp: Vec<f32> = t
        .vertex_edges(c)
        .iter()
        .map(|&e| t.edge_sharpness(e as usize))
        .collect();
    if sharp.iter().filter(|&&x| x > 0.0).count() != 2 {
        return None;
    }
    let (i, j) = crate::scheme::crease::crease_ends(&sharp);
    let ends: Vec<u32> = t.vertex_neighbours(c).collect();
    Some((ends[i] as usize, ends[j] as usize))
}

/// The first face and the control points of the sector of face `l.face` at its corner `k`: the corner, then
/// for each sector face (walking from one bounding edge to the other) its three other
/// vertices, without repeats. Children of these points, listed the same way one level
/// down, correspond one to one.
fn sector_ring(t: &Topology, face: usize, k: usize) -> Option<(usize, Vec<u32>)> {
    let c = t.face_vertices(face)[k];
    // Walk clockwise to the sector's first face, then counter-clockwise across it.
    let step = |g: usize, ccw: bool| -> Option<usize> {
        let gv = t.face_vertices(g);
        let m = gv.iter().position(|&x| x == c)?;
        let n = gv.len();
        let e = t.face_edge_list(g)[if ccw { (m + n - 1) % n } else { m }] as usize;
        let ef = t.edge_face_list(e);
        if t.edge_tag(e).inf_sharp || ef.len() != 2 {
            return None;
        }
        Some(if ef[0] as usize == g { ef[1] } else { ef[0] } as usize)
    };
    let max = t.vertex_faces(c as usize).len();
    let mut start = face;
    for _ in 0..max {
        match step(start, false) {
            Some(g) if g != face => start = g,
            _ => break,
        }
    }
    let mut ring = vec![c];
    // Around a high-valence vertex, look repeats up in a set (the same order, O(1) each).
    let mut seen = (max > HIGH_VALENCE).then(|| std::collections::HashSet::from([c]));
    let mut g = start;
    for _ in 0..max {
        let gv = t.face_vertices(g);
        let m = gv.iter().position(|&x| x == c)?;
        for d in 1..4 {
            let x = gv[(m + d) % 4];
            let new = match seen.as_mut() {
                Some(seen) => seen.insert(x),
                None => !ring.contains(&x),
            };
            if new {
                ring.push(x);
            }
        }
        match step(g, true) {
            Some(next) if next != start => g = next,
            _ => break,
        }
    }
    Some((start, ring))
}

/// The eigen-analysis of a corner's sector (see [`corner_limit`]): the sector's control
/// points and the weights of the limit position and of two tangents spanning the tangent
/// plane. The same for every face of the sector, so a shared region computes it once.
#[derive(Debug)]
pub(super) struct Eigen {
    ring: Vec<u32>,
    l0: Vec<f64>,
    w1: Vec<f64>,
    w2: Vec<f64>,
}

fn eigen_corner(l: &Local, k: usize, options: &Options) -> Option<Derivatives> {
    let (start, ring) = sector_ring(l.topo(), l.face, k)?;
    let analyse = || eigen_analysis(l, k, ring, options).map(Arc::new);
    let e = if l.region.is_shared() {
        let c = l.topo().face_vertices(l.face)[k];
        super::local::cached(&l.region.eigen, (c, start as u32), analyse)
    } else {
        analyse()
    }?;
    let pos = l.pos();
    let combine = |w: &[f64]| {
        let mut acc = [0.0; 3];
        for (wi, &x) in w.iter().zip(&e.ring) {
            let p = &pos[x as usize];
            (0..3).for_each(|i| acc[i] += wi * p[i]);
        }
        acc
    };
    // (No `l₀` for a high-valence crease vertex, whose caller takes the crease curve's point.)
    let p = if e.l0.is_empty() {
        pos[l.topo().face_vertices(l.face)[k] as usize]
    } else {
        combine(&e.l0)
    };
    let (t1, t2) = (combine(&e.w1), combine(&e.w2));
    let (du, dv) = face_tangents(l, k, t1, t2);
    Some(Derivatives {
        p,
        du,
        dv,
        ..Derivatives::default()
    })
}

/// The subdivision matrix `S` of the sector `ring` of corner `k` and its eigen-analysis.
///
/// The children of the ring's points (the corner's vertex point, the edge points of its
/// edges, the face points of its faces) depend only on the faces around the corner. In a
/// shared region (which may be large) `S` is therefore first computed on just those faces,
/// cut out of the region: the same stencils, so the same matrix, at the cost of the corner's
/// valence instead of the region's size. Should that fail (the neighbourhood only becomes
/// self-similar further down, see [`eigen_corner_settled`]), the whole region is used.
fn eigen_analysis(l: &Local, k: usize, ring: Vec<u32>, options: &Options) -> Option<Eigen> {
    if l.region.is_shared() {
        let t = l.topo();
        let c = t.face_vertices(l.face)[k] as usize;
        let faces = t.vertex_faces(c);
        let face = faces.iter().position(|&g| g as usize == l.face)?;
        let (sub, verts) = t.subset(faces);
        let pos = verts.iter().map(|&v| l.pos()[v as usize]).collect();
        let tiny = Local {
            region: Arc::new(Region::whole(sub, pos, false, usize::MAX)),
            face,
        };
        if let Some((_, sub_ring)) = sector_ring(tiny.topo(), face, k) {
            let mapped: Vec<u32> = sub_ring.iter().map(|&x| verts[x as usize]).collect();
            if mapped == ring {
                if let Some(e) = sector_eigen(&tiny, k, sub_ring, options) {
                    return Some(Eigen { ring, ..e });
                }
            }
        }
    }
    sector_eigen(l, k, ring, options)
}

/// [`eigen_analysis`] on the region as it is.
fn sector_eigen(l: &Local, k: usize, ring: Vec<u32>, options: &Options) -> Option<Eigen> {
    let t = l.topo();
    let childl = child_local(l, k, options);
    let child = childl.topo();
    let (_, child_ring) = sector_ring(child, childl.face, k)?;
    let m = ring.len();
    if child_ring.len() != m {
        return None;
    }
    // Column b of S (S[a][b]: value at child_ring[a] when ring[b] is 1 and every other
    // vertex 0), as (a, S[a][b]) for the non-zero entries, a ascending.
    let mut cols: Vec<Vec<(usize, f64)>> = Vec::with_capacity(m);
    let mut unit = vec![[0.0]; t.num_vertices()];
    let mut out = vec![[0.0]; child.num_vertices()];
    for &x in &ring {
        unit[x as usize] = [1.0];
        interpolate(t, child, options, &unit, &mut out);
        unit[x as usize] = [0.0];
        let col = child_ring
            .iter()
            .enumerate()
            .map(|(a, &y)| (a, out[y as usize][0]))
            .filter(|&(_, w)| w != 0.0)
            .collect();
        cols.push(col);
    }
    // Up to the sector of a vertex of HIGH_VALENCE faces, dense as it always was. Above,
    // S is applied sparsely (it has O(m) non-zeros; O(m) per step instead of O(m²)), and a
    // crease vertex skips the dominant eigenvector (O(m³)): its limit position comes from
    // the crease curve (see `corner_limit`), not from `l₀`.
    let high = m > 2 * HIGH_VALENCE + 1;
    let crease = t.vertex_tag(ring[0] as usize).rule == crate::mesh::Rule::Crease;
    let dense = || {
        let mut s = vec![vec![0.0; m]; m];
        for (b, col) in cols.iter().enumerate() {
            for &(a, w) in col {
                s[a][b] = w;
            }
        }
        s
    };
    let l0 = if high && crease {
        Vec::new()
    } else {
        dominant_left_eigenvector(&dense())?
    };
    let (w1, w2) = if high {
        subdominant_left_subspace(m, |w, i| cols[i].iter().map(|&(a, x)| x * w[a]).sum())
    } else {
        let s = dense();
        subdominant_left_subspace(m, |w, j| (0..m).map(|i| s[i][j] * w[i]).sum())
    };
    Some(Eigen { ring, l0, w1, w2 })
}

/// `l` with `l S = l`, `Σ l = 1`: solves `(Sᵀ − I) l = 0` with the last equation replaced
/// by the normalisation (Gaussian elimination, partial pivoting).
fn dominant_left_eigenvector(s: &[Vec<f64>]) -> Option<Vec<f64>> {
    let m = s.len();
    let mut a: Vec<Vec<f64>> = (0..m)
        .map(|i| {
            let mut row: Vec<f64> = (0..m)
                .map(|j| s[j][i] - if i == j { 1.0 } else { 0.0 })
                .collect();
            row.push(0.0);
            row
        })
        .collect();
    a[m - 1] = vec![1.0; m + 1];
    for col in 0..m {
        let piv = (col..m).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[piv][col].abs() < 1e-14 {
            return None;
        }
        a.swap(col, piv);
        for r in 0..m {
            if r != col {
                let f = a[r][col] / a[col][col];
                if f != 0.0 {
                    for c in col..=m {
                        a[r][c] -= f * a[col][c];
                    }
                }
            }
        }
    }
    Some((0..m).map(|i| a[i][m] / a[i][i]).collect())
}

/// Two vectors spanning the left invariant subspace of `S` for its two largest
/// eigenvalues after 1: subspace iteration on sum-free vectors (which `Sᵀ` maps to
/// sum-free vectors, since `S 1 = 1`), orthonormalised each step. `column_dot(w, j)` is
/// `Σᵢ S[i][j] wᵢ`, entry `j` of `Sᵀ w`, for `S` of size `m`.
fn subdominant_left_subspace(
    m: usize,
    column_dot: impl Fn(&[f64], usize) -> f64,
) -> (Vec<f64>, Vec<f64>) {
    let center = |v: &mut Vec<f64>| {
        let mean = v.iter().sum::<f64>() / m as f64;
        v.iter_mut().for_each(|x| *x -= mean);
    };
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let normalize = |v: &mut Vec<f64>| {
        let n = dot(v, v).sqrt();
        if n > 0.0 {
            v.iter_mut().for_each(|x| *x /= n);
        }
    };
    let mut w1: Vec<f64> = (0..m).map(|i| (i as f64 * 1.3).cos()).collect();
    let mut w2: Vec<f64> = (0..m).map(|i| (i as f64 * 0.7 + 0.4).sin()).collect();
    let apply = |w: &[f64]| -> Vec<f64> { (0..m).map(|j| column_dot(w, j)).collect() };
    for _ in 0..200 {
        w1 = apply(&w1);
        w2 = apply(&w2);
        center(&mut w1);
        center(&mut w2);
        normalize(&mut w1);
        let d = dot(&w2, &w1);
        w2.iter_mut().zip(&w1).for_each(|(x, y)| *x -= d * y);
        normalize(&mut w2);
    }
    (w1, w2)
}

/// The face's edge directions at corner `k` (along edge `k`, toward corner `k - 1`),
/// projected onto the plane spanned by `t1`, `t2`, mapped to `(du, dv)`.
fn face_tangents(l: &Local, k: usize, t1: V3, t2: V3) -> (V3, V3) {
    let (a, b) = face_edge_dirs(l, k);
    uv_from_corner_frame(k, project(a, t1, t2), project(b, t1, t2))
}

/// Tangents along edge `k` of a face and toward its corner `k - 1`, as `(du, dv)`.
fn uv_from_corner_frame(k: usize, a: [f64; 3], b: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let neg = |x: [f64; 3]| [-x[0], -x[1], -x[2]];
    match k {
        0 => (a, b),
        1 => (neg(b), a),
        2 => (neg(a), neg(b)),
        _ => (b, neg(a)),
    }
}

/// The exact limit position and tangents of a smooth interior vertex with quads around it,
/// from the limit masks, rotated so that the face comes first.
///
/// Above [`HIGH_VALENCE`] faces (in a shared region) the masks are applied once per vertex:
/// the smooth tangent masks at rotation `i` (the face listed `i`-th first) are
/// `t₁ᵢ = Σⱼ w(j − i)·xⱼ` and `t₂ᵢ = t₁,ᵢ₊₁`, with `w` cosines in `θ = 2π/n`, so
/// `t₁ᵢ = cos(iθ) C + sin(iθ) S` with `C`, `S` the cosine and sine masks applied at
/// rotation 0: equal to the direct sums up to rounding, in `O(1)` per face instead of `O(n)`.
fn smooth_corner(l: &Local, k: usize) -> Derivatives {
    let t = l.topo();
    let pos = l.pos();
    let c = t.face_vertices(l.face)[k] as usize;
    let faces = t.vertex_faces(c);
    let edges = t.vertex_edges(c);
    let nf = faces.len();
    let start = faces
        .iter()
        .position(|&g| g as usize == l.face)
        .unwrap_or(0);
    let rule = t.vertex_tag(c).rule;
    if l.region.is_shared() && nf > HIGH_VALENCE && rule == crate::mesh::Rule::Smooth {
        let [p, cm, sm] =
            super::local::cached(&l.region.smooth, (c as u32, 0), || smooth_masks_at(l, c));
        let theta = 2.0 * std::f64::consts::PI / nf as f64;
        let at = |i: usize| {
            let (sn, cs) = ((i % nf) as f64 * theta).sin_cos();
            [0, 1, 2].map(|x| cs * cm[x] + sn * sm[x])
        };
        let (du, dv) = uv_from_corner_frame(k, at(start), at(start + 1));
        return Derivatives {
            p,
            du,
            dv,
            ..Derivatives::default()
        };
    }
    let rot = |i: usize, n: usize| (i + start) % n.max(1);
    let ends: Vec<u32> = t.vertex_neighbours(c).collect();
    let ends: Vec<u32> = (0..edges.len())
        .map(|i| ends[rot(i, edges.len())])
        .collect();
    let locals = t.vertex_face_locals(c);
    let opposite: Vec<u32> = (0..nf)
        .map(|i| {
            let g = faces[rot(i, nf)] as usize;
            let fv = t.face_vertices(g);
            fv[(locals[rot(i, nf)] as usize + 2) % fv.len()]
        })
        .collect();
    let sharp = vec![0.0f32; edges.len()];
    let (mut pm, mut t1, mut t2) = (
        VertexMask::default(),
        VertexMask::default(),
        VertexMask::default(),
    );
    catmark::limit_position_mask(rule, &sharp, nf, &mut pm);
    catmark::limit_tangent_masks(rule, &sharp, nf, &mut t1, &mut t2);
    let apply = |m: &VertexMask| {
        let mut acc = [0.0; 3];
        let mut add = |w: f64, p: &[f64; 3]| (0..3).for_each(|i| acc[i] += w * p[i]);
        add(m.vertex, &pos[c]);
        if m.has_edges {
            ends.iter()
                .zip(&m.edges)
                .for_each(|(&x, &w)| add(w, &pos[x as usize]));
        }
        if m.has_faces {
            opposite
                .iter()
                .zip(&m.faces)
                .for_each(|(&x, &w)| add(w, &pos[x as usize]));
        }
        acc
    };
    let (du, dv) = uv_from_corner_frame(k, apply(&t1), apply(&t2));
    Derivatives {
        p: apply(&pm),
        du,
        dv,
        ..Derivatives::default()
    }
}

/// For a smooth interior vertex `c` of `n` quads: its limit position and the cosine and
/// sine tangent masks (OpenSubdiv's smooth tangent mask and its quarter-period shift)
/// applied at rotation 0, `[P, C, S]`. `C` is the first tangent of the face listed first
/// around `c`.
fn smooth_masks_at(l: &Local, c: usize) -> [[f64; 3]; 3] {
    let (t, pos) = (l.topo(), l.pos());
    let faces = t.vertex_faces(c);
    let n = faces.len();
    let locals = t.vertex_face_locals(c);
    let theta = 2.0 * std::f64::consts::PI / n as f64;
    let (cs, chs) = (theta.cos(), (0.5 * theta).cos());
    let lambda = 5.0 / 16.0 + (cs + chs * (2.0 * (9.0 + cs)).sqrt()) / 16.0;
    let fscale = 1.0 / (4.0 * lambda - 1.0);
    let sharp = vec![0.0f32; t.vertex_edges(c).len()];
    let mut pm = VertexMask::default();
    catmark::limit_position_mask(crate::mesh::Rule::Smooth, &sharp, n, &mut pm);
    let (mut p, mut cm, mut sm) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    (0..3).for_each(|x| p[x] = pm.vertex * pos[c][x]);
    for (i, x) in t.vertex_neighbours(c).enumerate() {
        let (si, ci) = (i as f64 * theta).sin_cos();
        let q = &pos[x as usize];
        let we = if pm.has_edges { pm.edges[i] } else { 0.0 };
        (0..3).for_each(|a| {
            p[a] += we * q[a];
            cm[a] += 4.0 * ci * q[a];
            sm[a] += 4.0 * si * q[a];
        });
    }
    for i in 0..n {
        let g = faces[i] as usize;
        let fv = t.face_vertices(g);
        let q = &pos[fv[(locals[i] as usize + 2) % fv.len()] as usize];
        let (si, ci) = (i as f64 * theta).sin_cos();
        let (si1, ci1) = ((i + 1) as f64 * theta).sin_cos();
        let wf = if pm.has_faces { pm.faces[i] } else { 0.0 };
        (0..3).for_each(|a| {
            p[a] += wf * q[a];
            cm[a] += fscale * (ci + ci1) * q[a];
            sm[a] += fscale * (si + si1) * q[a];
        });
    }
    [p, cm, sm]
}

/// Directions from corner `k` of the cut-out's face to its neighbours `k + 1` and `k - 1`.
fn face_edge_dirs(l: &Local, k: usize) -> (V3, V3) {
    let fv = l.topo().face_vertices(l.face);
    let n = fv.len();
    let pos = l.pos();
    let c = &pos[fv[k] as usize];
    (
        geom::sub(&pos[fv[(k + 1) % n] as usize], c),
        geom::sub(&pos[fv[(k + n - 1) % n] as usize], c),
    )
}

/// The least-squares projection of `e` onto the plane spanned by `t1`, `t2` (or `e` when
/// they are parallel).
fn project(e: V3, t1: V3, t2: V3) -> V3 {
    let (g11, g12, g22) = (
        geom::dot(&t1, &t1),
        geom::dot(&t1, &t2),
        geom::dot(&t2, &t2),
    );
    let det = g11 * g22 - g12 * g12;
    if det.abs() <= f64::MIN_POSITIVE {
        return e;
    }
    let (r1, r2) = (geom::dot(&e, &t1), geom::dot(&e, &t2));
    let x = (g22 * r1 - g12 * r2) / det;
    let y = (g11 * r2 - g12 * r1) / det;
    [0, 1, 2].map(|i| x * t1[i] + y * t2[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{BoundaryInterpolation, Options};

    /// A fan of `n` faces around vertex 0 (quads, or triangles when `tri`), closed or open
    /// (one gap), on a wavy surface so that nothing is planar or symmetric.
    fn fan(n: usize, tri: bool, closed: bool) -> PolyMesh {
        let mut p = vec![[0.0, 0.0, 0.1]];
        let wave = |a: f64| 0.2 * (3.0 * a).sin() + 0.05 * (7.0 * a).cos();
        for i in 0..n {
            let a = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            p.push([a.cos(), a.sin(), wave(a)]);
        }
        if !tri {
            for i in 0..n {
                let a = 2.0 * std::f64::consts::PI * (i as f64 + 0.5) / n as f64;
                p.push([2.0 * a.cos(), 2.0 * a.sin(), wave(a + 1.0)]);
            }
        }
        let m = if closed { n } else { n - 1 };
        let faces: Vec<Vec<u32>> = (0..m)
            .map(|i| {
                let (a, b) = (1 + i as u32, 1 + ((i + 1) % n) as u32);
                if tri {
                    vec![0, a, b]
                } else {
                    vec![0, a, 1 + (n + i) as u32, b]
                }
            })
            .collect();
        PolyMesh::from_faces(p, &faces).expect("valid fan")
    }

    /// The sparse application of `Sᵀ` used above [`HIGH_VALENCE`] gives the subspace of the
    /// dense one: the same sums without their zero terms.
    #[test]
    fn sparse_and_dense_subspace_iteration_agree() {
        let m = 41;
        // A row-stochastic band matrix (S 1 = 1), as a subdivision matrix is.
        let mut s = vec![vec![0.0; m]; m];
        for (i, row) in s.iter_mut().enumerate() {
            let w = [0.125, 0.75, 0.125];
            for (d, &x) in w.iter().enumerate() {
                row[(i + m + d - 1) % m] += x * (1.0 + 0.01 * (i % 3) as f64 * (d as f64 - 1.0));
            }
            let sum: f64 = row.iter().sum();
            row.iter_mut().for_each(|x| *x /= sum);
        }
        let cols: Vec<Vec<(usize, f64)>> = (0..m)
            .map(|b| {
                (0..m)
                    .map(|a| (a, s[a][b]))
                    .filter(|&(_, x)| x != 0.0)
                    .collect()
            })
            .collect();
        let dense = subdominant_left_subspace(m, |w, j| (0..m).map(|i| s[i][j] * w[i]).sum());
        let sparse =
            subdominant_left_subspace(m, |w, i| cols[i].iter().map(|&(a, x)| x * w[a]).sum());
        for (a, b) in [(&dense.0, &sparse.0), (&dense.1, &sparse.1)] {
            for (x, y) in a.iter().zip(b.iter()) {
                assert!((x - y).abs() < 1e-12, "{x} vs {y}");
            }
        }
        assert!(dense.0.iter().any(|x| x.abs() > 0.01));
    }

    /// Faces that share a region (around a vertex of more faces than [`HIGH_VALENCE`])
    /// give the same surface as faces cut out on their own: bit for bit, except at the
    /// high-valence vertex itself, where the smooth limit masks are applied once per vertex
    /// and rotated (equal up to rounding).
    #[test]
    fn shared_regions_equal_own_cut_outs() {
        let params = [0.0, 0.25, 0.5, 1.0 / 3.0, 0.9, 1.0];
        let cases = [
            (fan(HIGH_VALENCE + 7, false, true), "closed quad fan"),
            (fan(HIGH_VALENCE + 7, true, true), "closed triangle fan"),
            (fan(HIGH_VALENCE + 3, false, false), "open quad fan"),
            (fan(HIGH_VALENCE + 3, true, false), "open triangle fan"),
        ];
        for (mesh, what) in &cases {
            for boundary in [
                BoundaryInterpolation::EdgeOnly,
                BoundaryInterpolation::EdgeAndCorner,
            ] {
                let options = Options {
                    boundary,
                    ..Options::default()
                };
                let shared = LimitSurface::new(mesh, options).expect("surface");
                let alone =
                    LimitSurface::with_high_valence(mesh, options, usize::MAX).expect("surface");
                let mut compared = 0;
                for f in 0..shared.num_faces() {
                    for sub in 0..shared.num_subfaces(f) {
                        for &u in &params {
                            for &v in &params {
                                let p = SurfacePoint {
                                    face: f as u32,
                                    subface: sub as u32,
                                    u,
                                    v,
                                };
                                let (a, b) = (shared.eval_point(p), alone.eval_point(p));
                                let (a, b) = (a.expect("eval"), b.expect("eval"));
                                // Corner (0, 0) of a quad, and of sub-face 0's..n's, is
                                // vertex 0 of the fan.
                                if (u, v) == (0.0, 0.0) {
                                    for (x, y) in [(a.p, b.p), (a.du, b.du), (a.dv, b.dv)] {
                                        let d = geom::norm(&geom::sub(&x, &y));
                                        assert!(
                                            d <= 1e-12 * (1.0 + geom::norm(&y)),
                                            "{what}, {boundary:?}: face {f}/{sub} at the \
                                             centre: {x:?} vs {y:?}"
                                        );
                                    }
                                } else {
                                    assert_eq!(
                                        a, b,
                                        "{what}, {boundary:?}: face {f}/{sub} at ({u}, {v})"
                                    );
                                }
                                compared += 1;
                            }
                        }
                    }
                }
                assert!(compared > 500, "{what}: only {compared} points");
            }
        }
    }
}
