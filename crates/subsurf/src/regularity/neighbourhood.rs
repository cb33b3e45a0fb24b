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

// The fan walk of the limit surface's regular-patch test: both read the same neighbourhoods.
use crate::limit::patch::walk;
use crate::mesh::{Rule, Topology};
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

/// The patch neighbourhood of face `f` of `t`.
pub fn block(t: &Topology, f: usize) -> Result<Block, Inapplicable> {
    let fv = t.face_vertices(f);
    if fv.len() != 4 {
        return Err(Inapplicable::NotQuad { size: fv.len() });
    }
    if t.is_hole(f) {
        return Err(Inapplicable::Hole);
    }
    let mut cells = [[None; 4]; 4];
    const CORNER: [(i32, i32); 4] = [(1, 1), (2, 1), (2, 2), (1, 2)];
    let rot = |k: usize, (x, y): (i32, i32)| {
        let (mut x, mut y) = (x, y);
        for _ in 0..k {
            (x, y) = (-y, x);
        }
        (x, y)
    };
    let mut put = |k: usize, off: (i32, i32), v: u32| {
        let (dx, dy) = rot(k, off);
        cells[(CORNER[k].0 + dx) as usize][(CORNER[k].1 + dy) as usize] = Some(v);
    };
    for k in 0..4 {
        put(k, (0, 0), fv[k]);
    }
    for k in 0..4 {
        let q = |(g, m): (usize, usize), d: usize| t.face_vertices(g)[(m + d) % 4];
        match corner(t, f, k)? {
            Corner::Closed(ring) => {
                put(k, (-1, 1), q(ring[0], 2));
                put(k, (-1, 0), q(ring[0], 3));
                put(k, (-1, -1), q(ring[1], 2));
                put(k, (0, -1), q(ring[1], 3));
                put(k, (1, -1), q(ring[2], 2));
            }
            Corner::Sector { ccw, cw } => {
                for &g in &ccw {
                    put(k, (-1, 1), q(g, 2));
                    put(k, (-1, 0), q(g, 3));
                }
                for &g in &cw {
                    put(k, (0, -1), q(g, 1));
                    put(k, (1, -1), q(g, 2));
                }
            }
        }
    }
    let fe = t.face_edge_list(f);
    let sharp = [0, 1, 2, 3].map(|k| t.edge_tag(fe[k] as usize).inf_sharp);
    for i in 0..4 {
        for j in 0..4 {
            let phantom = (j == 0 && sharp[0])
                || (i == 3 && sharp[1])
                || (j == 3 && sharp[2])
                || (i == 0 && sharp[3]);
            if phantom {
                cells[i][j] = None;
            } else if cells[i][j].is_none() {
                // Not reached for a regular patch; refuse rather than guess.
                return Err(Inapplicable::Feature { vertex: fv[0] });
            }
        }
    }
    Ok(Block { cells })
}

enum Corner {
    Closed([(usize, usize); 3]),
    Sector {
        ccw: Vec<(usize, usize)>,
        cw: Vec<(usize, usize)>,
    },
}

/// Corner `k` of quad `f`: regular (with its neighbour faces), or why not.
fn corner(t: &Topology, f: usize, k: usize) -> Result<Corner, Inapplicable> {
    let c = t.face_vertices(f)[k] as usize;
    let vertex = c as u32;
    let tag = t.vertex_tag(c);
    let feature = Inapplicable::Feature { vertex };
    if tag.semi_sharp || crease::is_semi_sharp(t.vertex_sharpness(c)) {
        return Err(feature);
    }
    if t.vertex_edges(c)
        .iter()
        .any(|&e| t.edge_tag(e as usize).semi_sharp)
    {
        return Err(feature);
    }
    let (ccw, closed) = walk(t, f, c, true);
    let inf_edges = t
        .vertex_edges(c)
        .iter()
        .filter(|&&e| t.edge_tag(e as usize).inf_sharp)
        .count();
    let quads =
        |faces: &[(usize, usize)]| faces.iter().all(|&(g, _)| t.face_vertices(g).len() == 4);
    if closed {
        if tag.rule == Rule::Smooth && inf_edges == 0 && ccw.len() == 3 && quads(&ccw) {
            return Ok(Corner::Closed([ccw[0], ccw[1], ccw[2]]));
        }
        if inf_edges == 0 && ccw.len() != 3 {
            return Err(Inapplicable::InteriorExtraordinary {
                vertex,
                valence: t.vertex_faces(c).len(),
            });
        }
        return Err(feature);
    }
    let (cw, _) = walk(t, f, c, false);
    let sector = 1 + ccw.len() + cw.len();
    let ok = match tag.rule {
        Rule::Crease => inf_edges == 2 && sector == 2,
        Rule::Corner => sector == 1 && (tag.inf_sharp || inf_edges > 2),
        Rule::Smooth | Rule::Dart => false,
    };
    if ok && quads(&ccw) && quads(&cw) {
        return Ok(Corner::Sector { ccw, cw });
    }
    if !tag.boundary && !tag.non_manifold && inf_edges == 0 {
        // A fan too long for the walk: valence above 5.
        return Err(Inapplicable::InteriorExtraordinary {
            vertex,
            valence: t.vertex_faces(c).len(),
        });
    }
    if tag.boundary && tag.rule == Rule::Crease && sector == 1 && t.vertex_faces(c).len() == 1 {
        return Err(Inapplicable::SmoothCorner { vertex });
    }
    if tag.boundary || inf_edges >= 2 {
        return Err(Inapplicable::IrregularBoundary {
            vertex,
            faces: sector,
        });
    }
    Err(feature)
}
