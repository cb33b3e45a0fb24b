//! Skirt removal ("contour deletion", [Jiang et al.] §2.2): refinement of an open mesh that
//! never uses a boundary rule, for any subdivision scheme with Catmull-Clark topology.
//!
//! # The extension layer
//! A mesh refined with skirt removal carries one *extension layer*: its outer ring of faces
//! (every face with a boundary vertex). Only the knot intervals of the extension layer's
//! edges matter (they are the paper's *extension intervals*, the intervals beyond the
//! boundary); the positions of its outer vertices never reach the surface. The *real* mesh
//! is everything else, and its limit surface is the part that the real control points
//! determine, exactly as a B-spline has no surface over its outermost ring of control
//! points.
//!
//! # One step ([`skirt_step`])
//! Refine the whole mesh one step with any scheme, then keep only the children of real
//! faces, dropping the children of the extension layer (two child rings), and renumber
//! compactly. The kept children's outer ring is the new extension layer; its edges to the
//! new real mesh carry the halved intervals, as the paper's step 3 keeps "the edges to the
//! deleted layer as the new extension edges with their intervals".
//!
//! **Why the new real points never depend on a boundary rule or on the extension
//! positions.** The new real vertices are the interior vertices of the kept children:
//! face points of real faces (read only those faces' corners, which are real, and
//! intervals), edge points of edges between two real faces (read the two end points, the two
//! faces, and intervals — `d±` at a real-boundary end reads the extension edge's interval,
//! never a position), and vertex points of vertices all of whose faces are real. Boundary
//! rules (the scheme's, for the mesh's outer boundary) only make points of the dropped
//! rings, and the points that read extension positions (vertex points of real-boundary
//! vertices, edge points of real-boundary edges) are exactly the outer vertices of the new
//! extension layer. So the real part evolves exactly as the paper defines skirt removal —
//! new points only for the interior edges and vertices of the real mesh, with the extension
//! intervals standing in for the missing neighbours — and the same function serves
//! Catmull-Clark ([`catmark_step`]), NURSS ([`nurss_step`]) or any scheme with
//! Catmull-Clark topology and child numbering.

use std::collections::{HashMap, HashSet};

use super::grid::VertexGrid;
use super::BlendError;
use crate::mesh::{Corner, Crease, EdgeInterval, KnotTags, Options, PolyMesh, Tags, Topology};
use crate::nonuniform::Nurss;
use crate::refine::uniform::{refine_mesh, Steps};
use crate::scheme::adjustable::Mixed;

/// Boundary vertices of `mesh`: vertices on an edge that only one face uses.
pub(crate) fn boundary_vertices(mesh: &PolyMesh) -> Vec<bool> {
    let mut count: HashMap<(u32, u32), u32> = HashMap::new();
    for fv in mesh.faces() {
        for (i, &a) in fv.iter().enumerate() {
            let b = fv[(i + 1) % fv.len()];
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let mut out = vec![false; mesh.num_vertices()];
    for ((a, b), c) in count {
        if c == 1 {
            out[a as usize] = true;
            out[b as usize] = true;
        }
    }
    out
}

/// The extension layer of `mesh`: `true` for every face with a boundary vertex.
pub(crate) fn outer_ring(mesh: &PolyMesh) -> Vec<bool> {
    let b = boundary_vertices(mesh);
    mesh.faces()
        .map(|fv| fv.iter().any(|&v| b[v as usize]))
        .collect()
}

/// A mesh after skirt removal, with the renumbering from the refined mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct SkirtStep {
    /// The kept faces and vertices, compactly renumbered, with the knot intervals, weights,
    /// creases and corners of kept elements.
    pub mesh: PolyMesh,
    /// For every vertex of the refined mesh, its index in [`mesh`](Self::mesh), or
    /// `u32::MAX` if it was dropped.
    pub new_index: Vec<u32>,
}

/// Keeps the faces of `mesh` with `keep[f]`, drops unused vertices, renumbers compactly and
/// carries the tags (intervals, weights, creases, corners) of kept elements.
///
/// # Errors
/// [`BlendError::Holes`] if the mesh has hole faces.
pub(crate) fn keep_faces(mesh: &PolyMesh, keep: &[bool]) -> Result<SkirtStep, BlendError> {
    if let Some(&face) = mesh.tags.holes.first() {
        return Err(BlendError::Holes { face });
    }
    let mut new_index = vec![u32::MAX; mesh.num_vertices()];
    let mut positions = Vec::new();
    let mut offsets = vec![0u32];
    let mut verts = Vec::new();
    let mut edges = HashSet::new();
    for (f, fv) in mesh.faces().enumerate() {
        if !keep[f] {
            continue;
        }
        for (i, &v) in fv.iter().enumerate() {
            let w = fv[(i + 1) % fv.len()];
            edges.insert((v.min(w), v.max(w)));
            if new_index[v as usize] == u32::MAX {
                new_index[v as usize] = positions.len() as u32;
                positions.push(mesh.positions()[v as usize]);
            }
            verts.push(new_index[v as usize]);
        }
        offsets.push(verts.len() as u32);
    }
    let map = |v: u32| new_index.get(v as usize).copied().unwrap_or(u32::MAX);
    let kept_edge = |a: u32, b: u32| edges.contains(&(a.min(b), a.max(b)));
    let mut knots = KnotTags::default();
    for t in &mesh.knots.intervals {
        if kept_edge(t.v0, t.v1) {
            knots.intervals.push(EdgeInterval {
                v0: map(t.v0),
                v1: map(t.v1),
                interval: t.interval,
            });
        }
    }
    for w in &mesh.knots.weights {
        if map(w.vertex) != u32::MAX {
            let mut w = *w;
            w.vertex = map(w.vertex);
            knots.weights.push(w);
        }
    }
    let mut tags = Tags::default();
    for c in &mesh.tags.creases {
        if kept_edge(c.v0, c.v1) {
            tags.creases.push(Crease {
                v0: map(c.v0),
                v1: map(c.v1),
                sharpness: c.sharpness,
            });
        }
    }
    for c in &mesh.tags.corners {
        if map(c.vertex) != u32::MAX {
            tags.corners.push(Corner {
                vertex: map(c.vertex),
                sharpness: c.sharpness,
            });
        }
    }
    let mut out = PolyMesh::new(positions, offsets, verts)?;
    out.tags = tags;
    out.knots = knots;
    Ok(SkirtStep {
        mesh: out,
        new_index,
    })
}

/// Skirt removal after one refinement step: `child` is the one-step refinement of `parent`
/// by any scheme with Catmull-Clark topology and OpenSubdiv's child numbering (the child
/// faces of parent face `f` are `face_offsets[f] .. face_offsets[f + 1]`). Keeps the
/// children of the parent's real faces (not in its [`outer_ring`]); see the
/// [module documentation](self) for why this is the paper's skirt removal.
///
/// # Errors
/// [`BlendError::NotARefinement`] if the face counts do not match, [`BlendError::NoInterior`]
/// if every parent face is in the outer ring, [`BlendError::Holes`].
pub(crate) fn skirt_step(parent: &PolyMesh, child: &PolyMesh) -> Result<SkirtStep, BlendError> {
    let expected = parent.face_verts().len();
    if child.num_faces() != expected {
        return Err(BlendError::NotARefinement {
            expected,
            found: child.num_faces(),
        });
    }
    let ring = outer_ring(parent);
    if ring.iter().all(|&r| r) {
        return Err(BlendError::NoInterior);
    }
    let mut keep = vec![false; expected];
    let offsets = parent.face_offsets();
    for (f, &r) in ring.iter().enumerate() {
        if !r {
            for c in offsets[f]..offsets[f + 1] {
                keep[c as usize] = true;
            }
        }
    }
    keep_faces(child, &keep)
}

/// One NURSS step of `mesh` with its [`PolyMesh::knots`] (no skirt removal; the child
/// carries its intervals).
///
/// # Errors
/// As [`Nurss::new`].
pub fn nurss_refine_once(mesh: &PolyMesh) -> Result<PolyMesh, BlendError> {
    let mut s = Nurss::new(mesh, &Options::default())?;
    s.step();
    Ok(s.to_mesh(true))
}

/// One Catmull-Clark step of `mesh` (OpenSubdiv's rules; intervals are ignored).
///
/// # Errors
/// [`BlendError::Subdivide`] for an invalid mesh.
pub fn catmark_refine_once(mesh: &PolyMesh) -> Result<PolyMesh, BlendError> {
    let options = crate::mesh::Options::default();
    refine_mesh(mesh, &options, Steps::Family(Mixed::CATMULL_CLARK), 1, true)
        .map_err(|e| BlendError::Subdivide(e.to_string()))
}

/// One NURSS step with skirt removal.
///
/// # Errors
/// As [`nurss_refine_once`] and `skirt_step`.
pub fn nurss_step(mesh: &PolyMesh) -> Result<SkirtStep, BlendError> {
    skirt_step(mesh, &nurss_refine_once(mesh)?)
}

/// One Catmull-Clark step with skirt removal.
///
/// # Errors
/// As [`catmark_refine_once`] and `skirt_step`.
pub fn catmark_step(mesh: &PolyMesh) -> Result<SkirtStep, BlendError> {
    skirt_step(mesh, &catmark_refine_once(mesh)?)
}

/// `levels` steps of skirt-removal refinement with the one-step refinement `refine` (for
/// example [`nurss_refine_once`] or [`catmark_refine_once`], or any scheme with
/// Catmull-Clark topology), carrying the vertex `grids` along (each is mapped to its child
/// grid and trimmed of dropped rows and columns, see `VertexGrid::refine`).
///
/// # Errors
/// Those of `refine` and `skirt_step`; [`BlendError::Grid`] if a grid stops being a quad
/// grid of the mesh.
pub fn refine_with_skirt<F>(
    mesh: &PolyMesh,
    levels: u32,
    grids: &mut [VertexGrid],
    mut refine: F,
) -> Result<PolyMesh, BlendError>
where
    F: FnMut(&PolyMesh) -> Result<PolyMesh, BlendError>,
{
    let mut cur = mesh.clone();
    for _ in 0..levels {
        let child = refine(&cur)?;
        let step = skirt_step(&cur, &child)?;
        if !grids.is_empty() {
            let (topology, _) = Topology::from_mesh(&cur, &Options::default())?;
            for g in grids.iter_mut() {
                *g = g.refine(&topology)?.renumber(&step.new_index, &child)?;
            }
        }
        cur = step.mesh;
    }
    Ok(cur)
}

/// The real part of a mesh with an extension layer: the mesh without its `outer_ring`
/// (what the limit surface is made of), for output.
///
/// # Errors
/// [`BlendError::Holes`].
pub fn real_part(mesh: &PolyMesh) -> Result<PolyMesh, BlendError> {
    let keep: Vec<bool> = outer_ring(mesh).iter().map(|&r| !r).collect();
    Ok(keep_faces(mesh, &keep)?.mesh)
}

/// Relative distance (times the bounding-box diagonal) within which the two ends of an edge
/// of zero knot interval count as one point for [`merge_degenerate`].
pub(crate) const MERGE_TOLERANCE: f64 = 1e-12;

/// `mesh` (a real part, for output) with the two ends of every edge of knot interval 0 that
/// coincide (within [`MERGE_TOLERANCE`] of the bounding-box diagonal) merged into one
/// vertex, and the faces that this leaves with fewer than three vertices dropped.
///
/// Why they coincide: a run of `k ≥ 2` edges of interval 0 along a row is a knot of
/// multiplicity `k + 1 ≥ 3`, where the `k − 1` inner control points of a cubic are all the
/// curve's point there (inserting a knot of multiplicity 3 repeats that point; The NURBS
/// Book eq. 5.15 with `α = 0` or `1`). Every refinement step doubles the run, so the G1 fill
/// ([`super::g1`], whose boundary knots are tripled) gets more such points each level, and
/// the quads between two of them have zero area (two opposite sides of length 0). Merging
/// the points collapses each such quad onto an edge and turns a quad with one such side into
/// a triangle; every other face and vertex keeps its position, and the mesh stays
/// watertight: an edge two faces shared is still shared by two. The first of the merged
/// vertices (in order) is kept, with its position, weight and tags.
///
/// # Errors
/// [`BlendError::Mesh`] (none in practice), [`BlendError::Holes`].
pub(crate) fn merge_degenerate(mesh: &PolyMesh) -> Result<PolyMesh, BlendError> {
    let diagonal = mesh.bounding_box().map_or(0.0, |(lo, hi)| {
        (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
    });
    let tolerance = MERGE_TOLERANCE * diagonal;
    let pos = mesh.positions();
    let mut parent: Vec<u32> = (0..mesh.num_vertices() as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            let up = parent[parent[v as usize] as usize];
            parent[v as usize] = up;
            v = up;
        }
        v
    }
    let mut merged = false;
    for t in mesh.knots.intervals.iter().filter(|t| t.interval == 0.0) {
        let (a, b) = (pos[t.v0 as usize], pos[t.v1 as usize]);
        let d = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
        if d <= tolerance {
            let (ra, rb) = (root(&mut parent, t.v0), root(&mut parent, t.v1));
            if ra != rb {
                parent[ra.max(rb) as usize] = ra.min(rb);
                merged = true;
            }
        }
    }
    if !merged {
        return Ok(mesh.clone());
    }
    let map: Vec<u32> = (0..parent.len() as u32)
        .map(|v| root(&mut parent, v))
        .collect();
    let mut offsets = vec![0u32];
    let mut verts = Vec::with_capacity(mesh.face_verts().len());
    for fv in mesh.faces() {
        let n = fv.len();
        let start = verts.len();
        for (i, &v) in fv.iter().enumerate() {
            let (m, next) = (map[v as usize], map[fv[(i + 1) % n] as usize]);
            if m != next {
                verts.push(m);
            }
        }
        if verts.len() - start < 3 {
            verts.truncate(start);
        } else {
            offsets.push(verts.len() as u32);
        }
    }
    let mut out = PolyMesh::new(pos.to_vec(), offsets, verts)?;
    let mut knots = mesh.knots.clone();
    for t in &mut knots.intervals {
        (t.v0, t.v1) = (map[t.v0 as usize], map[t.v1 as usize]);
    }
    knots.intervals.retain(|t| t.v0 != t.v1);
    knots.weights.retain(|w| map[w.vertex as usize] == w.vertex);
    let mut tags = mesh.tags.clone();
    for c in &mut tags.creases {
        (c.v0, c.v1) = (map[c.v0 as usize], map[c.v1 as usize]);
    }
    tags.creases.retain(|c| c.v0 != c.v1);
    tags.corners.retain(|c| map[c.vertex as usize] == c.vertex);
    out.knots = knots;
    out.tags = tags;
    let all = vec![true; out.num_faces()];
    Ok(keep_faces(&out, &all)?.mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: u32) -> PolyMesh {
        let mut pos = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f64, j as f64);
                pos.push([x, y, 0.1 * x * x - 0.05 * x * y + 0.2 * y]);
            }
        }
        let mut faces = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = (n + 1) * j + i;
                faces.push([v, v + 1, v + n + 2, v + n + 1]);
            }
        }
        PolyMesh::from_faces(pos, &faces).unwrap()
    }

    #[test]
    fn each_step_keeps_the_children_of_real_faces_only() {
        // A 6×6 grid: 16 real faces (the 4×4 middle) → 64 kept children, an 8×8 grid.
        let m = grid(6);
        let s = catmark_step(&m).unwrap();
        assert_eq!(s.mesh.num_faces(), 64);
        assert_eq!(s.mesh.num_vertices(), 81);
        let s2 = catmark_step(&s.mesh).unwrap();
        assert_eq!(s2.mesh.num_faces(), 36 * 4);
    }

    #[test]
    fn real_points_do_not_depend_on_extension_positions() {
        // Moving the outer vertices must not move any new real vertex, for both schemes.
        let m = grid(5);
        let mut moved = m.clone();
        let b = boundary_vertices(&m);
        for (v, p) in moved.positions_mut().iter_mut().enumerate() {
            if b[v] {
                p[2] += 3.0 + v as f64;
            }
        }
        for step in [nurss_step, catmark_step] {
            let a = step(&m).unwrap().mesh;
            let c = step(&moved).unwrap().mesh;
            let bb = boundary_vertices(&a);
            let mut checked = 0;
            for v in 0..a.num_vertices() {
                if !bb[v] {
                    checked += 1;
                    for k in 0..3 {
                        assert!((a.positions()[v][k] - c.positions()[v][k]).abs() < 1e-12);
                    }
                }
            }
            assert!(checked > 0);
        }
    }

    #[test]
    fn a_mesh_that_is_all_ring_is_rejected() {
        let m = grid(2);
        assert_eq!(catmark_step(&m).unwrap_err(), BlendError::NoInterior);
    }
}
