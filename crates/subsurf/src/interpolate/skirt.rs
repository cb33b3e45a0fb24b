//! Skirt removal (seed 002; seed 001 §2: "boundary edges and points of the zone get no new
//! points"): refine, then drop the outer ring of faces.
//!
//! Computing new points only for interior edges and vertices and then keeping only the faces
//! built from them is the same as refining everything and removing every child face that
//! touches the child mesh's boundary: a child face `(V_v, E_a, F_f, E_b)` of face `f` at corner
//! `v` survives exactly when `v` and the face edges `a`, `b` at `v` are interior, so all its
//! vertices are interior vertex, edge and face points, computed by the interior masks from the
//! parent's positions. The boundary *position* rules (the B-spline curve rules of boundary
//! edges and vertices) produce only points that are thrown away, so any boundary rule gives
//! the same result. (What interior masks read is the parent's positions and its knot intervals;
//! in NURSS an interior edge or face next to the boundary also reads intervals "two steps
//! around" a boundary vertex, for which the scheme uses the mirror image across the boundary —
//! give the skirt the intervals you want read there.)
//!
//! Each step removes one ring: a mesh whose interior must survive `L` steps needs `L` rings
//! of skirt, or the skirt is rebuilt after each step by the caller.

use crate::mesh::{
    Corner, Crease, EdgeInterval, KnotTags, MeshError, PolyMesh, Tags, VertexWeight,
};
use crate::nurss::{Nurss, NurssError};
use std::collections::HashMap;

/// `mesh` without the faces that touch its boundary (a vertex on an edge with a single face),
/// vertices renumbered in order, unused vertices dropped; creases, corners, holes, knot
/// intervals and weights of what remains are kept (side intervals are dropped: they belong
/// to a base mesh's first step only).
///
/// # Errors
/// [`MeshError`] if the remaining faces do not form a valid mesh (never for a valid input).
pub fn remove_outer_ring(mesh: &PolyMesh) -> Result<PolyMesh, MeshError> {
    let mut edge_faces: HashMap<(u32, u32), u32> = HashMap::new();
    for f in mesh.faces() {
        for i in 0..f.len() {
            let (a, b) = (f[i], f[(i + 1) % f.len()]);
            *edge_faces.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let mut boundary = vec![false; mesh.num_vertices()];
    for (&(a, b), &n) in &edge_faces {
        if n == 1 {
            boundary[a as usize] = true;
            boundary[b as usize] = true;
        }
    }
    let mut map = vec![u32::MAX; mesh.num_vertices()];
    let mut positions = Vec::new();
    let mut faces: Vec<Vec<u32>> = Vec::new();
    let mut face_map = vec![u32::MAX; mesh.num_faces()];
    for (fi, f) in mesh.faces().enumerate() {
        if f.iter().any(|&v| boundary[v as usize]) {
            continue;
        }
        face_map[fi] = faces.len() as u32;
        faces.push(
            f.iter()
                .map(|&v| {
                    if map[v as usize] == u32::MAX {
                        map[v as usize] = positions.len() as u32;
                        positions.push(mesh.positions()[v as usize]);
                    }
                    map[v as usize]
                })
                .collect(),
        );
    }
    let mut out = PolyMesh::from_faces(positions, &faces)?;
    let kept = |v: u32| map.get(v as usize).copied().filter(|&m| m != u32::MAX);
    out.tags = Tags {
        creases: mesh
            .tags
            .creases
            .iter()
            .filter_map(|c| {
                Some(Crease {
                    v0: kept(c.v0)?,
                    v1: kept(c.v1)?,
                    sharpness: c.sharpness,
                })
            })
            .collect(),
        corners: mesh
            .tags
            .corners
            .iter()
            .filter_map(|c| {
                Some(Corner {
                    vertex: kept(c.vertex)?,
                    sharpness: c.sharpness,
                })
            })
            .collect(),
        holes: mesh
            .tags
            .holes
            .iter()
            .filter_map(|&h| face_map.get(h as usize).copied().filter(|&f| f != u32::MAX))
            .collect(),
    };
    out.knots = KnotTags {
        intervals: mesh
            .knots
            .intervals
            .iter()
            .filter_map(|t| {
                Some(EdgeInterval {
                    v0: kept(t.v0)?,
                    v1: kept(t.v1)?,
                    interval: t.interval,
                })
            })
            .collect(),
        side_intervals: Vec::new(),
        weights: mesh
            .knots
            .weights
            .iter()
            .filter_map(|w| {
                Some(VertexWeight {
                    vertex: kept(w.vertex)?,
                    weight: w.weight,
                })
            })
            .collect(),
    };
    // Intervals of edges that no longer exist (both ends kept, edge gone) would be invalid.
    let mut present: std::collections::HashSet<(u32, u32)> = std::collections::HashSet::new();
    for f in out.faces() {
        for i in 0..f.len() {
            let (a, b) = (f[i], f[(i + 1) % f.len()]);
            present.insert((a.min(b), a.max(b)));
        }
    }
    out.knots
        .intervals
        .retain(|t| present.contains(&(t.v0.min(t.v1), t.v0.max(t.v1))));
    out.tags
        .creases
        .retain(|t| present.contains(&(t.v0.min(t.v1), t.v0.max(t.v1))));
    Ok(out)
}

/// Errors of [`refine_without_skirt`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SkirtError {
    /// NURSS refused the mesh.
    #[error(transparent)]
    Nurss(#[from] NurssError),
    /// The ring removal left an invalid mesh.
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// `levels` steps of NURSS (default options), each followed by [`remove_outer_ring`]: the
/// interior of `mesh` refined with skirt removal (it shrinks by one ring per step).
///
/// # Errors
/// [`SkirtError`].
pub fn refine_without_skirt(mesh: &PolyMesh, levels: u32) -> Result<PolyMesh, SkirtError> {
    let mut m = mesh.clone();
    for _ in 0..levels {
        let mut s = Nurss::new(&m, &Default::default())?;
        s.step();
        m = remove_outer_ring(&s.to_mesh(false))?;
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{BoundaryInterpolation, Options};

    /// An `n × n` grid of quads, bumpy, with non-uniform intervals on one column of edges.
    fn grid(n: u32) -> PolyMesh {
        let m = n + 1;
        let mut pos = Vec::new();
        for j in 0..m {
            for i in 0..m {
                let (x, y) = (i as f64, j as f64);
                pos.push([x + 0.1 * y.sin(), y, (0.7 * x).sin() * (0.4 * y).cos()]);
            }
        }
        let mut faces = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = m * j + i;
                faces.push([v, v + 1, v + m + 1, v + m]);
            }
        }
        let mut g = PolyMesh::from_faces(pos, &faces).unwrap();
        for j in 0..m {
            g.knots.intervals.push(EdgeInterval {
                v0: m * j + 1,
                v1: m * j + 2,
                interval: 2.5,
            });
        }
        g
    }

    #[test]
    fn outer_ring_of_a_grid_is_its_border_faces() {
        let g = grid(4);
        let inner = remove_outer_ring(&g).unwrap();
        assert_eq!(inner.num_faces(), 4);
        assert_eq!(inner.num_vertices(), 9);
        // The tagged column keeps its intervals where its edges survive (rows 1..=3).
        assert_eq!(inner.knots.intervals.len(), 3);
        assert!(inner.knots.validate(&inner).is_ok());
    }

    #[test]
    fn interior_after_skirt_removal_does_not_depend_on_the_boundary_rules() {
        let g = grid(5);
        let refine = |boundary| {
            let opts = Options {
                boundary,
                ..Options::default()
            };
            let mut s = Nurss::new(&g, &opts).unwrap();
            s.step();
            remove_outer_ring(&s.to_mesh(false)).unwrap()
        };
        let a = refine(BoundaryInterpolation::EdgeOnly);
        let b = refine(BoundaryInterpolation::EdgeAndCorner);
        assert_eq!(a.num_faces(), 8 * 8);
        assert_eq!(a.positions(), b.positions());
        // ... while the boundary points themselves do differ (the corners).
        let full = |boundary| {
            let opts = Options {
                boundary,
                ..Options::default()
            };
            let mut s = Nurss::new(&g, &opts).unwrap();
            s.step();
            s.positions()
        };
        assert_ne!(
            full(BoundaryInterpolation::EdgeOnly),
            full(BoundaryInterpolation::EdgeAndCorner)
        );
        let twice = refine_without_skirt(&g, 2).unwrap();
        assert_eq!(twice.num_faces(), 14 * 14);
    }
}
