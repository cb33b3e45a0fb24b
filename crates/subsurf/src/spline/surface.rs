//! [`SubBasisSurface`]: the rational bicubic spline surface `P(u,v) = Σ ϖ_i(u,v) P_i` of a quad
//! mesh ([Sub-basis splines], eq. 12), evaluated face by face.

use super::error::SplineError;
use super::patch::{bernstein, net_index, RationalPatch, AB};
use super::subbasis::Class;
use super::table::{valence_table, ValenceTable};
use crate::limit::Derivatives;
use crate::mesh::{Options, PolyMesh, Topology};
use crate::refine::uniform::{refine_mesh, Steps};
use crate::scheme::adjustable::Mixed;
use rayon::prelude::*;
use std::borrow::Cow;
use std::collections::HashMap;
use std::sync::Arc;

/// One sub-basis piece that is non-zero on a face: its owner (the control point whose basis
/// function `W_owner` it belongs to), the face corner it is centred at, its class and its
/// Bézier coefficients `[b00, b10, b01, b11]` in that corner's rhombus coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// Control point owning the piece.
    pub owner: u32,
    /// Face corner (0..4) at whose star the piece is centred.
    pub corner: u8,
    /// Class of the piece.
    pub class: Class,
    /// Bézier coefficients (see [`super::SubBasis::bezier`]).
    pub bezier: [f64; 4],
}

#[derive(Clone, Debug)]
struct FacePatch {
    pieces: Vec<Piece>,
    patch: RationalPatch,
}

#[derive(Clone, Debug)]
enum FaceSurface {
    /// The first corner vertex whose sub-basis functions are incomplete.
    Missing(u32),
    Patch(Box<FacePatch>),
}

/// The sub-basis spline surface of a quad mesh ([Sub-basis splines]).
///
/// Every control point `P_i` of valence `n` owns a basis function `W_i` made of `2n + 1`
/// sub-basis pieces: its class-1 piece on its own star, one class-2 piece on the star of each
/// edge neighbour and one class-3 piece on the star of each diagonal neighbour (section 1.3).
/// The surface is `P = Σ ϖ_i P_i` with `ϖ_i = W_i / Σ_j W_j` (eq. 12). Over a face only the
/// pieces centred at its four corners are non-zero, so each face is one rational bicubic
/// patch (`super::patch`). On a regular mesh `Σ W_j ≡ 1` and the surface is the uniform
/// bicubic B-spline (= the Catmull-Clark limit).
///
/// Parametrisation: like [`crate::limit::LimitSurface`], a quad `[v0 v1 v2 v3]` has `(0, 0)` at
/// `v0`, `u` toward `v1`, `v` toward `v3`.
///
/// Faces without a surface: a face has a surface iff each of its four corners is an interior
/// manifold vertex of valence ≥ 3 (its star of quads is closed), since only then are all
/// sub-basis pieces on the face defined ("on faces whose sub-basis functions are incomplete
/// no surface is built", section 3, as for B-splines). On an open mesh this removes exactly
/// the faces that touch the boundary. Crease, corner and hole tags are ignored: the
/// construction has no sharp features.
///
/// ```
/// use subsurf::mesh::PolyMesh;
/// use subsurf::spline::SubBasisSurface;
/// let p = vec![
///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
/// ];
/// let f = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
/// let cube = PolyMesh::from_faces(p, &f).unwrap();
/// let s = SubBasisSurface::new(&cube).unwrap();
/// // By symmetry the centre of the top face lies above the cube's centre, normal up.
/// let d = s.eval(1, 0.5, 0.5).unwrap();
/// assert!((d.p[0] - 0.5).abs() < 1e-12 && (d.p[1] - 0.5).abs() < 1e-12);
/// assert!(d.normal()[2] > 0.999_999);
/// ```
#[derive(Clone, Debug)]
pub struct SubBasisSurface {
    num_vertices: usize,
    faces: Vec<FaceSurface>,
}

/// The quad control mesh of `mesh`: `mesh` itself when all faces are quads, otherwise the
/// result of one Catmull-Clark step (default options: edge-only boundaries), as the paper
/// prescribes (section 2). The flag says whether the step was taken. The refined mesh keeps
/// the input's vertices as its first vertices (OpenSubdiv numbering), moved by the step.
///
/// # Errors
/// [`SplineError::Mesh`] for an invalid mesh, [`SplineError::Subdivide`] if the step fails.
pub fn quad_control_mesh(mesh: &PolyMesh) -> Result<(Cow<'_, PolyMesh>, bool), SplineError> {
    mesh.validate()?;
    if mesh.faces().all(|f| f.len() == 4) {
        return Ok((Cow::Borrowed(mesh), false));
    }
    let out = refine_mesh(
        mesh,
        &Options::default(),
        Steps::Family(Mixed::CATMULL_CLARK),
        1,
        false,
    )
    .map_err(|e| SplineError::Subdivide(e.to_string()))?;
    Ok((Cow::Owned(out), true))
}

/// A [`SubBasisSurface`] of any polygon mesh, with the quad control mesh it was built on.
#[derive(Clone, Debug)]
pub struct QuadSpline {
    /// The quad control mesh: the input, or the input after one Catmull-Clark step.
    pub control: PolyMesh,
    /// Whether the Catmull-Clark step was applied (the input had non-quad faces).
    pub subdivided: bool,
    /// The surface over `control`'s faces.
    pub surface: SubBasisSurface,
}

impl QuadSpline {
    /// [`quad_control_mesh`] of `mesh`, then [`SubBasisSurface::new`] on it.
    ///
    /// # Errors
    /// As those two.
    pub fn new(mesh: &PolyMesh) -> Result<Self, SplineError> {
        let (control, subdivided) = quad_control_mesh(mesh)?;
        let control = control.into_owned();
        let surface = SubBasisSurface::new(&control)?;
        Ok(Self {
            control,
            subdivided,
            surface,
        })
    }
}

impl SubBasisSurface {
    /// Builds the surface of the quad mesh `mesh` (control points = its vertices).
    ///
    /// # Errors
    /// [`SplineError::Mesh`] for an invalid mesh, [`SplineError::NotQuad`] naming the first
    /// face that is not a quad.
    pub fn new(mesh: &PolyMesh) -> Result<Self, SplineError> {
        mesh.validate()?;
        if let Some((face, f)) = mesh.faces().enumerate().find(|(_, f)| f.len() != 4) {
            return Err(SplineError::NotQuad {
                face,
                size: f.len(),
            });
        }
        let (topo, _) = Topology::from_mesh(mesh, &Options::default())?;
        let nv = topo.num_vertices();
        // Valence of each vertex with a complete star (0 otherwise), and its tables.
        let valence: Vec<usize> = (0..nv)
            .map(|v| {
                let tag = topo.vertex_tag(v);
                let n = topo.vertex_faces(v).len();
                if tag.boundary || tag.non_manifold || n < 3 || topo.vertex_edges(v).len() != n {
                    0
                } else {
                    n
                }
            })
            .collect();
        let mut tables: HashMap<usize, Arc<ValenceTable>> = HashMap::new();
        for &n in &valence {
            if n >= 3 {
                tables
                    .entry(n)
                    .or_insert_with(|| valence_table(n).expect("n >= 3"));
            }
        }
        let pos = mesh.positions();
        let faces = (0..topo.num_faces())
            .into_par_iter()
            .map(|f| build_face(&topo, pos, &valence, &tables, f))
            .collect();
        Ok(Self {
            num_vertices: nv,
            faces,
        })
    }

    /// Number of faces of the control mesh.
    pub fn num_faces(&self) -> usize {
        self.faces.len()
    }

    /// Number of control points.
    pub fn num_vertices(&self) -> usize {
        self.num_vertices
    }

    /// Whether face `f` has a surface (see the type docs).
    pub fn has_surface(&self, f: usize) -> bool {
        matches!(self.faces.get(f), Some(FaceSurface::Patch(_)))
    }

    #[inline]
    fn face(&self, face: u32, u: f64, v: f64) -> Result<&FacePatch, SplineError> {
        let fs = self
            .faces
            .get(face as usize)
            .ok_or(SplineError::NoSuchFace {
                face,
                count: self.faces.len(),
            })?;
        if !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v) {
            return Err(SplineError::BadParameter { u, v });
        }
        match fs {
            FaceSurface::Patch(p) => Ok(p),
            FaceSurface::Missing(vertex) => Err(SplineError::NoSurface {
                face,
                vertex: *vertex,
            }),
        }
    }

    /// Position and first and second derivatives at `(u, v)` of `face`, differentiating the
    /// rational form `N/D` exactly.
    ///
    /// # Errors
    /// [`SplineError::NoSuchFace`], [`SplineError::NoSurface`], [`SplineError::BadParameter`].
    #[inline]
    pub fn eval(&self, face: u32, u: f64, v: f64) -> Result<Derivatives, SplineError> {
        Ok(self.face(face, u, v)?.patch.eval(u, v))
    }

    /// Position only at `(u, v)` of `face`.
    ///
    /// # Errors
    /// As [`eval`](Self::eval).
    pub fn position(&self, face: u32, u: f64, v: f64) -> Result<[f64; 3], SplineError> {
        Ok(self.face(face, u, v)?.patch.position(u, v))
    }

    /// [`eval`](Self::eval) at many `(face, u, v)` points, in parallel (rayon).
    pub fn eval_many(&self, points: &[(u32, f64, f64)]) -> Vec<Result<Derivatives, SplineError>> {
        points
            .par_iter()
            .map(|&(f, u, v)| self.eval(f, u, v))
            .collect()
    }

    /// The rational Bézier patch of `face` (`None` without a surface or out of range).
    pub fn patch(&self, face: usize) -> Option<&RationalPatch> {
        match self.faces.get(face) {
            Some(FaceSurface::Patch(p)) => Some(&p.patch),
            _ => None,
        }
    }

    /// The sub-basis pieces that are non-zero on `face` (empty without a surface).
    pub fn pieces(&self, face: usize) -> &[Piece] {
        match self.faces.get(face) {
            Some(FaceSurface::Patch(p)) => &p.pieces,
            _ => &[],
        }
    }

    /// The un-normalised basis functions `W_i(u, v)` that are non-zero on `face`, as
    /// `(control point, W_i)` sorted by control point: each the sum of its pieces there.
    ///
    /// # Errors
    /// As [`eval`](Self::eval).
    pub fn basis_values(&self, face: u32, u: f64, v: f64) -> Result<Vec<(u32, f64)>, SplineError> {
        let fp = self.face(face, u, v)?;
        let (bu, _, _) = bernstein(u);
        let (bv, _, _) = bernstein(v);
        let mut out: Vec<(u32, f64)> = fp
            .pieces
            .iter()
            .map(|pc| {
                let mut s = 0.0;
                for (q, &(a, b)) in AB.iter().enumerate() {
                    let (i, j) = net_index(pc.corner as usize, a, b);
                    s += pc.bezier[q] * bu[i] * bv[j];
                }
                (pc.owner, s)
            })
            .collect();
        out.sort_by_key(|x| x.0);
        out.dedup_by(|b, a| {
            if a.0 == b.0 {
                a.1 += b.1;
                true
            } else {
                false
            }
        });
        Ok(out)
    }

    /// The normalised basis functions `ϖ_i = W_i / Σ_j W_j` (eq. 12) non-zero on `face`, as
    /// `(control point, ϖ_i)` sorted by control point; they sum to 1.
    ///
    /// # Errors
    /// As [`eval`](Self::eval).
    pub fn weights(&self, face: u32, u: f64, v: f64) -> Result<Vec<(u32, f64)>, SplineError> {
        let mut w = self.basis_values(face, u, v)?;
        let total: f64 = w.iter().map(|x| x.1).sum();
        for x in &mut w {
            x.1 /= total;
        }
        Ok(w)
    }

    /// `ϖ_vertex(u, v)` on `face` (0 where the vertex's basis function does not reach).
    ///
    /// # Errors
    /// [`SplineError::NoSuchVertex`], and as [`eval`](Self::eval).
    pub fn weight_of(&self, vertex: u32, face: u32, u: f64, v: f64) -> Result<f64, SplineError> {
        if vertex as usize >= self.num_vertices {
            return Err(SplineError::NoSuchVertex {
                vertex,
                count: self.num_vertices,
            });
        }
        Ok(self
            .weights(face, u, v)?
            .iter()
            .find(|x| x.0 == vertex)
            .map_or(0.0, |x| x.1))
    }
}

/// The pieces and rational patch of face `f`, or the first corner with an incomplete star.
fn build_face(
    topo: &Topology,
    pos: &[[f64; 3]],
    valence: &[usize],
    tables: &HashMap<usize, Arc<ValenceTable>>,
    f: usize,
) -> FaceSurface {
    let fv = topo.face_vertices(f);
    if let Some(&v) = fv.iter().find(|&&v| valence[v as usize] == 0) {
        return FaceSurface::Missing(v);
    }
    let mut pieces = Vec::with_capacity(fv.iter().map(|&v| 1 + 2 * valence[v as usize]).sum());
    for (j, &v) in fv.iter().enumerate() {
        let v = v as usize;
        let n = valence[v];
        let t = &tables[&n];
        let vf = topo.vertex_faces(v);
        let vl = topo.vertex_face_locals(v);
        let k = match (0..n).find(|&i| vf[i] as usize == f && vl[i] as usize == j) {
            Some(k) => k,
            None => return FaceSurface::Missing(v as u32),
        };
        pieces.push(Piece {
            owner: v as u32,
            corner: j as u8,
            class: Class::Centre,
            bezier: t.centre.bezier(k),
        });
        for (m, owner) in topo.vertex_neighbours(v).enumerate() {
            pieces.push(Piece {
                owner,
                corner: j as u8,
                class: Class::Edge,
                bezier: t.edge.bezier((k + n - m) % n),
            });
        }
        for m in 0..n {
            let g = topo.face_vertices(vf[m] as usize);
            let owner = g[(vl[m] as usize + 2) % 4];
            pieces.push(Piece {
                owner,
                corner: j as u8,
                class: Class::Corner,
                bezier: t.corner.bezier((k + n - m) % n),
            });
        }
    }
    let mut net = [[[0.0f64; 4]; 4]; 4];
    for pc in &pieces {
        let p = pos[pc.owner as usize];
        for (q, &(a, b)) in AB.iter().enumerate() {
            let (i, jj) = net_index(pc.corner as usize, a, b);
            let c = pc.bezier[q];
            let h = &mut net[i][jj];
            h[0] += c * p[0];
            h[1] += c * p[1];
            h[2] += c * p[2];
            h[3] += c;
        }
    }
    FaceSurface::Patch(Box::new(FacePatch {
        pieces,
        patch: RationalPatch { net },
    }))
}

/// The sub-basis spline surface in the vocabulary of every surface: a face without a surface
/// (a corner the spline does not cover) reads as a hole.
impl crate::limit::Surface for SubBasisSurface {
    fn num_faces(&self) -> usize {
        SubBasisSurface::num_faces(self)
    }

    /// 1 for every face: the control mesh is all quads.
    fn num_subfaces(&self, f: usize) -> usize {
        usize::from(f < self.num_faces())
    }

    fn has_surface(&self, f: usize) -> bool {
        SubBasisSurface::has_surface(self, f)
    }

    fn evaluate(
        &self,
        p: crate::limit::SurfacePoint,
    ) -> Result<Derivatives, crate::limit::EvalError> {
        use crate::limit::EvalError;
        self.eval(p.face, p.u, p.v).map_err(|e| match e {
            SplineError::NoSurface { face, .. } => EvalError::Hole { face },
            SplineError::NoSuchFace { face, count } => EvalError::NoSuchFace { face, count },
            _ => EvalError::BadParameter { u: p.u, v: p.v },
        })
    }
}
