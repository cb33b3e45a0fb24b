//! A face's patch neighbourhood: the 4×4 control vertices of its bicubic B-spline patch,
//! with the phantom rows and columns across infinitely sharp sides left out, or why the
//! face has no such patch.
//!
//! The criterion and the layout are those of the exact evaluator's regular patches
//! (`limit::patch`, OpenSubdiv's regular, boundary and corner patches): `cells[i][j]`,
//! `i` along `u`, `j` along `v`; the face is the middle cell with corners 0, 1, 2, 3 at
//! `(1,1)`, `(2,1)`, `(2,2)`, `(1,2)`. A corner is regular when it is a smooth interior
//! vertex with four quads, a crease vertex between exactly two infinitely sharp edges whose
//! sector is two quads, or an infinitely sharp corner whose sector is the face alone, with
//! no semi-sharp vertex or edge. Across a sharp side the patch uses the phantom row
//! `P₋₁ = 2 P₀ − P₁`; those cells are `None` here (see [`super`] for why their differences
//! need not be listed).

// The limit surface's regular-patch test: the certificate reads the same neighbourhoods.
use crate::mesh::{Rule, Topology};
use crate::refine::patch::{regular_corner, regular_patch_cells, walk, Sharp};
use crate::scheme::crease;

/// The 16 cells of a patch neighbourhood: a vertex, or `None` for a phantom point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Block {
    /// `cells[i][j]`, `i` along `u`, `j` along `v`.
    pub cells: [[Option<u32>; 4]; 4],
}

/// Why a face has no bicubic patch neighbourhood (the certificate does not apply).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Inapplicable {
    /// The face is not a quad.
    NotQuad {
        /// Number of vertices.
        size: usize,
    },
    /// The face is a hole (no surface).
    Hole,
    /// A corner is an interior vertex of valence other than 4 (an extraordinary vertex:
    /// outside the paper's setting).
    InteriorExtraordinary {
        /// The vertex.
        vertex: u32,
        /// Its number of faces.
        valence: usize,
    },
    /// A corner is a boundary vertex with one face in edge-only mode: the boundary curve
    /// is smooth there, so `S_u` and `S_v` turn antiparallel towards the corner (they tend
    /// to `(A − B)/2` and `(B − A)/2` for its neighbours `A`, `B`: the Jacobian tends to 0,
    /// the parametrisation is singular); tag it as a corner (`edge-and-corner`) to make it
    /// a regular corner.
    SmoothCorner {
        /// The vertex.
        vertex: u32,
    },
    /// A corner is a boundary (or crease) vertex whose sector is not regular (e.g. three
    /// faces at a concave corner): its crease rule mixes u- and v-differences with
    /// negative weights, so the cone argument does not reach it.
    IrregularBoundary {
        /// The vertex.
        vertex: u32,
        /// Number of faces in its sector.
        faces: usize,
    },
    /// A corner has a semi-sharp vertex or edge, a dart, or a non-quad neighbour.
    Feature {
        /// The vertex.
        vertex: u32,
    },
}

impl std::fmt::Display for Inapplicable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::NotQuad { size } => write!(f, "not a quad ({size} vertices)"),
            Self::Hole => write!(f, "a hole"),
            Self::InteriorExtraordinary { vertex, valence } => {
                write!(f, "interior extraordinary vertex {vertex} (valence {valence})")
            }
            Self::SmoothCorner { vertex } => write!(
                f,
                "boundary corner {vertex} is smooth (edge-only): S_u, S_v turn antiparallel there; tag it (edge-and-corner)"
            ),
            Self::IrregularBoundary { vertex, faces } => {
                write!(f, "irregular boundary vertex {vertex} ({faces} faces in its sector)")
            }
            Self::Feature { vertex } => write!(
                f,
                "vertex {vertex}: semi-sharp feature, dart or non-quad neighbour"
            ),
        }
    }
}

/// The patch neighbourhood of face `f` of `t`: the control net of the limit surface's
/// regular patch (`refine::patch::regular_patch_cells`, so the certificate applies to exactly the faces
/// that are bicubic patches there), phantom cells left out; or why there is none.
pub fn block(t: &Topology, f: usize) -> Result<Block, Inapplicable> {
    let fv = t.face_vertices(f);
    if fv.len() != 4 {
        return Err(Inapplicable::NotQuad { size: fv.len() });
    }
    if t.is_hole(f) {
        return Err(Inapplicable::Hole);
    }
    let Some(net) = regular_patch_cells(t, f) else {
        let irregular = (0..4).find(|&k| regular_corner(t, f, k, Sharp::LIMIT).is_none());
        return Err(match irregular {
            Some(k) => why_irregular(t, f, k),
            // Every corner is regular, so the net exists: not reached.
            None => Inapplicable::Feature { vertex: fv[0] },
        });
    };
    let fe = t.face_edge_list(f);
    let sharp = [0, 1, 2, 3].map(|k| t.edge_tag(fe[k] as usize).inf_sharp);
    let cells = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let phantom = (j == 0 && sharp[0])
                || (i == 3 && sharp[1])
                || (j == 3 && sharp[2])
                || (i == 0 && sharp[3]);
            (!phantom).then_some(net[i][j].verts[0])
        })
    });
    Ok(Block { cells })
}

/// Why corner `k` of quad `f` is not a regular patch corner
/// ([`regular_corner`] is `None`), for the report.
fn why_irregular(t: &Topology, f: usize, k: usize) -> Inapplicable {
    let c = t.face_vertices(f)[k] as usize;
    let vertex = c as u32;
    let tag = t.vertex_tag(c);
    let feature = Inapplicable::Feature { vertex };
    if tag.semi_sharp
        || crease::is_semi_sharp(t.vertex_sharpness(c))
        || t.vertex_edges(c)
            .iter()
            .any(|&e| t.edge_tag(e as usize).semi_sharp)
    {
        return feature;
    }
    let (ccw, closed) = walk(t, f, c, true, Sharp::LIMIT);
    let inf_edges = t
        .vertex_edges(c)
        .iter()
        .filter(|&&e| t.edge_tag(e as usize).inf_sharp)
        .count();
    if closed {
        return if inf_edges == 0 && ccw.len() != 3 {
            Inapplicable::InteriorExtraordinary {
                vertex,
                valence: t.vertex_faces(c).len(),
            }
        } else {
            feature
        };
    }
    let (cw, _) = walk(t, f, c, false, Sharp::LIMIT);
    let sector = 1 + ccw.len() + cw.len();
    if !tag.boundary && !tag.non_manifold && inf_edges == 0 {
        // A fan too long for the walk: valence above 5.
        return Inapplicable::InteriorExtraordinary {
            vertex,
            valence: t.vertex_faces(c).len(),
        };
    }
    if tag.boundary && tag.rule == Rule::Crease && sector == 1 && t.vertex_faces(c).len() == 1 {
        return Inapplicable::SmoothCorner { vertex };
    }
    if tag.boundary || inf_edges >= 2 {
        return Inapplicable::IrregularBoundary {
            vertex,
            faces: sector,
        };
    }
    feature
}
