//! [`tessellate`]: a watertight polygon mesh sampled from any [`Surface`] (the exact limit
//! surface, the mixed, G2 and sub-basis spline surfaces, the exact faces of NURSS).
//!
//! See [`tessellate`] for the grid, the sharing of samples, normals and limits.

use super::bspline::{Derivatives, Order};
use super::eval::{Domain, Surface};
use super::surface::{EvalError, LimitSurface, SurfacePoint};
use crate::mesh::{FaceVarying, MeshError, Options, PolyMesh, Topology, INVALID};

/// The largest number of output vertices [`tessellate`] accepts (2³¹).
pub const MAX_TESSELLATION_VERTICES: u64 = 1 << 31;

/// Points evaluated per call of [`Surface::evaluate_many`].
const CHUNK: usize = 1 << 16;

/// A polygon mesh sampled from a surface. See [`tessellate`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tessellation {
    /// The rate actually used: samples per base edge (the requested rate, rounded up to
    /// even when an `n`-gon has a surface).
    pub rate: u32,
    /// Vertex positions on the surface.
    pub positions: Vec<[f64; 3]>,
    /// Unit vertex normals (`[0, 0, 0]` only where no normal exists, see [`tessellate`]).
    pub normals: Vec<[f64; 3]>,
    /// CSR offsets of the output faces (`num_faces() + 1` entries).
    pub face_offsets: Vec<u32>,
    /// CSR vertex indices of the output faces: quads, or triangles with `triangles` (and
    /// always on triangle domains), counter-clockwise like their base faces.
    pub face_verts: Vec<u32>,
    /// Per output face, the base face and sub-face (0 for quads) it samples.
    pub source: Vec<(u32, u32)>,
    /// Per vertex, the point of the surface it was evaluated at (by its owner, see
    /// [`tessellate`]), e.g. to evaluate more data there (a basis function, texture
    /// coordinates). Empty for a tessellation sampled through refinement
    /// ([`nonuniform::tessellate`](crate::nonuniform::tessellate())).
    pub points: Vec<SurfacePoint>,
    /// Face-varying channels of the output faces (texture coordinates, named `"uv"`), from
    /// [`evaluate_face_varying`](Self::evaluate_face_varying); empty unless added.
    pub face_varying: Vec<FaceVarying>,
}

impl Tessellation {
    /// Number of output vertices.
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }

    /// Number of output faces.
    pub fn num_faces(&self) -> usize {
        self.face_offsets.len().saturating_sub(1)
    }

    /// The vertices of output face `f`.
    ///
    /// # Panics
    /// If `f >= num_faces()`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.face_verts[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// The tessellation as a [`PolyMesh`] (without tags, with its face-varying channels),
    /// e.g. for
    /// [`write_obj`](crate::io::obj::write_obj) with [`normals`](Self::normals).
    ///
    /// # Errors
    /// [`MeshError`] from [`PolyMesh::new`]'s validation (a tessellation produced by
    /// [`tessellate`] always passes).
    pub fn to_polymesh(&self) -> Result<PolyMesh, MeshError> {
        let mut mesh = PolyMesh::new(
            self.positions.clone(),
            self.face_offsets.clone(),
            self.face_verts.clone(),
        )?;
        mesh.face_varying = self.face_varying.clone();
        mesh.validate()?;
        Ok(mesh)
    }
}

/// Errors of [`tessellate`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TessellateError {
    /// `rate` was 0.
    #[error("the tessellation rate must be at least 1")]
    ZeroRate,
    /// The mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The surface was not built from this mesh.
    #[error(
        "the limit surface does not belong to the mesh (face {face}: {surface} sub-faces in the \
         surface, {mesh} vertices in the mesh)"
    )]
    Mismatch {
        /// First face that differs.
        face: usize,
        /// Sub-faces of the surface's face (0 when it has no such face).
        surface: usize,
        /// Vertices of the mesh's face (0 when it has no such face).
        mesh: usize,
    },
    /// The output would be too large.
    #[error(
        "a tessellation at rate {rate} would have {vertices} vertices and {faces} faces \
         ({face_verts} face-vertex indices); the limit is {limit} vertices and {max_face_verts} \
         indices: lower the rate"
    )]
    TooLarge {
        /// Rate (after rounding up to even, see [`Tessellation::rate`]).
        rate: u64,
        /// Estimated output vertices.
        vertices: u128,
        /// Estimated output faces.
        faces: u128,
        /// Estimated face-vertex indices.
        face_verts: u128,
        /// [`MAX_TESSELLATION_VERTICES`].
        limit: u64,
        /// `u32::MAX`.
        max_face_verts: u64,
    },
    /// The tessellation keeps no surface points (it was sampled through refinement), so
    /// nothing can be evaluated at its corners.
    #[error(
        "the tessellation was sampled through refinement and keeps no surface points to \
         evaluate more data at"
    )]
    NoCornerPoints,
    /// The tessellation's faces are not laid out as [`tessellate`] lays out the mesh's.
    #[error("output face {face} is not where tessellating this mesh puts it (another mesh's tessellation?)")]
    Layout {
        /// First output face out of place.
        face: usize,
    },
    /// Evaluation failed at a sample (not expected for a surface built from the mesh).
    #[error("evaluating face {face}, sub-face {subface} at ({u}, {v}): {source}")]
    Eval {
        /// Face.
        face: u32,
        /// Sub-face.
        subface: u32,
        /// `u`.
        u: f64,
        /// `v`.
        v: f64,
        /// The evaluator's error.
        source: EvalError,
    },
}

/// Builds the limit surface of `mesh` with `options` and [`tessellate`]s it.
///
/// ```
/// use subsurf::limit::tessellate_mesh;
/// use subsurf::mesh::{Options, PolyMesh};
/// let p = vec![
///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
/// ];
/// let f = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
/// let cube = PolyMesh::from_faces(p, &f).unwrap();
/// let t = tessellate_mesh(&cube, &Options::default(), 4, false).unwrap();
/// // 6 faces of 4 × 4 quads; vertices shared along edges and at corners (Euler: V = F + 2).
/// assert_eq!(t.num_faces(), 6 * 16);
/// assert_eq!(t.num_vertices(), 6 * 16 + 2);
/// ```
///
/// # Errors
/// As [`tessellate`], and [`MeshError`] when the mesh is invalid.
pub fn tessellate_mesh(
    mesh: &PolyMesh,
    options: &Options,
    rate: u32,
    triangles: bool,
) -> Result<Tessellation, TessellateError> {
    if rate == 0 {
        return Err(TessellateError::ZeroRate);
    }
    let surface = LimitSurface::new(mesh, *options)?;
    tessellate(&surface, mesh, rate, triangles)
}

/// Samples `surface` (built from `mesh`, which gives the adjacency) on a watertight grid of
/// `rate` segments per base edge. Any [`Surface`] is tessellated the same way: the exact
/// Catmull-Clark and Loop limit surfaces, the mixed, G2 and sub-basis spline surfaces, a
/// NURSS surface that is exact on every face.
///
/// # Grid
/// Every quad face with a surface becomes a `rate × rate` grid of quads, sampled at
/// `u = i / rate`, `v = j / rate` in the face's parametrisation (see
/// [`Parameterization`](super::Parameterization)).
/// An `n`-gon (`n ≠ 4`) is evaluated through its `n` quad sub-faces, each of which covers
/// *half* of two of the face's edges; so that every base edge is cut into the same number
/// of segments on both of its sides, a mesh in which any non-quad face has a surface is
/// tessellated at an **even** rate (an odd `rate` is rounded up, see
/// [`Tessellation::rate`]): quads get a `rate × rate` grid, sub-faces a
/// `rate/2 × rate/2` grid. This is the grid of the once-refined mesh (all quads, the same
/// limit surface) at `rate / 2`. Every base edge therefore has `rate` segments, sampled at
/// the same points of the limit surface from either side.
///
/// Output faces come in base face order (sub-faces in order), each grid by rows of
/// cells from `v = 0`, each row from `u = 0`; the cell at `(a, b)` is the quad of the
/// samples `(a, b)`, `(a + 1, b)`, `(a + 1, b + 1)`, `(a, b + 1)` (counter-clockwise like
/// its base face, in units of `1 / rate`, or of `2 / rate` on a sub-face).
///
/// A face whose domain is a triangle ([`Domain::Triangle`]: every face of a
/// [`LoopSurface`](super::LoopSurface)) is sampled at `u = a / rate`, `v = b / rate` with
/// `a + b ≤ rate`, and becomes the `rate²` triangles of that grid, by rows of constant
/// `v` from `v = 0`: in row `b`, for `a = 0, 1, …, rate − b − 1`, the triangle `(a, b)`,
/// `(a + 1, b)`, `(a, b + 1)` and, unless it is the row's last, `(a + 1, b)`,
/// `(a + 1, b + 1)`, `(a, b + 1)` (counter-clockwise like the base triangle). Its edges
/// have `rate` segments too, so it meets any neighbour watertight.
///
/// Faces without a surface (holes, and the faces that
/// [`BoundaryInterpolation::None`](crate::mesh::BoundaryInterpolation::None) drops) produce
/// nothing.
///
/// # Watertightness
/// Samples on the boundary of a grid are shared: each base vertex, each interior sample
/// of a base edge, and each sample on the boundary between two sub-faces of an `n`-gon is
/// evaluated **once**, from its owner (the lowest-numbered face with a surface that
/// contains it; for a spoke between sub-faces `j` and `j + 1`, sub-face `j`), and becomes
/// one output vertex used by every face around it. Positions are thus bit-identical and
/// indices shared: on a closed manifold input the output is a closed 2-manifold, and its
/// boundary loops run along the input's boundary edges. Neighbouring faces that run an
/// edge in opposite directions see its samples in reverse order.
///
/// # Normals
/// One normal per vertex: [`Derivatives::normal`] of the owner's evaluation (at a sharp
/// feature the normal is that of the owner's side of it). Where it is zero (degenerate
/// derivatives, e.g. coincident control points), the normalised sum of the area-weighted
/// normals of the output faces around the vertex is used; where that is zero too (all of
/// them degenerate) the normal is `[0, 0, 0]`. Normals are never NaN.
///
/// # Triangles
/// With `triangles`, each output quad `a b c d` is split into two triangles of the same
/// orientation, along its shorter diagonal in space (`a c` when both are equally long) —
/// except at a vertex with only two quads around it (at a base vertex of valence 2), where
/// the two quads share two sides: both are split through that vertex, as otherwise they
/// would give two triangles on the same three vertices. The triangles of triangle domains
/// are output as they are, with or without `triangles`.
///
/// # Cost
/// Evaluation runs in parallel ([`Surface::evaluate_many`]) in chunks; memory is about
/// 72 bytes per output vertex and 28 per output quad (24 per triangle). More than
/// [`MAX_TESSELLATION_VERTICES`] output vertices (or more face-vertex indices than `u32`
/// can count) are refused with [`TessellateError::TooLarge`], with the exact counts,
/// before any work.
///
/// # Errors
/// [`TessellateError::ZeroRate`], [`TessellateError::Mismatch`] when `surface` has another
/// face structure than `mesh`, [`TessellateError::TooLarge`] (with the estimate) when the
/// output would exceed [`MAX_TESSELLATION_VERTICES`], [`MeshError`] for an invalid mesh,
/// [`TessellateError::Eval`] when a sample cannot be evaluated (a NURSS face without an
/// exact evaluation).
pub fn tessellate<S: Surface + ?Sized>(
    surface: &S,
    mesh: &PolyMesh,
    rate: u32,
    triangles: bool,
) -> Result<Tessellation, TessellateError> {
    if rate == 0 {
        return Err(TessellateError::ZeroRate);
    }
    check_match(surface, mesh)?;
    // The adjacency only: the scheme's options play no part in it.
    let (topo, _) = Topology::from_mesh(mesh, &Options::default())?;
    let live: Vec<bool> = (0..topo.num_faces())
        .map(|f| surface.has_surface(f))
        .collect();
    let tri: Vec<bool> = (0..topo.num_faces())
        .map(|f| surface.domain(f) == Domain::Triangle)
        .collect();
    let has_ngon =
        (0..topo.num_faces()).any(|f| live[f] && !tri[f] && topo.face_vertices(f).len() != 4);
    let rate = if has_ngon && rate % 2 == 1 {
        // Only u32::MAX is odd and cannot be rounded up; the size guard refuses it anyway.
        rate.checked_add(1).unwrap_or(rate)
    } else {
        rate
    };
    estimate(&topo, &live, &tri, rate, triangles)?;

    let g = Grid::number(&topo, &live, tri, rate);
    let (positions, mut normals) = evaluate(surface, &g.points)?;
    let mut cells = g.cells(&topo, &live);
    if triangles {
        cells = cells.split(&positions);
    }
    let Cells {
        offsets: face_offsets,
        verts: face_verts,
        source,
    } = cells;
    fix_normals(&mut normals, &positions, &face_offsets, &face_verts);
    Ok(Tessellation {
        rate,
        positions,
        normals,
        face_offsets,
        face_verts,
        source,
        points: g.points,
        face_varying: Vec::new(),
    })
}

fn check_match<S: Surface + ?Sized>(surface: &S, mesh: &PolyMesh) -> Result<(), TessellateError> {
    for f in 0..mesh.num_faces().max(surface.num_faces()) {
        let size = if f < mesh.num_faces() {
            mesh.face(f).len()
        } else {
            0
        };
        // A triangle domain is one triangle; a quad domain is a quad or the sub-faces of
        // an n-gon.
        let tri = surface.domain(f) == Domain::Triangle;
        let expect = if size == 4 || tri { 1 } else { size };
        if surface.num_subfaces(f) != expect || (tri && size != 3 && size != 0) {
            return Err(TessellateError::Mismatch {
                face: f,
                surface: surface.num_subfaces(f),
                mesh: size,
            });
        }
    }
    Ok(())
}

/// Refuses outputs beyond [`MAX_TESSELLATION_VERTICES`] or `u32` face-vertex indices, before any
/// allocation. The counts are exact (the numbering below produces exactly these).
fn estimate(
    topo: &Topology,
    live: &[bool],
    tri: &[bool],
    rate: u32,
    triangles: bool,
) -> Result<(), TessellateError> {
    let r = u128::from(rate);
    let mut used_v = vec![false; topo.num_vertices()];
    let mut used_e = vec![false; topo.num_edges()];
    // Interior samples, quads and triangles of triangle domains.
    let (mut interior, mut faces, mut tris) = (0u128, 0u128, 0u128);
    for f in (0..topo.num_faces()).filter(|&f| live[f]) {
        let fv = topo.face_vertices(f);
        fv.iter().for_each(|&v| used_v[v as usize] = true);
        topo.face_edge_list(f)
            .iter()
            .for_each(|&e| used_e[e as usize] = true);
        let n = fv.len() as u128;
        if tri[f] {
            interior += (r - 1) * r.saturating_sub(2) / 2;
            tris += r * r;
        } else if fv.len() == 4 {
            interior += (r - 1) * (r - 1);
            faces += r * r;
        } else {
            let s = r / 2;
            interior += 1 + n * (s - 1) + n * (s - 1) * (s - 1);
            faces += n * s * s;
        }
    }
    let count = |u: &[bool]| u.iter().filter(|&&x| x).count() as u128;
    let vertices = count(&used_v) + count(&used_e) * (r - 1) + interior;
    let (faces, face_verts) = if triangles {
        (2 * faces + tris, 6 * faces + 3 * tris)
    } else {
        (faces + tris, 4 * faces + 3 * tris)
    };
    if vertices > u128::from(MAX_TESSELLATION_VERTICES) || face_verts > u128::from(u32::MAX) {
        return Err(TessellateError::TooLarge {
            rate: u64::from(rate),
            vertices,
            faces,
            face_verts,
            limit: MAX_TESSELLATION_VERTICES,
            max_face_verts: u64::from(u32::MAX),
        });
    }
    Ok(())
}

/// The numbering of the samples: which output vertex each grid point of each face is.
struct Grid {
    /// Samples per base edge.
    r: u32,
    /// Per base vertex, its output vertex ([`INVALID`] when no face with a surface uses it).
    vert: Vec<u32>,
    /// Per base edge, the output vertex of its first interior sample; sample `k`
    /// (`1 ≤ k < r`, at `k / r` from `edge_vertices[0]` to `[1]`) is `edge[e] + k - 1`.
    edge: Vec<u32>,
    /// Per base face, the output vertex of its first interior sample (see
    /// [`Grid::number`], which pushes them row by row).
    face: Vec<u32>,
    /// Per output vertex, where its owner evaluates it.
    points: Vec<SurfacePoint>,
    /// Per base face, whether its domain is a triangle ([`Domain::Triangle`]).
    tri: Vec<bool>,
}

/// Output polygons: CSR offsets and vertices, and per polygon its base face and sub-face.
struct Cells {
    offsets: Vec<u32>,
    verts: Vec<u32>,
    source: Vec<(u32, u32)>,
}

fn param(k: u32, n: u32) -> f64 {
    f64::from(k) / f64::from(n)
}

fn point(face: usize, subface: usize, u: f64, v: f64) -> SurfacePoint {
    SurfacePoint {
        face: face as u32,
        subface: subface as u32,
        u,
        v,
    }
}

impl Grid {
    /// Numbers every sample, faces in order, each at first sight (so its owner is the
    /// lowest-numbered face with a surface that contains it), and records where to
    /// evaluate it.
    fn number(topo: &Topology, live: &[bool], tri: Vec<bool>, r: u32) -> Self {
        let mut g = Grid {
            r,
            vert: vec![INVALID; topo.num_vertices()],
            edge: vec![INVALID; topo.num_edges()],
            face: vec![INVALID; topo.num_faces()],
            points: Vec::new(),
            tri,
        };
        for f in (0..topo.num_faces()).filter(|&f| live[f]) {
            let fv = topo.face_vertices(f);
            let fe = topo.face_edge_list(f);
            let n = fv.len();
            for i in 0..n {
                let v = fv[i] as usize;
                if g.vert[v] == INVALID {
                    g.vert[v] = g.points.len() as u32;
                    g.points.push(g.boundary_point(f, n, i, 0));
                }
            }
            for i in 0..n {
                let e = fe[i] as usize;
                if g.edge[e] == INVALID && r > 1 {
                    g.edge[e] = g.points.len() as u32;
                    let forward = forward(topo, f, i);
                    for k in 1..r {
                        let m = if forward { k } else { r - k };
                        g.points.push(g.boundary_point(f, n, i, m));
                    }
                }
            }
            g.face[f] = g.points.len() as u32;
            if g.tri[f] {
                for b in 1..r {
                    for a in 1..r - b {
                        g.points.push(point(f, 0, param(a, r), param(b, r)));
                    }
                }
            } else if n == 4 {
                for b in 1..r {
                    for a in 1..r {
                        g.points.push(point(f, 0, param(a, r), param(b, r)));
                    }
                }
            } else {
                let s = r / 2;
                g.points.push(point(f, 0, 1.0, 1.0));
                for j in 0..n {
                    for k in 1..s {
                        g.points.push(point(f, j, 1.0, param(k, s)));
                    }
                }
                for j in 0..n {
                    for b in 1..s {
                        for a in 1..s {
                            g.points.push(point(f, j, param(a, s), param(b, s)));
                        }
                    }
                }
            }
        }
        g
    }

    /// The sample `m` of `r` along edge `i` of face `f` (of `n` vertices), in the face's
    /// direction: `m = 0` at vertex `i`, `m = r` at vertex `i + 1`.
    fn boundary_point(&self, f: usize, n: usize, i: usize, m: u32) -> SurfacePoint {
        let r = self.r;
        let t = param(m, r);
        let t_rev = param(r - m, r);
        if self.tri[f] {
            // Edge 1 runs from (1, 0) to (0, 1), edge 2 down the v axis.
            return match i {
                0 => point(f, 0, t, 0.0),
                1 => point(f, 0, t_rev, t),
                _ => point(f, 0, 0.0, t_rev),
            };
        }
        if n == 4 {
            return match i {
                0 => point(f, 0, t, 0.0),
                1 => point(f, 0, 1.0, t),
                2 => point(f, 0, t_rev, 1.0),
                _ => point(f, 0, 0.0, t_rev),
            };
        }
        // Sub-face i covers the first half (along u), sub-face i + 1 the second (along v,
        // from the vertex i + 1 back to the edge's midpoint).
        let s = r / 2;
        if m <= s {
            point(f, i, param(m, s), 0.0)
        } else {
            point(f, (i + 1) % n, 0.0, param(r - m, s))
        }
    }

    /// Output vertex of sample `m` of `r` along edge `i` of face `f`, in the face's
    /// direction.
    fn on_edge(&self, topo: &Topology, f: usize, i: usize, m: u32) -> u32 {
        let fv = topo.face_vertices(f);
        let r = self.r;
        if m == 0 {
            return self.vert[fv[i] as usize];
        }
        if m == r {
            return self.vert[fv[(i + 1) % fv.len()] as usize];
        }
        let e = topo.face_edge_list(f)[i] as usize;
        let k = if forward(topo, f, i) { m } else { r - m };
        self.edge[e] + k - 1
    }

    /// Output vertex of sample `k` of `s` along spoke `j` of `n`-gon `f` (from the
    /// midpoint of edge `j`, `k = 0`, to the centre, `k = s`).
    fn on_spoke(&self, topo: &Topology, f: usize, j: usize, k: u32) -> u32 {
        let s = self.r / 2;
        if k == 0 {
            return self.on_edge(topo, f, j, s);
        }
        if k == s {
            return self.face[f];
        }
        self.face[f] + 1 + j as u32 * (s - 1) + (k - 1)
    }

    /// The output vertices of the `(s + 1)²` grid points of sub-face `j` of face `f`
    /// (`(a, b)` at `b * (s + 1) + a`; on a triangle domain only those with `a + b ≤ s`,
    /// the others [`INVALID`]).
    fn patch(&self, topo: &Topology, f: usize, j: usize, out: &mut Vec<u32>) -> u32 {
        let n = topo.face_vertices(f).len();
        let r = self.r;
        out.clear();
        if self.tri[f] {
            out.resize(((r + 1) * (r + 1)) as usize, INVALID);
            let mut interior = self.face[f];
            for b in 0..=r {
                for a in 0..=r - b {
                    out[(b * (r + 1) + a) as usize] = if b == 0 {
                        self.on_edge(topo, f, 0, a)
                    } else if a + b == r {
                        self.on_edge(topo, f, 1, b)
                    } else if a == 0 {
                        self.on_edge(topo, f, 2, r - b)
                    } else {
                        interior += 1;
                        interior - 1
                    };
                }
            }
            return r;
        }
        if n == 4 {
            let w = r - 1;
            for b in 0..=r {
                for a in 0..=r {
                    out.push(if b == 0 {
                        self.on_edge(topo, f, 0, a)
                    } else if a == r {
                        self.on_edge(topo, f, 1, b)
                    } else if b == r {
                        self.on_edge(topo, f, 2, r - a)
                    } else if a == 0 {
                        self.on_edge(topo, f, 3, r - b)
                    } else {
                        self.face[f] + (b - 1) * w + (a - 1)
                    });
                }
            }
            return r;
        }
        let s = r / 2;
        let prev = (j + n - 1) % n;
        let w = s.saturating_sub(1);
        let first = self.face[f] + 1 + n as u32 * w + j as u32 * w * w;
        for b in 0..=s {
            for a in 0..=s {
                out.push(if b == 0 {
                    self.on_edge(topo, f, j, a)
                } else if a == 0 {
                    self.on_edge(topo, f, prev, r - b)
                } else if a == s {
                    self.on_spoke(topo, f, j, b)
                } else if b == s {
                    self.on_spoke(topo, f, prev, a)
                } else {
                    first + (b - 1) * w + (a - 1)
                });
            }
        }
        s
    }

    /// The output polygons, in base face order, sub-faces in order, each grid by rows of
    /// constant `v` from `v = 0`: on a quad domain the quads along `u`, on a triangle
    /// domain the triangles along `u` (see [`tessellate`]).
    fn cells(&self, topo: &Topology, live: &[bool]) -> Cells {
        let mut verts = Vec::new();
        let mut source = Vec::new();
        let mut offsets = vec![0u32];
        let mut grid = Vec::new();
        let mut push = |poly: &[u32], f: usize, j: usize| {
            verts.extend_from_slice(poly);
            offsets.push(verts.len() as u32);
            source.push((f as u32, j as u32));
        };
        for f in (0..topo.num_faces()).filter(|&f| live[f]) {
            let n = topo.face_vertices(f).len();
            if self.tri[f] {
                let s = self.patch(topo, f, 0, &mut grid) as usize;
                let at = |a: usize, b: usize| grid[b * (s + 1) + a];
                for b in 0..s {
                    for a in 0..s - b {
                        push(&[at(a, b), at(a + 1, b), at(a, b + 1)], f, 0);
                        if a + 1 < s - b {
                            push(&[at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)], f, 0);
                        }
                    }
                }
                continue;
            }
            let subfaces = if n == 4 { 1 } else { n };
            for j in 0..subfaces {
                let s = self.patch(topo, f, j, &mut grid) as usize;
                let at = |a: usize, b: usize| grid[b * (s + 1) + a];
                for b in 0..s {
                    for a in 0..s {
                        let quad = [at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)];
                        push(&quad, f, j);
                    }
                }
            }
        }
        Cells {
            offsets,
            verts,
            source,
        }
    }
}

impl Cells {
    /// Splits each quad `a b c d` into two triangles (triangles are kept): through a
    /// corner that has only two quads around it (where two quads share two sides, and
    /// splitting both along the other diagonal would put two triangles on the same three
    /// vertices), else along the shorter diagonal (`a c` on a tie).
    fn split(self, pos: &[[f64; 3]]) -> Self {
        let polys = || {
            self.offsets
                .windows(2)
                .map(|w| &self.verts[w[0] as usize..w[1] as usize])
        };
        let mut valence = vec![0u8; pos.len()];
        for &v in polys().filter(|p| p.len() == 4).flatten() {
            valence[v as usize] = valence[v as usize].saturating_add(1);
        }
        let mut verts = Vec::with_capacity(self.verts.len() / 4 * 6);
        let mut source = Vec::with_capacity(2 * self.source.len());
        for (q, &src) in polys().zip(&self.source) {
            if q.len() != 4 {
                verts.extend_from_slice(q);
                source.push(src);
                continue;
            }
            let two = |k: usize| valence[q[k] as usize] == 2;
            let d02 = dist2(&pos[q[0] as usize], &pos[q[2] as usize]);
            let d13 = dist2(&pos[q[1] as usize], &pos[q[3] as usize]);
            let along02 = if two(0) || two(2) {
                true
            } else if two(1) || two(3) {
                false
            } else {
                d02 <= d13
            };
            if along02 {
                verts.extend_from_slice(&[q[0], q[1], q[2], q[0], q[2], q[3]]);
            } else {
                verts.extend_from_slice(&[q[0], q[1], q[3], q[1], q[2], q[3]]);
            }
            source.extend([src, src]);
        }
        let offsets = (0..=source.len()).map(|f| (3 * f) as u32).collect();
        Cells {
            offsets,
            verts,
            source,
        }
    }
}

/// Whether face `f` runs its edge `i` from the edge's first vertex to its second.
fn forward(topo: &Topology, f: usize, i: usize) -> bool {
    let e = topo.face_edge_list(f)[i] as usize;
    topo.edge_vertices(e)[0] == topo.face_vertices(f)[i]
}

fn dist2(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}

/// Positions and normals of `points`, evaluated in parallel chunks.
#[allow(clippy::type_complexity)]
fn evaluate<S: Surface + ?Sized>(
    surface: &S,
    points: &[SurfacePoint],
) -> Result<(Vec<[f64; 3]>, Vec<[f64; 3]>), TessellateError> {
    let mut positions = Vec::with_capacity(points.len());
    let mut normals = Vec::with_capacity(points.len());
    let mut results = Vec::new();
    for chunk in points.chunks(CHUNK) {
        // Normals need first derivatives only.
        results.clear();
        results.resize(chunk.len(), Ok(Derivatives::default()));
        surface.evaluate_many(chunk, Order::First, &mut results);
        for (p, d) in chunk.iter().zip(results.drain(..)) {
            let d: Derivatives = d.map_err(|source| TessellateError::Eval {
                face: p.face,
                subface: p.subface,
                u: p.u,
                v: p.v,
                source,
            })?;
            positions.push(d.p);
            normals.push(d.normal());
        }
    }
    Ok((positions, normals))
}

/// Replaces zero (or non-finite) normals by the normalised sum of the cross-product
/// (area-weighted) normals of the output faces around the vertex, or zero.
fn fix_normals(normals: &mut [[f64; 3]], pos: &[[f64; 3]], offsets: &[u32], verts: &[u32]) {
    let bad = |n: &[f64; 3]| !n.iter().all(|x| x.is_finite()) || n.iter().all(|&x| x == 0.0);
    if !normals.iter().any(bad) {
        return;
    }
    let fix: Vec<bool> = normals.iter().map(bad).collect();
    let mut acc = vec![[0.0f64; 3]; normals.len()];
    for w in offsets.windows(2) {
        let fv = &verts[w[0] as usize..w[1] as usize];
        if !fv.iter().any(|&v| fix[v as usize]) {
            continue;
        }
        // Newell's normal: twice the area vector of the (possibly non-planar) polygon.
        let nrm = crate::geom::newell_normal(pos, fv);
        for &v in fv {
            if fix[v as usize] {
                (0..3).for_each(|k| acc[v as usize][k] += nrm[k]);
            }
        }
    }
    for (v, n) in normals.iter_mut().enumerate() {
        if fix[v] {
            *n = crate::geom::normalize_or_zero(acc[v]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::LoopSurface;
    use super::*;
    use crate::mesh::{Crease, Tags};

    /// Every grid point of every (sub-)face, evaluated from that face itself, is where the
    /// shared output vertex the numbering assigns to it lies: the mapping of samples
    /// between neighbours (orientation, half-edges of n-gons, spokes) is right.
    fn check_grid(mesh: &PolyMesh, options: Options, rate: u32) {
        let surface = LimitSurface::new(mesh, options).unwrap();
        check_surface_grid(&surface, mesh, options, rate);
    }

    fn check_surface_grid(surface: &dyn Surface, mesh: &PolyMesh, options: Options, rate: u32) {
        let t = tessellate(surface, mesh, rate, false).unwrap();
        let (topo, _) = Topology::from_mesh(mesh, &options).unwrap();
        let live: Vec<bool> = (0..topo.num_faces())
            .map(|f| surface.has_surface(f))
            .collect();
        let tri = (0..topo.num_faces())
            .map(|f| surface.domain(f) == Domain::Triangle)
            .collect();
        let g = Grid::number(&topo, &live, tri, t.rate);
        assert_eq!(g.points.len(), t.num_vertices());
        let mut grid = Vec::new();
        let mut checked = 0;
        for f in (0..topo.num_faces()).filter(|&f| live[f]) {
            for j in 0..surface.num_subfaces(f) {
                let s = g.patch(&topo, f, j, &mut grid);
                for b in 0..=s {
                    for a in 0..=s {
                        if g.tri[f] && a + b > s {
                            continue;
                        }
                        let d = surface
                            .evaluate(point(f, j, param(a, s), param(b, s)))
                            .unwrap();
                        let got = t.positions[grid[(b * (s + 1) + a) as usize] as usize];
                        let err = dist2(&d.p, &got).sqrt();
                        assert!(
                            err < 1e-12,
                            "face {f}/{j} at ({a}, {b}) of {s}: off by {err}"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 0);
    }

    use crate::mesh::test_cube as cube;

    /// A cube whose top is split into a triangle and a pentagon.
    fn mixed() -> PolyMesh {
        let mut p = cube().positions().to_vec();
        p.push([0.5, 1.0, 1.0]);
        let f: Vec<Vec<u32>> = vec![
            vec![0, 3, 2, 1],
            vec![4, 5, 6],
            vec![4, 6, 8, 7],
            vec![0, 1, 5, 4],
            vec![1, 2, 6, 5],
            vec![2, 3, 7, 8, 6],
            vec![3, 0, 4, 7],
        ];
        // Face 2 is a quad; with 6-8-7 on top, the pentagon's top edge is split at 8.
        PolyMesh::from_faces(p, &f).unwrap()
    }

    #[test]
    fn shared_samples_agree_with_every_face() {
        for rate in [1, 2, 3, 4, 5] {
            check_grid(&cube(), Options::default(), rate);
            check_grid(&mixed(), Options::default(), rate);
        }
        let mut creased = cube();
        creased.tags = Tags {
            creases: vec![
                Crease {
                    v0: 4,
                    v1: 5,
                    sharpness: 10.0,
                },
                Crease {
                    v0: 5,
                    v1: 6,
                    sharpness: 1.5,
                },
            ],
            holes: vec![3],
            ..Tags::default()
        };
        check_grid(&creased, Options::default(), 3);
    }

    /// The cube with each face split into two triangles: a Loop mesh whose vertices have
    /// valence 4 or 5 (every face irregular).
    fn tri_cube() -> PolyMesh {
        let c = cube();
        let faces: Vec<[u32; 3]> = (c.faces())
            .flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]])
            .collect();
        PolyMesh::from_faces(c.positions().to_vec(), &faces).unwrap()
    }

    /// Triangle domains become triangular grids whose shared samples agree with every
    /// face; the output is a closed, consistently oriented 2-manifold with the counts of
    /// the grid, facing the way the limit normals do, with or without `triangles`.
    #[test]
    fn triangle_domains_are_watertight_triangular_grids() {
        let m = tri_cube();
        let o = Options::default();
        let s = LoopSurface::new(&m, o).unwrap();
        for rate in 1..=5 {
            check_surface_grid(&s, &m, o, rate);
            let t = tessellate(&s, &m, rate, false).unwrap();
            let r = rate as usize;
            assert_eq!(t.rate, rate);
            assert_eq!(t.num_faces(), 12 * r * r);
            // 8 vertices, 18 edges of r − 1 inner samples, 12 faces of (r − 1)(r − 2) / 2.
            let inner = (r - 1) * r.saturating_sub(2) / 2;
            assert_eq!(t.num_vertices(), 8 + 18 * (r - 1) + 12 * inner);
            let mut directed = std::collections::HashSet::new();
            for f in 0..t.num_faces() {
                let fv = t.face(f);
                assert_eq!(fv.len(), 3);
                for i in 0..3 {
                    assert!(directed.insert((fv[i], fv[(i + 1) % 3])), "face {f}");
                }
                let n = crate::geom::newell_normal(&t.positions, fv);
                let at = |k: usize| t.normals[fv[k] as usize];
                let mean: [f64; 3] = std::array::from_fn(|c| at(0)[c] + at(1)[c] + at(2)[c]);
                assert!(crate::geom::dot(&n, &mean) > 0.0, "face {f} faces inwards");
            }
            assert!(directed.iter().all(|&(a, b)| directed.contains(&(b, a))));
            assert_eq!(tessellate(&s, &m, rate, true).unwrap(), t);
        }
        let mut creased = tri_cube();
        creased.tags = Tags {
            creases: vec![Crease {
                v0: 4,
                v1: 5,
                sharpness: 2.5,
            }],
            holes: vec![3],
            ..Tags::default()
        };
        let s = LoopSurface::new(&creased, o).unwrap();
        check_surface_grid(&s, &creased, o, 4);
        assert_eq!(
            tessellate(&s, &creased, 4, false).unwrap().num_faces(),
            11 * 16
        );
    }

    #[test]
    fn odd_rates_round_up_only_with_ngons() {
        let o = Options::default();
        assert_eq!(tessellate_mesh(&cube(), &o, 3, false).unwrap().rate, 3);
        let t = tessellate_mesh(&mixed(), &o, 3, false).unwrap();
        assert_eq!(t.rate, 4);
        // Quads: 16 cells; triangle: 3 sub-faces of 2 × 2; pentagon: 5 of 2 × 2.
        assert_eq!(t.num_faces(), 5 * 16 + 3 * 4 + 5 * 4);
    }

    #[test]
    fn refuses_zero_and_huge_rates() {
        let o = Options::default();
        assert_eq!(
            tessellate_mesh(&cube(), &o, 0, false),
            Err(TessellateError::ZeroRate)
        );
        let e = tessellate_mesh(&cube(), &o, 1 << 20, false).unwrap_err();
        let TessellateError::TooLarge { vertices, .. } = e else {
            panic!("{e}")
        };
        assert_eq!(vertices, 6 * (1u128 << 40) + 2);
        assert!(e.to_string().contains("6597069766658 vertices"), "{e}");
        let e = tessellate_mesh(&mixed(), &o, u32::MAX, true).unwrap_err();
        assert!(matches!(e, TessellateError::TooLarge { .. }), "{e}");
    }

    #[test]
    fn mismatched_surface_is_an_error() {
        let o = Options::default();
        let s = LimitSurface::new(cube(), o).unwrap();
        let e = tessellate(&s, &mixed(), 2, false).unwrap_err();
        assert!(
            matches!(e, TessellateError::Mismatch { face: 1, .. }),
            "{e}"
        );
        // A triangle domain over a quad.
        let s = LoopSurface::new(&tri_cube(), o).unwrap();
        let e = tessellate(&s, &cube(), 2, false).unwrap_err();
        assert!(
            matches!(e, TessellateError::Mismatch { face: 0, .. }),
            "{e}"
        );
    }

    /// Where the derivatives give no normal (a corner whose edges collapse), the normal
    /// comes from the output faces around the vertex: unit length, never NaN.
    #[test]
    fn degenerate_derivatives_fall_back_to_face_normals() {
        let p = vec![
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let quad = PolyMesh::from_faces(p, &[[0u32, 1, 2, 3]]).unwrap();
        let o = Options {
            boundary: crate::mesh::BoundaryInterpolation::EdgeAndCorner,
            ..Options::default()
        };
        let s = LimitSurface::new(&quad, o).unwrap();
        assert_eq!(s.eval(0, 0.0, 0.0).unwrap().normal(), [0.0; 3]);
        let t = tessellate(&s, &quad, 4, false).unwrap();
        for n in &t.normals {
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-12, "{n:?}");
            assert!(n[2] > 0.0, "{n:?}");
        }
    }
}
