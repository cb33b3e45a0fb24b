//! [`compare_with_limit`]: how far the sub-basis spline is from the Catmull-Clark limit
//! surface of the same control mesh, and how large its normal jumps across edges are.

use super::error::SplineError;
use super::surface::SubBasisSurface;
use crate::geom;
use crate::limit::LimitSurface;
use crate::mesh::{Options, PolyMesh, Topology};
use rayon::prelude::*;

/// Measurements of [`compare_with_limit`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Comparison {
    /// Faces with a spline surface (all compared).
    pub faces: usize,
    /// Samples compared (`(m + 1)²` per face).
    pub samples: usize,
    /// Largest `|P_spline(f,u,v) − P_limit(f,u,v)|` over the samples (same parameter: an
    /// upper bound of the distance between the surfaces near the sample).
    pub max_distance: f64,
    /// Root mean square of the same distances.
    pub rms_distance: f64,
    /// Face of the largest distance.
    pub max_distance_face: u32,
    /// Diagonal of the control mesh's bounding box (to read distances relative to size).
    pub size: f64,
    /// Interior edges with an end of valence ≠ 4 where both faces have a surface.
    pub irregular_edges: usize,
    /// Largest angle (degrees) between the two faces' normals at the edges' interior samples.
    pub max_jump_irregular: f64,
    /// Mean over those edges of their largest interior jump (degrees).
    pub mean_jump_irregular: f64,
    /// Largest angle (degrees) between the normals of the faces around an irregular vertex,
    /// at the vertex itself (pairs of faces sharing an edge).
    pub max_jump_at_vertices: f64,
    /// Interior edges whose both ends have valence 4, where both faces have a surface.
    pub regular_edges: usize,
    /// Largest normal jump (degrees) over all samples of those edges (C1 there: ~0).
    pub max_jump_regular: f64,
}

/// Compares `surface` (built from the quad mesh `mesh`) with the Catmull-Clark limit surface
/// of `mesh` without its tags (default options, edge-only boundaries; the spline ignores
/// creases): positions on an `(m + 1) × (m + 1)` grid per face with a
/// surface, and the angle between the two faces' unit normals at `m + 1` points along every
/// interior edge (`m = samples`, at least 1).
///
/// # Errors
/// [`SplineError::Mesh`], [`SplineError::Mismatch`].
pub fn compare_with_limit(
    surface: &SubBasisSurface,
    mesh: &PolyMesh,
    samples: u32,
) -> Result<Comparison, SplineError> {
    if mesh.num_faces() != surface.num_faces() || mesh.num_vertices() != surface.num_vertices() {
        return Err(SplineError::Mismatch {
            surface_faces: surface.num_faces(),
            surface_vertices: surface.num_vertices(),
            mesh_faces: mesh.num_faces(),
            mesh_vertices: mesh.num_vertices(),
        });
    }
    let m = samples.max(1) as usize;
    // The spline has no sharp features: compare with the limit of the untagged mesh.
    let plain = PolyMesh::new(
        mesh.positions().to_vec(),
        mesh.face_offsets().to_vec(),
        mesh.face_verts().to_vec(),
    )?;
    let limit = LimitSurface::new(&plain, Options::default())?;
    let mut c = compare_positions(surface, &limit, mesh.num_faces(), m);
    c.size = mesh
        .bounding_box()
        .map_or(0.0, |(lo, hi)| geom::norm(&geom::sub(&hi, &lo)));
    let (topo, _) = Topology::from_mesh(mesh, &Options::default())?;
    let jumps: Vec<(bool, f64, f64)> = (0..topo.num_edges())
        .into_par_iter()
        .filter_map(|e| edge_normal_jump(surface, &topo, e, m))
        .collect();
    let mut sum = 0.0;
    for &(irr, interior, ends) in &jumps {
        if irr {
            c.irregular_edges += 1;
            c.max_jump_irregular = c.max_jump_irregular.max(interior);
            c.max_jump_at_vertices = c.max_jump_at_vertices.max(ends);
            sum += interior;
        } else {
            c.regular_edges += 1;
            c.max_jump_regular = c.max_jump_regular.max(interior);
        }
    }
    if c.irregular_edges > 0 {
        c.mean_jump_irregular = sum / c.irregular_edges as f64;
    }
    Ok(c)
}

/// The position measurements of [`Comparison`] (faces, samples, largest and RMS distance,
/// the face of the largest): `|P_spline − P_limit|` on the `(m + 1) × (m + 1)` grid of every
/// face of `surface` with a spline surface (of the `num_faces`), where both evaluate.
fn compare_positions(
    surface: &SubBasisSurface,
    limit: &LimitSurface,
    num_faces: usize,
    m: usize,
) -> Comparison {
    let faces: Vec<u32> = (0..num_faces as u32)
        .filter(|&f| surface.has_surface(f as usize))
        .collect();
    // Per face: (max distance, sum of squares, count).
    let per_face: Vec<(f64, f64, usize)> = faces
        .par_iter()
        .map(|&f| {
            let (mut mx, mut ss, mut cnt) = (0.0f64, 0.0, 0);
            for a in 0..=m {
                for b in 0..=m {
                    let (u, v) = (a as f64 / m as f64, b as f64 / m as f64);
                    if let (Ok(p), Ok(q)) = (surface.position(f, u, v), limit.eval(f, u, v)) {
                        let d = geom::norm(&geom::sub(&p, &q.p));
                        mx = mx.max(d);
                        ss += d * d;
                        cnt += 1;
                    }
                }
            }
            (mx, ss, cnt)
        })
        .collect();
    let mut c = Comparison {
        faces: faces.len(),
        ..Default::default()
    };
    let mut ss = 0.0;
    for (i, &(mx, s, n)) in per_face.iter().enumerate() {
        if mx > c.max_distance {
            c.max_distance = mx;
            c.max_distance_face = faces[i];
        }
        ss += s;
        c.samples += n;
    }
    c.rms_distance = if c.samples > 0 {
        (ss / c.samples as f64).sqrt()
    } else {
        0.0
    };
    c
}

/// The normal jump across interior edge `e` when both its faces have a spline surface:
/// `(an end has valence ≠ 4, largest angle in degrees between the two faces' unit normals
/// at the m + 1 samples, counting a regular end with the interior, largest at an irregular
/// end)`; `None` for a boundary edge or one without two surfaces.
fn edge_normal_jump(
    surface: &SubBasisSurface,
    topo: &Topology,
    e: usize,
    m: usize,
) -> Option<(bool, f64, f64)> {
    let valence = |v: u32| topo.vertex_faces(v as usize).len();
    let ef = topo.edge_face_list(e);
    if ef.len() != 2 || !ef.iter().all(|&f| surface.has_surface(f as usize)) {
        return None;
    }
    let ev = topo.edge_vertices(e);
    let irregular = [valence(ev[0]) != 4, valence(ev[1]) != 4];
    let normal_at = |f: u32, x: f64| -> Option<[f64; 3]> {
        // x: fraction from ev[0] to ev[1].
        let fv = topo.face_vertices(f as usize);
        let i = (0..4).find(|&i| topo.face_edge_list(f as usize)[i] as usize == e)?;
        let t = if fv[i] == ev[0] { x } else { 1.0 - x };
        let (u, v) = match i {
            0 => (t, 0.0),
            1 => (1.0, t),
            2 => (1.0 - t, 1.0),
            _ => (0.0, 1.0 - t),
        };
        surface.eval(f, u, v).ok().map(|d| d.normal())
    };
    let (mut interior, mut ends) = (0.0f64, 0.0f64);
    for s in 0..=m {
        let x = s as f64 / m as f64;
        let (Some(a), Some(b)) = (normal_at(ef[0], x), normal_at(ef[1], x)) else {
            continue;
        };
        // atan2(|a × b|, a · b): accurate also for tiny angles (acos is not).
        let ang = geom::norm(&geom::cross(&a, &b))
            .atan2(geom::dot(&a, &b))
            .to_degrees();
        if s == 0 || s == m {
            let end = if s == 0 { irregular[0] } else { irregular[1] };
            if end {
                ends = ends.max(ang);
            } else {
                interior = interior.max(ang);
            }
        } else {
            interior = interior.max(ang);
        }
    }
    Some((irregular[0] || irregular[1], interior, ends))
}
