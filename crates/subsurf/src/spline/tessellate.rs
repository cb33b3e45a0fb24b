//! [`tessellate`]: a watertight quad mesh sampled from a [`SubBasisSurface`], and
//! [`face_colours`] for Fig. 7-style pictures.

use super::error::SplineError;
use super::surface::SubBasisSurface;
use crate::mesh::{Options, PolyMesh, Topology};
use rayon::prelude::*;

/// The largest number of output vertices [`tessellate`] accepts (2³¹).
pub(crate) const MAX_VERTICES: u64 = 1 << 31;

const UNSET: u32 = u32::MAX;

/// A quad mesh sampled from a [`SubBasisSurface`]. See [`tessellate`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SplineTessellation {
    /// Samples per control-mesh edge.
    pub rate: u32,
    /// Vertex positions on the surface.
    pub positions: Vec<[f64; 3]>,
    /// Unit normals `P_u × P_v / |P_u × P_v|` of the face each vertex was evaluated on.
    pub normals: Vec<[f64; 3]>,
    /// Where each vertex was evaluated: `(face, u, v)`.
    pub params: Vec<(u32, f64, f64)>,
    /// CSR offsets of the output quads.
    pub face_offsets: Vec<u32>,
    /// CSR vertex indices of the output quads (counter-clockwise like their base faces).
    pub face_verts: Vec<u32>,
    /// Base face of each output quad.
    pub source: Vec<u32>,
}

impl SplineTessellation {
    /// Number of output vertices.
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }

    /// Number of output quads.
    pub fn num_faces(&self) -> usize {
        self.source.len()
    }
}

/// Samples every face of `surface` that has a surface at `u = a/rate`, `v = b/rate`
/// (`0 ≤ a, b ≤ rate`) and joins the samples into `rate × rate` quads per face. `mesh` is the
/// quad control mesh the surface was built from. Samples on control-mesh vertices and edges
/// are evaluated once (on the first face that has them) and shared, so the output is
/// watertight: neighbouring faces use the very same vertices.
///
/// # Errors
/// [`SplineError::ZeroRate`], [`SplineError::Mismatch`] when `mesh` is not the surface's
/// mesh, [`SplineError::Empty`] when no face has a surface, [`SplineError::TooLarge`].
pub fn tessellate(
    surface: &SubBasisSurface,
    mesh: &PolyMesh,
    rate: u32,
) -> Result<SplineTessellation, SplineError> {
    if rate == 0 {
        return Err(SplineError::ZeroRate);
    }
    if mesh.num_faces() != surface.num_faces() || mesh.num_vertices() != surface.num_vertices() {
        return Err(SplineError::Mismatch {
            surface_faces: surface.num_faces(),
            surface_vertices: surface.num_vertices(),
            mesh_faces: mesh.num_faces(),
            mesh_vertices: mesh.num_vertices(),
        });
    }
    let faces: Vec<usize> = (0..mesh.num_faces())
        .filter(|&f| surface.has_surface(f))
        .collect();
    if faces.is_empty() {
        return Err(SplineError::Empty);
    }
    let n = rate as usize;
    let estimate = faces.len() as u128 * (n as u128 + 1) * (n as u128 + 1);
    if estimate > MAX_VERTICES as u128 {
        return Err(SplineError::TooLarge {
            rate,
            vertices: estimate,
            limit: MAX_VERTICES,
        });
    }
    let (topo, _) = Topology::from_mesh(mesh, &Options::default())?;
    let mut vert_index = vec![UNSET; topo.num_vertices()];
    let mut edge_base = vec![UNSET; topo.num_edges()];
    let mut params: Vec<(u32, f64, f64)> = Vec::new();
    let mut face_offsets = vec![0u32];
    let mut face_verts = Vec::with_capacity(faces.len() * n * n * 4);
    let mut source = Vec::with_capacity(faces.len() * n * n);
    let inv = 1.0 / n as f64;
    let mut grid = vec![0u32; (n + 1) * (n + 1)];
    for &f in &faces {
        let fv = topo.face_vertices(f);
        let fe = topo.face_edge_list(f);
        let param = |a: usize, b: usize| (f as u32, a as f64 * inv, b as f64 * inv);
        // Corners.
        for (j, &(a, b)) in [(0, 0), (n, 0), (n, n), (0, n)].iter().enumerate() {
            let v = fv[j] as usize;
            if vert_index[v] == UNSET {
                vert_index[v] = params.len() as u32;
                params.push(param(a, b));
            }
            grid[a * (n + 1) + b] = vert_index[v];
        }
        // Edges: edge i runs from corner i to corner i + 1.
        for i in 0..4 {
            let e = fe[i] as usize;
            let forward = topo.edge_vertices(e)[0] == fv[i];
            let first = edge_base[e] == UNSET;
            if first {
                edge_base[e] = params.len() as u32;
            }
            for t in 1..n {
                let (a, b) = match i {
                    0 => (t, 0),
                    1 => (n, t),
                    2 => (n - t, n),
                    _ => (0, n - t),
                };
                let along = if forward { t } else { n - t };
                let idx = edge_base[e] + (along - 1) as u32;
                grid[a * (n + 1) + b] = idx;
            }
            if first {
                // Push params in the edge's canonical order (along = 1..n).
                for along in 1..n {
                    let t = if forward { along } else { n - along };
                    let (a, b) = match i {
                        0 => (t, 0),
                        1 => (n, t),
                        2 => (n - t, n),
                        _ => (0, n - t),
                    };
                    params.push(param(a, b));
                }
            }
        }
        // Interior.
        for a in 1..n {
            for b in 1..n {
                grid[a * (n + 1) + b] = params.len() as u32;
                params.push(param(a, b));
            }
        }
        for a in 0..n {
            for b in 0..n {
                let g = |a: usize, b: usize| grid[a * (n + 1) + b];
                face_verts.extend_from_slice(&[g(a, b), g(a + 1, b), g(a + 1, b + 1), g(a, b + 1)]);
                face_offsets.push(face_verts.len() as u32);
                source.push(f as u32);
            }
        }
    }
    let evaluated: Vec<([f64; 3], [f64; 3])> = params
        .par_iter()
        .map(|&(f, u, v)| surface.eval(f, u, v).map(|d| (d.p, d.normal())))
        .collect::<Result<_, _>>()?;
    let (positions, normals) = evaluated.into_iter().unzip();
    Ok(SplineTessellation {
        rate,
        positions,
        normals,
        params,
        face_offsets,
        face_verts,
        source,
    })
}

/// A colour index per face such that faces sharing an edge get different indices (greedy
/// colouring in face order; at most `1 +` the largest number of edge neighbours, 5 for
/// quads), for pictures like the paper's Fig. 7 where neighbouring patches differ in colour.
///
/// # Errors
/// [`SplineError::Mesh`] for an invalid mesh.
pub fn face_colours(mesh: &PolyMesh) -> Result<Vec<u8>, SplineError> {
    let (topo, _) = Topology::from_mesh(mesh, &Options::default())?;
    let mut colour = vec![u8::MAX; topo.num_faces()];
    for f in 0..topo.num_faces() {
        let mut used = 0u64;
        for &e in topo.face_edge_list(f) {
            for &g in topo.edge_face_list(e as usize) {
                let c = colour[g as usize];
                if c < 64 {
                    used |= 1 << c;
                }
            }
        }
        colour[f] = (!used).trailing_zeros().min(63) as u8;
    }
    Ok(colour)
}
