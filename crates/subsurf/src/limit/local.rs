//! Local neighbourhoods: the part of a level that determines the limit surface over one
//! face, cut out as a small mesh of its own so that it can be refined on its own.
//!
//! The limit surface over a face `f` depends on the faces around `f`'s vertices (its
//! 1-ring); the rules and sharpness of those faces' elements depend on one ring more.
//! The *2-ring* (faces sharing a vertex with a face that shares a vertex with `f`) is
//! therefore enough to refine `f` exactly any number of levels: every element whose
//! position matters has all its neighbours. The cut-out is a [`Topology::subset`]: edges,
//! tags, sharpness and rules are copied from the level, not re-derived, so it refines
//! exactly as the whole level would around `f`. Elements on the cut-out's rim have
//! incomplete neighbourhoods, but they never influence `f`'s children.

use crate::mesh::Topology;

/// A face of a small mesh cut out around it, with positions.
#[derive(Clone, Debug)]
pub struct Local {
    /// The cut-out topology (tags and rules derived as for a base mesh).
    pub topo: Topology,
    /// Positions of its vertices.
    pub pos: Vec<[f64; 3]>,
    /// The face of interest in `topo` (its vertex order is the original face's).
    pub face: usize,
}

/// Cuts the 2-ring of face `f` out of level `t` (positions `pos`).
pub fn extract(t: &Topology, pos: &[[f64; 3]], f: usize) -> Local {
    // Faces: f first, then the rest of its 2-ring, each once. Cut-outs of cut-outs are
    // small, so a mark per face is cheap there; on a large level, search the short list.
    let mut marks = if t.num_faces() <= 1 << 14 {
        vec![false; t.num_faces()]
    } else {
        Vec::new()
    };
    if let Some(m) = marks.get_mut(f) {
        *m = true;
    }
    let mut faces = vec![f as u32];
    let mut add = |g: u32, faces: &mut Vec<u32>| {
        let seen = match marks.get_mut(g as usize) {
            Some(m) => std::mem::replace(m, true),
            None => faces.contains(&g),
        };
        if !seen && g as usize != f {
            faces.push(g);
        }
    };
    for &v in t.face_vertices(f) {
        for &g in t.vertex_faces(v as usize) {
            add(g, &mut faces);
        }
    }
    let ring1 = faces.len();
    for i in 0..ring1 {
        for &v in t.face_vertices(faces[i] as usize) {
            for &g in t.vertex_faces(v as usize) {
                add(g, &mut faces);
            }
        }
    }
    let (topo, verts) = t.subset(&faces);
    let pos = verts.iter().map(|&v| pos[v as usize]).collect();
    Local { topo, pos, face: 0 }
}
