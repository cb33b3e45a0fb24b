//! [`mesh_info`]: a summary of a mesh for `subsurf info`.

use crate::mesh::{Options, PolyMesh, Topology};
use crate::refine::Error;
use crate::scheme::Scheme;
use std::collections::BTreeMap;

/// Counts and classification of a mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshInfo {
    /// Vertices.
    pub vertices: usize,
    /// Edges.
    pub edges: usize,
    /// Faces.
    pub faces: usize,
    /// `(face size, count)`, ascending.
    pub face_sizes: Vec<(usize, usize)>,
    /// `(valence, count)` over vertices with faces, ascending.
    pub valences: Vec<(usize, usize)>,
    /// Vertices whose valence is not regular (4 inside, 3 on a boundary; corners excluded).
    pub extraordinary_vertices: usize,
    /// Isolated vertices (no face).
    pub isolated_vertices: usize,
    /// Number of closed boundary loops.
    pub boundary_loops: usize,
    /// Boundary edges.
    pub boundary_edges: usize,
    /// Non-manifold edges.
    pub non_manifold_edges: usize,
    /// Non-manifold vertices (isolated vertices excluded).
    pub non_manifold_vertices: usize,
    /// Euler characteristic V - E + F.
    pub euler_characteristic: i64,
    /// Crease tags.
    pub creases: usize,
    /// Tagged corner vertices.
    pub corners: usize,
    /// Hole faces.
    pub holes: usize,
    /// Bounding box.
    pub bounding_box: Option<([f64; 3], [f64; 3])>,
}

impl MeshInfo {
    /// The scheme that suits the mesh: Loop when every face is a triangle (a scan, a game
    /// asset, a CAD tessellation: Catmull-Clark splits each triangle into three quads with
    /// an extraordinary vertex at its centre, a bumpier surface than Loop's), else
    /// Catmull-Clark. A suggestion for `subsurf info`; nothing chooses a scheme by it.
    pub fn suggested_scheme(&self) -> Scheme {
        match self.face_sizes.as_slice() {
            [(3, _)] => Scheme::Loop,
            _ => Scheme::CatmullClark,
        }
    }
}

/// Summarises `mesh` (topology built with `options`).
///
/// # Errors
/// [`Error::Mesh`] if the mesh is invalid.
pub fn mesh_info(mesh: &PolyMesh, options: &Options) -> Result<MeshInfo, Error> {
    mesh.validate()?;
    let (t, _) = Topology::from_mesh(mesh, options)?;
    let mut face_sizes = BTreeMap::new();
    for f in 0..t.num_faces() {
        *face_sizes.entry(t.face_vertices(f).len()).or_insert(0) += 1;
    }
    let mut valences = BTreeMap::new();
    let (mut extraordinary, mut isolated, mut nm_verts) = (0, 0, 0);
    for v in 0..t.num_vertices() {
        let (ne, nf) = (t.vertex_edges(v).len(), t.vertex_faces(v).len());
        if nf == 0 {
            isolated += 1;
            continue;
        }
        *valences.entry(ne).or_insert(0) += 1;
        let tag = t.vertex_tag(v);
        if tag.non_manifold {
            nm_verts += 1;
        } else if tag.boundary {
            let corner = nf == 1 && ne == 2;
            extraordinary += (!corner && ne != 3) as usize;
        } else {
            extraordinary += (ne != 4) as usize;
        }
    }
    // Boundary loops: connected components of the boundary edges (union-find).
    let mut parent: Vec<u32> = (0..t.num_vertices() as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    let (mut boundary_edges, mut nm_edges) = (0, 0);
    let mut on_boundary = vec![false; t.num_vertices()];
    for e in 0..t.num_edges() {
        let tag = t.edge_tag(e);
        nm_edges += tag.non_manifold as usize;
        if tag.boundary {
            boundary_edges += 1;
            let [a, b] = t.edge_vertices(e);
            on_boundary[a as usize] = true;
            on_boundary[b as usize] = true;
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            parent[ra as usize] = rb;
        }
    }
    let boundary_loops = (0..t.num_vertices() as u32)
        .filter(|&v| on_boundary[v as usize] && find(&mut parent, v) == v)
        .count();
    Ok(MeshInfo {
        vertices: t.num_vertices(),
        edges: t.num_edges(),
        faces: t.num_faces(),
        face_sizes: face_sizes.into_iter().collect(),
        valences: valences.into_iter().collect(),
        extraordinary_vertices: extraordinary,
        isolated_vertices: isolated,
        boundary_loops,
        boundary_edges,
        non_manifold_edges: nm_edges,
        non_manifold_vertices: nm_verts,
        euler_characteristic: t.num_vertices() as i64 - t.num_edges() as i64 + t.num_faces() as i64,
        creases: mesh.tags.creases.len(),
        corners: mesh.tags.corners.len(),
        holes: mesh.tags.holes.len(),
        bounding_box: mesh.bounding_box(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_grid_has_one_boundary_loop_and_euler_one() {
        // 2×2 quads.
        let p: Vec<[f64; 3]> = (0..9)
            .map(|i| [(i % 3) as f64, (i / 3) as f64, 0.0])
            .collect();
        let faces = [[0u32, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
        let m = PolyMesh::from_faces(p, &faces).unwrap();
        let i = mesh_info(&m, &Options::default()).unwrap();
        assert_eq!((i.vertices, i.edges, i.faces), (9, 12, 4));
        assert_eq!(i.boundary_loops, 1);
        assert_eq!(i.boundary_edges, 8);
        assert_eq!(i.euler_characteristic, 1);
        assert_eq!(i.extraordinary_vertices, 0);
        assert_eq!(i.valences, vec![(2, 4), (3, 4), (4, 1)]);
    }
}
