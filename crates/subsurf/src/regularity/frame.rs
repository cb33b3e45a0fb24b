//! A global `(i, j)` labelling of a quad mesh: which edges are u-edges and which way they
//! point, as the paper's indices `p_ij` assume (§1.1.1: `Δu(p_ij) = p_i,j+1 − p_ij`,
//! `Δv(p_ij) = p_i+1,j − p_ij`).
//!
//! Each face gets a rotation `r`: its u-edges run from corner `r` to `r+1` and from `r+3` to
//! `r+2`, its v-edges from `r` to `r+3` and from `r+1` to `r+2` (indices mod 4). Crossing a
//! shared edge that is side `q = (k − r) mod 4` of face `f` (side 0: `v = 0`, 1: `u = 1`,
//! 2: `v = 1`, 3: `u = 0`) and edge `m` of its neighbour `g`, the neighbour's frame is
//! `s = (m − (q + 2)) mod 4` (the side becomes the opposite side of `g`, and the two faces
//! run the edge in opposite directions). The frames are propagated breadth-first per
//! connected component; a contradiction (a quad strip that closes with a twist, e.g.
//! around an interior vertex of valence other than 4) means there is no global labelling.

use std::collections::VecDeque;

use super::cone::Difference;
use crate::mesh::Topology;

/// Why a mesh has no global labelling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoFrame {
    /// The face is not a quad or is a hole.
    NotQuad {
        /// The face.
        face: u32,
    },
    /// The edge has more than two faces or is run in the same direction by both.
    NonManifold {
        /// An end vertex of the edge.
        a: u32,
        /// The other end.
        b: u32,
    },
    /// Propagating the frames around a loop of faces comes back to this face rotated.
    Twisted {
        /// The face.
        face: u32,
    },
}

impl std::fmt::Display for NoFrame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::NotQuad { face } => write!(f, "face {face} is not a quad (or is a hole)"),
            Self::NonManifold { a, b } => {
                write!(f, "edge {a}-{b} is non-manifold or inconsistently oriented")
            }
            Self::Twisted { face } => write!(
                f,
                "no consistent u/v labelling: the frames come back rotated at face {face}"
            ),
        }
    }
}

/// A global labelling: per face its rotation and connected component.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frames {
    /// Rotation of each face (see the module docs).
    pub rotation: Vec<u8>,
    /// Component of each face (0, 1, …, in order of their lowest face).
    pub component: Vec<u32>,
    /// Number of components.
    pub num_components: usize,
}

impl Frames {
    /// The labelling of `t`'s faces.
    pub fn new(t: &Topology) -> Result<Self, NoFrame> {
        let nf = t.num_faces();
        for f in 0..nf {
            if t.face_vertices(f).len() != 4 || t.is_hole(f) {
                return Err(NoFrame::NotQuad { face: f as u32 });
            }
        }
        const UNSET: u8 = u8::MAX;
        let mut rotation = vec![UNSET; nf];
        let mut component = vec![0u32; nf];
        let mut num_components = 0;
        let mut queue = VecDeque::new();
        for start in 0..nf {
            if rotation[start] != UNSET {
                continue;
            }
            rotation[start] = 0;
            component[start] = num_components as u32;
            queue.push_back(start);
            while let Some(f) = queue.pop_front() {
                let fv = t.face_vertices(f);
                let r = rotation[f] as usize;
                for (k, &e) in t.face_edge_list(f).iter().enumerate() {
                    let ef = t.edge_face_list(e as usize);
                    if ef.len() == 1 {
                        continue;
                    }
                    let [a, b] = [fv[k], fv[(k + 1) % 4]];
                    if ef.len() != 2 {
                        return Err(NoFrame::NonManifold { a, b });
                    }
                    let g = if ef[0] as usize == f { ef[1] } else { ef[0] } as usize;
                    let gv = t.face_vertices(g);
                    let Some(m) = (0..4).find(|&m| gv[m] == b && gv[(m + 1) % 4] == a) else {
                        return Err(NoFrame::NonManifold { a, b });
                    };
                    let q = (k + 4 - r) % 4;
                    let s = ((m + 8 - (q + 2)) % 4) as u8;
                    if rotation[g] == UNSET {
                        rotation[g] = s;
                        component[g] = num_components as u32;
                        queue.push_back(g);
                    } else if rotation[g] != s {
                        return Err(NoFrame::Twisted { face: g as u32 });
                    }
                }
            }
            num_components += 1;
        }
        Ok(Self {
            rotation,
            component,
            num_components,
        })
    }

    /// The u- and v-differences of face `f` of `t` in this labelling:
    /// `([u at v=0, u at v=1], [v at u=0, v at u=1])`.
    pub fn face_differences(&self, t: &Topology, f: usize) -> ([Difference; 2], [Difference; 2]) {
        local_differences(t.face_vertices(f), self.rotation[f] as usize)
    }
}

/// The u- and v-differences of a quad `fv` whose u-edge starts at corner `r`.
pub(crate) fn local_differences(fv: &[u32], r: usize) -> ([Difference; 2], [Difference; 2]) {
    let c = |j: usize| fv[(r + j) % 4];
    let d = |from, to| Difference { from, to };
    (
        [d(c(0), c(1)), d(c(3), c(2))],
        [d(c(0), c(3)), d(c(1), c(2))],
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Options, PolyMesh};

    fn topology(pos: Vec<[f64; 3]>, faces: &[[u32; 4]]) -> Topology {
        let mesh = PolyMesh::from_faces(pos, faces).expect("valid mesh");
        Topology::from_mesh(&mesh, &Options::default())
            .expect("topology")
            .0
    }

    #[test]
    fn a_grid_with_rotated_faces_gets_one_consistent_frame() {
        // 2×1 grid; the second face lists its corners starting elsewhere.
        let pos = (0..6)
            .map(|i| [(i % 3) as f64, (i / 3) as f64, 0.0])
            .collect();
        let t = topology(pos, &[[0, 1, 4, 3], [5, 4, 1, 2]]);
        let fr = Frames::new(&t).expect("labelling");
        assert_eq!(fr.num_components, 1);
        let (u0, v0) = fr.face_differences(&t, 0);
        let (u1, v1) = fr.face_differences(&t, 1);
        assert_eq!(u0[0], Difference { from: 0, to: 1 });
        assert_eq!(u1[0], Difference { from: 1, to: 2 });
        assert_eq!(u1[1], Difference { from: 4, to: 5 });
        assert_eq!(v0[1], Difference { from: 1, to: 4 });
        assert_eq!(v1[0], Difference { from: 1, to: 4 });
    }

    #[test]
    fn an_interior_vertex_of_valence_three_twists_the_frames() {
        // Three quads around vertex 0 (a cube corner flattened).
        let pos = vec![[0.0; 3]; 7];
        let t = topology(pos, &[[0, 1, 2, 3], [0, 3, 4, 5], [0, 5, 6, 1]]);
        assert!(matches!(Frames::new(&t), Err(NoFrame::Twisted { .. })));
    }
}
