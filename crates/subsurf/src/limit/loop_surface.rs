//! [`LoopSurface`]: exact evaluation of the Loop limit surface at any `(triangle, u, v)`,
//! with first and second derivatives, matching OpenSubdiv's `Bfr` for `SCHEME_LOOP`.
//!
//! # Parameterisation
//! Each face is a triangle `[c₀ c₁ c₂]` with its own domain `u, v ≥ 0, u + v ≤ 1`: `(0, 0)`
//! at `c₀`, `u` toward `c₁`, `v` toward `c₂` (OpenSubdiv's `Bfr::Parameterization` of a
//! triangle, [`Domain::Triangle`](super::Domain::Triangle)).
//!
//! # Method: sub-patch recursion
//! (J. Stam, "Evaluation of Loop subdivision surfaces", SIGGRAPH 1998 course notes, §3, by
//! recursion rather than eigen-analysis; OpenSubdiv's `Bfr` likewise refines irregular faces.)
//! - A triangle whose limit is one quartic box-spline patch ([`super::box_spline`]: its
//!   corners smooth of valence 6, or regular boundary/crease corners of 3 faces, or
//!   infinitely sharp corners of one face, with phantom points where the sector ends, and no
//!   semi-sharp feature at a corner) is evaluated in closed form on its twelve control points.
//! - Any other triangle is refined: its 1-ring is cut out ([`super::local::cut_out_unbounded`],
//!   with the far ends of semi-sharp edges under Chaikin's rule and only the face's sectors at
//!   infinitely sharp vertices) as a [`Topology::subset_canonical`], whose tags, sharpness and
//!   rules are the level's, and refined one Loop step by the project's own refinement
//!   ([`refine_tri_topology`](crate::refine::refine_tri_topology) and the rows of its masks,
//!   which [`interpolate_loop`](crate::refine::interpolate_loop) applies), so creases decay,
//!   boundaries, corners and non-manifold vertices behave exactly as in
//!   [`subdivide`](fn@crate::subdivide). That refinement depends on the cut-out's topology
//!   alone: it is done once per configuration ([`super::loop_tree`]) and shared by every face
//!   and node with the same, whose points flow through its rows. Its four children
//!   (OpenSubdiv's numbering: child `j < 3` at corner `j`, `(u, v) = (s, t)/2`
//!   shifted to that corner; the middle child `3 = [E₁ E₂ E₀]` turned by half a turn,
//!   `(u, v) = ((1, 1) − (s, t))/2`) are patches or refined again. A point on an edge
//!   shared by children is taken in a patch child if there is one, else in the middle one,
//!   away from the irregular corners. First derivatives scale by 2 per level (by −2 through
//!   the middle child), second ones by 4.
//! - A point exactly at a corner of a face that is not one patch takes its corner child if
//!   that is a patch; otherwise, when the corner's rule is final (smooth of valence ≥ 3,
//!   crease in a sector of three faces, or corner, no semi-sharp feature left to decay),
//!   the limit masks of the level
//!   ([`Rules::limit_position_mask`](crate::scheme::Rules::limit_position_mask),
//!   [`Rules::limit_tangent_masks`](crate::scheme::Rules::limit_tangent_masks)): the position
//!   is exact, and as `du`, `dv` the tangents along the face's sides, mapped as the face's
//!   `(u, v)` maps them (at an extraordinary vertex the parametric derivatives are degenerate;
//!   at a smooth vertex these span the exact tangent plane, their lengths are not
//!   derivatives; `Bfr`'s are approximate there too); second derivatives are zero. At a
//!   crease or boundary vertex whose sector is not the regular one of three faces, the
//!   crease's across tangent mask (OpenSubdiv's `assignCreaseLimitTangentMasks`, after
//!   Hoppe et al. 1994) is not the limit's tangent plane (22° off at level 0 on
//!   `loop_xord_boundary`): the corner is refined down to [`MAX_DEPTH`] first, where the
//!   masks' error has decayed geometrically with refinement (the points are kept relative
//!   to the face's corner, so no digit is lost). There the normal differs from `Bfr`'s
//!   (approximation level 10) by 1.3e-4 rad, the error that `Bfr`'s own convergence over
//!   levels 6, 8, 10 (ratio 0.46 per level) extrapolates for it, 1.31e-4: ours is that
//!   limit. At an interior crease vertex (two infinitely sharp edges) each of the two sectors
//!   has its own tangent plane: the masks are those of the face's sector (the vertex's
//!   edges listed from the sharp edge that begins it), as `Bfr` evaluates a corner in its
//!   face's sector (on `loop_cubes_infsharp` `Bfr`'s normals converge to ours, 1.4e-4 rad
//!   off at its level 10, its extrapolated error). Otherwise (a dart, a semi-sharp vertex
//!   or edge that still decays) the corner child is refined again.
//! - The depth is capped at [`MAX_DEPTH`] levels: a point within `2^-48` of its face's size
//!   from an irregular corner (or a dart reached so deep) takes that corner's masks at that
//!   level. At a dart, whose masks are the smooth vertex's and not exact, the position so
//!   taken is the limit up to the dart's subdominant eigenvalue to the 48th power.
//!
//! # Cost
//! Building the surface analyses nothing; a face that is one patch costs a walk around its
//! corners per evaluation. An irregular face costs its cut-out in canonical form and a look-up
//! of its configuration, built the first time (its refinement's rows and children, as deep
//! as points need) and kept by the surface (at most 8,192 of them, and four per face of the
//! mesh plus 64; past that a face's configurations are built for it and dropped after it). [`LoopSurface::eval_many`]
//! evaluates the points of each face together (list them face by face): the points of the
//! face's nodes are computed once for them and dropped after them.

use std::cell::OnceCell;
use std::sync::Arc;

use rayon::prelude::*;

use super::box_spline::{box_net, BoxPoly};
use super::local::cut_out_unbounded;
use super::loop_tree::{cut_out_topology, LoopKid, LoopTree, LoopTrees};
use super::{copy_positions, Derivatives, EvalError, Order, SurfacePoint, VertexMasks, MAX_DEPTH};
use crate::geom;
use crate::mesh::{CreaseMethod, MeshError, Options, PolyMesh, Rule, Topology};
use crate::refine::check_triangles;
use crate::scheme::loop_::Loop;

/// The exact Loop limit surface of a triangle mesh (see the module docs).
///
/// ```
/// use subsurf::limit::LoopSurface;
/// use subsurf::mesh::{Options, PolyMesh};
/// // A tetrahedron: every vertex of valence 3.
/// let p = vec![[1.0, 1.0, 1.0], [-1.0, -1.0, 1.0], [-1.0, 1.0, -1.0], [1.0, -1.0, -1.0]];
/// let tet = PolyMesh::from_faces(p, &[[0u32, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]]).unwrap();
/// let s = LoopSurface::new(&tet, Options::default()).unwrap();
/// let centre = s.eval(0, 1.0 / 3.0, 1.0 / 3.0).unwrap();
/// // The limit of a regular tetrahedron is symmetric about the origin, inside the hull.
/// let r = centre.p.iter().map(|x| x * x).sum::<f64>().sqrt();
/// assert!(r > 0.1 && r < 1.0);
/// ```
#[derive(Clone, Debug)]
pub struct LoopSurface {
    topo: Topology,
    options: Options,
    pos: Vec<[f64; 3]>,
    /// The configurations of the irregular faces met so far (see the module docs), shared
    /// by clones (they depend on the topology only).
    trees: Arc<LoopTrees>,
}

impl LoopSurface {
    /// The Loop limit surface of `mesh` (every face a triangle) with `options` (boundary
    /// interpolation, crease method; the mesh's tags give creases, corners and holes).
    ///
    /// # Errors
    /// [`MeshError::NotTriangle`] naming the first face that is not a triangle, or any error
    /// of [`Topology::from_mesh`].
    pub fn new(mesh: &PolyMesh, options: Options) -> Result<Self, MeshError> {
        mesh.validate()?;
        check_triangles(mesh)?;
        let (topo, _) = Topology::from_mesh(mesh, &options)?;
        Ok(Self {
            trees: Arc::new(LoopTrees::for_faces(topo.num_faces())),
            topo,
            options,
            pos: mesh.positions().to_vec(),
        })
    }

    /// Number of faces of the control mesh.
    pub fn num_faces(&self) -> usize {
        self.topo.num_faces()
    }

    /// Estimated peak bytes of the surface of `mesh`: what
    /// [`LimitSurface::estimate_build_memory`](super::LimitSurface::estimate_build_memory)
    /// charges for the mesh's topology and points, plus the configuration trees it may keep
    /// (at most `min(8192, 4 × faces + 64)`, 8 KiB each; see the module docs).
    pub fn estimate_memory(mesh: &PolyMesh) -> u64 {
        let trees = LoopTrees::cap(mesh.num_faces()) as u64;
        super::LimitSurface::estimate_build_memory(mesh)
            .saturating_add(trees.saturating_mul(super::loop_tree::TREE_BYTES))
    }

    /// Number of configuration trees built so far and kept (distinct cut-outs of the
    /// irregular faces evaluated and of the nodes below them; see the module docs).
    pub fn num_configurations(&self) -> usize {
        self.trees.len()
    }

    /// Whether face `f` exists and has a surface (is not a hole, nor made one by
    /// [`BoundaryInterpolation::None`](crate::mesh::BoundaryInterpolation::None)).
    pub fn has_surface(&self, f: usize) -> bool {
        f < self.num_faces() && !self.topo.is_hole(f)
    }

    /// The control points.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.pos
    }

    /// Replaces the control points (the same number, finite).
    ///
    /// # Errors
    /// [`EvalError::InvalidPositions`]: naming the first vertex that is not finite, or, when
    /// the number of points differs from the mesh's, the smaller of the two counts.
    pub fn set_positions(&mut self, pos: &[[f64; 3]]) -> Result<(), EvalError> {
        copy_positions(&mut self.pos, pos)
    }

    /// Position and first and second derivatives at `(u, v)` of triangle `face`.
    ///
    /// # Errors
    /// As [`LoopSurface::eval_point`].
    pub fn eval(&self, face: u32, u: f64, v: f64) -> Result<Derivatives, EvalError> {
        self.eval_point(SurfacePoint {
            face,
            subface: 0,
            u,
            v,
        })
    }

    /// Position and derivatives at `p` (its `subface` must be 0).
    ///
    /// # Errors
    /// [`EvalError::NoSuchFace`], [`EvalError::NoSuchSubface`], [`EvalError::Hole`], and
    /// [`EvalError::OutsideTriangle`] for `(u, v)` outside the triangle `u, v ≥ 0, u + v ≤ 1`
    /// (or not finite).
    pub fn eval_point(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        self.check(p)?;
        Ok(FaceEval::new(self, p.face as usize).eval(p.u, p.v))
    }

    /// [`eval_point`](Self::eval_point) at every point, in parallel over runs of points on
    /// one face (each run shares its face's refinement, see the module docs); `order` is
    /// accepted for the [`Surface`](super::Surface) interface (second derivatives are
    /// always computed).
    pub fn eval_many(
        &self,
        points: &[SurfacePoint],
        order: Order,
    ) -> Vec<Result<Derivatives, EvalError>> {
        let mut out = vec![Ok(Derivatives::default()); points.len()];
        self.eval_many_to(points, order, &mut out);
        out
    }

    /// [`eval_many`](Self::eval_many) into `out` (one result per point).
    ///
    /// # Panics
    /// If `out.len() != points.len()`.
    pub fn eval_many_to(
        &self,
        points: &[SurfacePoint],
        _order: Order,
        out: &mut [Result<Derivatives, EvalError>],
    ) {
        assert_eq!(out.len(), points.len(), "one result per point");
        // Runs of consecutive points on one face.
        let mut runs = Vec::new();
        let mut start = 0;
        for i in 1..=points.len() {
            if i == points.len() || points[i].face != points[start].face {
                runs.push(start..i);
                start = i;
            }
        }
        let mut slices = Vec::with_capacity(runs.len());
        let mut rest = out;
        for r in &runs {
            let (head, tail) = rest.split_at_mut(r.len());
            slices.push((r.clone(), head));
            rest = tail;
        }
        slices.into_par_iter().for_each(|(r, o)| {
            let mut face: Option<FaceEval<'_>> = None;
            for (p, o) in points[r].iter().zip(o.iter_mut()) {
                *o = self.check(*p).map(|()| {
                    let f = face.get_or_insert_with(|| FaceEval::new(self, p.face as usize));
                    f.eval(p.u, p.v)
                });
            }
        });
    }

    /// The errors of point `p` (see [`eval_point`](Self::eval_point)).
    fn check(&self, p: SurfacePoint) -> Result<(), EvalError> {
        let f = p.face as usize;
        if f >= self.num_faces() {
            return Err(EvalError::NoSuchFace {
                face: p.face,
                count: self.num_faces(),
            });
        }
        if p.subface != 0 {
            return Err(EvalError::NoSuchSubface {
                face: p.face,
                subface: p.subface,
                size: 1,
            });
        }
        if !in_triangle(p.u, p.v) {
            return Err(EvalError::OutsideTriangle { u: p.u, v: p.v });
        }
        if self.topo.is_hole(f) {
            return Err(EvalError::Hole { face: p.face });
        }
        Ok(())
    }
}

/// Whether `(u, v)` is in the triangle `u, v ≥ 0, u + v ≤ 1`, allowing `u + v` a few units
/// of rounding above 1 (a grid's `i/(N−1) + j/(N−1)` with `i + j = N − 1`).
pub(super) fn in_triangle(u: f64, v: f64) -> bool {
    u.is_finite() && v.is_finite() && u >= 0.0 && v >= 0.0 && u + v <= 1.0 + 4.0 * f64::EPSILON
}

/// The evaluation of one base face: a patch, or the root of its configuration's tree with
/// the face's points.
#[allow(clippy::large_enum_variant)] // one per face being evaluated, on the stack
enum FaceEval<'a> {
    Patch(BoxPoly),
    Tree(Box<Node<'a>>),
}

impl<'a> FaceEval<'a> {
    fn new(s: &'a LoopSurface, f: usize) -> Self {
        match box_net(&s.topo, f) {
            Some(net) => FaceEval::Patch(BoxPoly::new(&net.map(|p| p.at(&s.pos)))),
            None => {
                let chaikin = s.options.crease_method == CreaseMethod::Chaikin;
                let faces = cut_out_unbounded(&s.topo, f, chaikin);
                let (sub, verts) = cut_out_topology(&s.topo, &faces);
                let tree = s.trees.get(sub);
                let pos: Vec<[f64; 3]> = verts.iter().map(|&v| s.pos[v as usize]).collect();
                FaceEval::Tree(Box::new(Node::new(s, tree, pos, [0.0; 3])))
            }
        }
    }

    fn eval(&self, u: f64, v: f64) -> Derivatives {
        // Rounding above the hypotenuse is moved onto it.
        let excess = (u + v - 1.0).max(0.0);
        let (u, v) = (u - 0.5 * excess, v - 0.5 * excess);
        match self {
            FaceEval::Patch(poly) => poly.eval(u, v),
            FaceEval::Tree(n) => n.eval(u, v, 0),
        }
    }
}

/// An irregular face of a level: its configuration's tree (the face is face 0 of the
/// tree's cut-out), the cut-out's points, and, built when first needed, its four children.
/// The points are kept relative to `origin` (the face's first corner), so that deep in the
/// tree, where they lie within `2^-depth` of the size of each other, their differences
/// (tangents, masks that sum to zero) keep all their digits: subdivision commutes with
/// translation (every row's weights sum to one).
struct Node<'a> {
    surface: &'a LoopSurface,
    tree: Arc<LoopTree>,
    pos: Vec<[f64; 3]>,
    origin: [f64; 3],
    children: OnceCell<Box<[Child<'a>; 4]>>,
}

/// A child of an irregular face: a patch or irregular again.
#[allow(clippy::large_enum_variant)] // patches are most children; a box each would cost more
enum Child<'a> {
    Patch(BoxPoly),
    Node(Box<Node<'a>>),
}

impl<'a> Node<'a> {
    /// The face of configuration `tree` whose cut-out's points are `pos` (relative to
    /// `origin`), its points moved to be relative to its first corner.
    fn new(
        surface: &'a LoopSurface,
        tree: Arc<LoopTree>,
        mut pos: Vec<[f64; 3]>,
        origin: [f64; 3],
    ) -> Self {
        let o = pos[tree.topo.face_vertices(0)[0] as usize];
        pos.iter_mut().for_each(|p| *p = geom::sub(p, &o));
        Node {
            surface,
            tree,
            pos,
            origin: geom::add(&origin, &o),
            children: OnceCell::new(),
        }
    }

    /// The four children, from the refined points of the cut-out.
    fn children(&self) -> &[Child<'a>; 4] {
        self.children.get_or_init(|| {
            let s = self.surface;
            let kids = self.tree.kids(&s.options, &s.trees);
            let mut refined = Vec::new();
            kids.refine_into(&self.pos, &mut refined);
            Box::new(std::array::from_fn(|j| match &kids.kids[j] {
                LoopKid::Patch(net) => Child::Patch(BoxPoly::new(&net.map(|p| p.at(&refined)))),
                LoopKid::Node(tree, cols) => {
                    let pos = cols.iter().map(|&c| refined[c as usize]).collect();
                    Child::Node(Box::new(Node::new(s, tree.clone(), pos, self.origin)))
                }
            }))
        })
    }

    /// Position and derivatives at `(u, v)` of this face, `depth` levels below the base.
    fn eval(&self, u: f64, v: f64, depth: u32) -> Derivatives {
        let corner = match (u, v) {
            (0.0, 0.0) => Some(0),
            (1.0, 0.0) => Some(1),
            (0.0, 1.0) => Some(2),
            _ if depth >= MAX_DEPTH => Some(nearest_corner(u, v)),
            _ => None,
        };
        if let Some(k) = corner {
            let settled = depth >= MAX_DEPTH || self.corner_is_final(k);
            if settled && !matches!(self.children()[k], Child::Patch(_)) {
                return self.corner_limit(k);
            }
        }
        let (j, s, t) = self.pick_child(u, v);
        let d = match &self.children()[j] {
            Child::Patch(poly) => {
                let mut d = poly.eval(s, t);
                d.p = geom::add(&d.p, &self.origin);
                d
            }
            Child::Node(n) => n.eval(s, t, depth + 1),
        };
        d.scaled(if j == 3 { -2.0 } else { 2.0 })
    }

    /// The child holding `(u, v)` and the point in the child's parameters: a patch child if
    /// one holds it, else the middle child, else a corner child.
    fn pick_child(&self, u: f64, v: f64) -> (usize, f64, f64) {
        let local = [
            (2.0 * u, 2.0 * v),
            (2.0 * u - 1.0, 2.0 * v),
            (2.0 * u, 2.0 * v - 1.0),
            (1.0 - 2.0 * u, 1.0 - 2.0 * v),
        ];
        // How far each child's parameters are outside its triangle (0 inside).
        let outside = |(s, t): (f64, f64)| (-s).max(-t).max(s + t - 1.0).max(0.0);
        let children = self.children();
        let rank = |j: usize| {
            let patch = matches!(children[j], Child::Patch(_));
            (outside(local[j]) > 0.0, !patch, j != 3)
        };
        let best = (0..4)
            .min_by(|&a, &b| {
                let (ra, rb) = (rank(a), rank(b));
                if ra.0 && rb.0 {
                    outside(local[a]).total_cmp(&outside(local[b]))
                } else {
                    ra.cmp(&rb)
                }
            })
            .unwrap_or(3);
        let (s, t) = local[best];
        // A point a rounding error outside is moved in.
        (best, s.max(0.0), t.max(0.0))
    }

    /// Whether the rule at corner `k` no longer changes with refinement and its limit masks
    /// are exact: smooth of valence ≥ 3 (manifold, interior), a crease in a sector of three
    /// faces, or a corner, with no semi-sharp vertex or edge.
    fn corner_is_final(&self, k: usize) -> bool {
        let topo = &self.tree.topo;
        let c = topo.face_vertices(0)[k] as usize;
        let tag = topo.vertex_tag(c);
        if tag.semi_sharp || tag.semi_sharp_edges {
            return false;
        }
        match tag.rule {
            Rule::Smooth => {
                let n = topo.vertex_faces(c).len();
                !tag.boundary && !tag.non_manifold && n >= 3 && topo.vertex_edges(c).len() == n
            }
            // A crease's limit tangent masks span the tangent plane only in a regular
            // sector of three faces; elsewhere the corner is refined down to MAX_DEPTH,
            // where the masks' error has decayed with the sector's subdominant eigenvalues.
            Rule::Crease => topo.vertex_faces(c).len() == 3,
            Rule::Corner => true,
            Rule::Dart => false,
        }
    }

    /// The limit at corner `k` from the level's masks (module docs): the position, and the
    /// tangents along the face's sides mapped to `du`, `dv`.
    fn corner_limit(&self, k: usize) -> Derivatives {
        let t = &self.tree.topo;
        let fv = t.face_vertices(0);
        let (c, next, prev) = (fv[k] as usize, fv[(k + 1) % 3], fv[(k + 2) % 3]);
        let pos = &self.pos;
        let mut masks = VertexMasks::default();
        let loaded = masks.load_for_face(Loop, t, c, true, Some(0));
        let (p, toward): ([f64; 3], [[f64; 3]; 2]) = if !loaded {
            (
                pos[c],
                [next, prev].map(|x| geom::sub(&pos[x as usize], &pos[c])),
            )
        } else {
            let mut acc = [[0.0; 3]; 3];
            masks.terms(c, |x, w| {
                for (a, &wi) in acc.iter_mut().zip(&w) {
                    for d in 0..3 {
                        a[d] += wi * pos[x as usize][d];
                    }
                }
            });
            let [p, t1, t2] = acc;
            (p, side_tangents(t, pos, c, [next, prev], p, [t1, t2]))
        };
        // `toward` = tangents toward the next and the previous corner; the face's `(u, v)`
        // maps the sides at corner `k` as: k = 0: u → next, v → prev; k = 1: u → −prev,
        // v → next − prev; k = 2: u → prev − next... see `map_sides`.
        let (du, dv) = map_sides(k, toward);
        Derivatives {
            p: geom::add(&p, &self.origin),
            du,
            dv,
            ..Derivatives::default()
        }
    }
}

/// The tangents at vertex `c` (limit `p`, mask tangents `t1`, `t2`) toward its neighbours
/// `toward`: for a smooth interior vertex of valence `n ≥ 3`, the tangent of Loop's
/// characteristic map along the edge `j` to the neighbour, `cos(2πj/n) t₁ + sin(2πj/n) t₂`;
/// at any other vertex the chord to the neighbour projected onto the tangent plane
/// `t₁ × t₂` (under the corner rule, or where the masks' tangents are parallel, the chord).
fn side_tangents(
    t: &Topology,
    pos: &[[f64; 3]],
    c: usize,
    toward: [u32; 2],
    p: [f64; 3],
    [t1, t2]: [[f64; 3]; 2],
) -> [[f64; 3]; 2] {
    let tag = t.vertex_tag(c);
    let edges = t.vertex_edges(c);
    let n = edges.len();
    let smooth = matches!(tag.rule, Rule::Smooth | Rule::Dart)
        && !tag.boundary
        && !tag.non_manifold
        && n >= 3
        && t.vertex_faces(c).len() == n;
    let chord = |x: u32| geom::sub(&pos[x as usize], &pos[c]);
    if smooth {
        let along = |x: u32| {
            let j = edges.iter().position(|&e| {
                let [a, b] = t.edge_vertices(e as usize);
                (a == x && b as usize == c) || (b == x && a as usize == c)
            });
            match j {
                Some(j) => {
                    let th = 2.0 * std::f64::consts::PI * j as f64 / n as f64;
                    std::array::from_fn(|d| th.cos() * t1[d] + th.sin() * t2[d])
                }
                None => chord(x),
            }
        };
        return toward.map(along);
    }
    // Parallel tangents (one of them zero, as across a sector of one face at a
    // non-manifold edge) span no plane: their cross product is rounding noise, whose
    // direction is arbitrary, so it is taken as zero below a relative threshold.
    let cross = geom::cross(&t1, &t2);
    let scale = geom::dot(&t1, &t1) + geom::dot(&t2, &t2);
    let spans = geom::dot(&cross, &cross).sqrt() > 1e-10 * scale;
    if tag.rule == Rule::Corner || !spans {
        return toward.map(chord);
    }
    let normal = geom::normalize_or_zero(cross);
    toward.map(|x| {
        let d = geom::sub(&pos[x as usize], &p);
        let h = geom::dot(&d, &normal);
        std::array::from_fn(|i| d[i] - h * normal[i])
    })
}

/// `(du, dv)` at corner `k` of a triangle from the tangents `[a, b]` along its sides toward
/// the next and the previous corner: the linear map that takes the sides' parameter
/// directions (corner 0: `(1, 0)` and `(0, 1)`; corner 1: `(−1, 1)` and `(−1, 0)`; corner 2:
/// `(0, −1)` and `(1, −1)`) to them.
fn map_sides(k: usize, [a, b]: [[f64; 3]; 2]) -> ([f64; 3], [f64; 3]) {
    let lin = |x: f64, p: &[f64; 3], y: f64, q: &[f64; 3]| -> [f64; 3] {
        std::array::from_fn(|i| x * p[i] + y * q[i])
    };
    match k {
        // Corner 0: next = c₁ along (1, 0), prev = c₂ along (0, 1).
        0 => (a, b),
        // Corner 1: next = c₂ along (−1, 1), prev = c₀ along (−1, 0):
        // (1, 0) = −prev, (0, 1) = next − prev.
        1 => (lin(-1.0, &b, 0.0, &a), lin(1.0, &a, -1.0, &b)),
        // Corner 2: next = c₀ along (0, −1), prev = c₁ along (1, −1):
        // (1, 0) = prev − next, (0, 1) = −next.
        _ => (lin(1.0, &b, -1.0, &a), lin(-1.0, &a, 0.0, &b)),
    }
}

/// The corner of the triangle nearest `(u, v)`.
fn nearest_corner(u: f64, v: f64) -> usize {
    let d = [u + v, (1.0 - u) + v, u + (1.0 - v)];
    (0..3).min_by(|&a, &b| d[a].total_cmp(&d[b])).unwrap_or(0)
}

#[cfg(test)]
#[path = "loop_surface_tests.rs"]
mod tests;
