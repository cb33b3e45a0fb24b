//! Regular patches: when the limit surface over a quad is one bicubic B-spline patch, and
//! its 16 control points (with phantom points across boundaries and infinitely sharp
//! creases).
//!
//! A quad `f` is *regular* when, for each of its four corners `c`, looking only at the
//! *sector* of faces around `c` that contains `f` and is bounded by infinitely sharp edges
//! (boundary and non-manifold edges are infinitely sharp):
//! - smooth: no sharp edge at `c`, `c` not sharp, four quads around it; or
//! - crease: `c` has the crease rule from exactly two infinitely sharp edges, and the
//!   sector is two quads; or
//! - corner: `c` has the corner rule, is not semi-sharp, and the sector is `f` alone;
//!
//! and no edge at a corner is semi-sharp. Then the Catmull-Clark rules that shape `f`'s
//! limit surface at every later level are the uniform B-spline rules, with the boundary
//! and crease rules reproduced by *phantom* points: across a sharp side the missing row is
//! `P₋₁ = 2 P₀ − P₁` (so the B-spline rules give `⅛, ¾, ⅛` along the side and the side
//! curve is the cubic B-spline of its points), and a corner cell is extrapolated in both
//! directions, `4 P₀₀ − 2 P₁₀ − 2 P₀₁ + P₁₁`, which keeps the corner fixed. The two sides of an
//! infinitely sharp crease do not influence each other, so each side is such a patch.
//! This is the construction of OpenSubdiv's regular boundary and corner patches.

use crate::mesh::{CreaseMethod, Rule, Topology};
use crate::scheme::crease;
use std::sync::OnceLock;

/// An index type of the compact tables of configuration trees: 8-bit or 16-bit where the
/// indices fit (nearly always: a tree node reads a few dozen to a few thousand points),
/// else 32-bit.
pub(crate) trait Index: Copy {
    /// `x` if it fits.
    fn narrow(x: u32) -> Option<Self>;
    /// The index.
    fn get(self) -> usize;
}

/// [`Index`] for unsigned types narrower than `u32`.
macro_rules! narrow_index {
    ($($t:ty),*) => {$(
        impl Index for $t {
            fn narrow(x: u32) -> Option<Self> {
                <$t>::try_from(x).ok()
            }
            #[inline]
            fn get(self) -> usize {
                usize::from(self)
            }
        }
    )*};
}

narrow_index!(u8, u16);

impl Index for u32 {
    fn narrow(x: u32) -> Option<Self> {
        Some(x)
    }
    #[inline]
    fn get(self) -> usize {
        self as usize
    }
}

/// Which edges and vertices the patch tests treat as infinitely sharp: those that are
/// (sharpness ≥ 10, boundary and non-manifold edges) and, for a bounded number of
/// refinement levels, semi-sharp ones that stay sharp through all of them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sharp {
    /// Semi-sharp edges and vertices of at least this sharpness count as infinitely sharp.
    from: f32,
}

/// How [`Sharp`] sees an edge or a vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Feature {
    Smooth,
    /// Infinitely sharp, or sharp through all the levels that matter.
    Sharp,
    /// Semi-sharp and softening within them: no patch has the same rules.
    Softening,
}

impl Sharp {
    /// For the limit surface: only the infinitely sharp.
    pub(crate) const LIMIT: Sharp = Sharp {
        from: f32::INFINITY,
    };

    /// For `levels` levels of refinement with `method`. With the uniform decay an edge's
    /// sharpness drops by 1 per level, and a step whose parent sharpness is at least 1
    /// applies the crease rules (at exactly 1 the child is smooth, and OpenSubdiv's
    /// transitional blend weighs the crease rule by the parent sharpness, 1): an edge
    /// (or vertex) of sharpness `s ≥ levels` keeps the rules of an infinitely sharp one for
    /// all `levels`. With Chaikin's decay a child's sharpness depends on its neighbours,
    /// so only the infinitely sharp count.
    pub(crate) fn for_levels(levels: u32, method: CreaseMethod) -> Sharp {
        match method {
            CreaseMethod::Uniform => Sharp {
                from: levels as f32,
            },
            CreaseMethod::Chaikin => Sharp::LIMIT,
        }
    }

    fn edge(self, t: &Topology, e: usize) -> Feature {
        let tag = t.edge_tag(e);
        if tag.inf_sharp || (tag.semi_sharp && t.edge_sharpness(e) >= self.from) {
            Feature::Sharp
        } else if tag.semi_sharp {
            Feature::Softening
        } else {
            Feature::Smooth
        }
    }

    fn vertex(self, t: &Topology, v: usize) -> Feature {
        let (tag, s) = (t.vertex_tag(v), t.vertex_sharpness(v));
        let semi = tag.semi_sharp || crease::is_semi_sharp(s);
        if tag.inf_sharp || (semi && s >= self.from) {
            Feature::Sharp
        } else if semi {
            Feature::Softening
        } else {
            Feature::Smooth
        }
    }
}

/// One control point of a regular patch as a combination of at most four vertices of
/// its level: a vertex itself, or a phantom point extrapolated across a sharp side
/// (`2 P₀ − P₁`, or `4 P₀₀ − 2 P₁₀ − 2 P₀₁ + P₁₁` in a corner cell).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Cell {
    /// Vertices (the first `len` are used).
    pub verts: [u32; 4],
    /// Their weights (summing to 1).
    pub weights: [f64; 4],
    /// Number of terms.
    pub len: usize,
}

impl Cell {
    fn vertex(v: u32) -> Self {
        Cell {
            verts: [v, 0, 0, 0],
            weights: [1.0, 0.0, 0.0, 0.0],
            len: 1,
        }
    }

    /// `2 a − b`.
    fn extrapolate(a: &Cell, b: &Cell) -> Cell {
        let mut c = Cell::default();
        let terms = (a.verts.iter().zip(&a.weights).take(a.len))
            .map(|(&v, &w)| (v, 2.0 * w))
            .chain((b.verts.iter().zip(&b.weights).take(b.len)).map(|(&v, &w)| (v, -w)));
        for (v, w) in terms {
            match c.verts[..c.len].iter().position(|&x| x == v) {
                Some(i) => c.weights[i] += w,
                // At most four distinct vertices by construction (module docs); a fifth
                // would mean a broken walk, and is dropped rather than overflow.
                None if c.len < 4 => {
                    c.verts[c.len] = v;
                    c.weights[c.len] = w;
                    c.len += 1;
                }
                None => {}
            }
        }
        c
    }

    /// The point `Σ wₖ pos[vₖ]` (of any number `D` of components).
    #[inline]
    pub(crate) fn eval<const D: usize>(&self, pos: &[[f64; D]]) -> [f64; D] {
        let mut acc = [0.0; D];
        for (&v, &w) in self.verts.iter().zip(&self.weights).take(self.len) {
            let p = &pos[v as usize];
            (0..D).for_each(|k| acc[k] += w * p[k]);
        }
        acc
    }
}

/// The 16 control points of a patch as combinations of vertices, kept to evaluate them
/// again when the vertices move ([`LimitSurface::set_positions`]) without walking the
/// topology again: vertex indices when every cell is one vertex (64 bytes; every patch
/// away from boundaries and creases); at a boundary or an infinitely sharp crease, the
/// vertex indices and the sharp sides, the phantom cells evaluated from a table of
/// their terms per set of sharp sides ([`sided_terms`]: the same sums as [`Net::Cells`],
/// in the same order); else (where a phantom cell does not
/// come out the same, as when a degenerate face repeats a vertex) the cells (896
/// bytes).
///
/// The vertex indices are of type `I`: `u32`, or `u8` in configuration trees, whose nets
/// index a node's refined points ([`Net::narrow`]).
///
/// [`LimitSurface::set_positions`]: crate::limit::LimitSurface::set_positions
#[derive(Clone, Debug)]
pub(crate) enum Net<I = u32> {
    Plain([I; 16]),
    /// Vertex `v[4 i + j]` in cell `[i][j]` (0 in a phantom cell), and the sharp sides
    /// in [`fill_phantoms`]' order.
    Sided([I; 16], [bool; 4]),
    Cells(Box<[[Cell; 4]; 4]>),
}

impl Net {
    pub(crate) fn new(cells: [[Cell; 4]; 4]) -> Self {
        let is_vertex = |c: &Cell| c.len == 1 && c.weights[0] == 1.0;
        let verts = |keep: &dyn Fn(&Cell) -> bool| -> [u32; 16] {
            std::array::from_fn(|k| {
                let c = &cells[k / 4][k % 4];
                if keep(c) {
                    c.verts[0]
                } else {
                    0
                }
            })
        };
        if cells.iter().flatten().all(is_vertex) {
            return Net::Plain(verts(&|_| true));
        }
        // A side is sharp where the middle cells beyond it are phantoms; kept as sides if
        // filling them in again gives these very cells.
        let sides = [&cells[1][0], &cells[3][1], &cells[1][3], &cells[0][1]].map(|c| !is_vertex(c));
        let v = verts(&is_vertex);
        if table_cells(&v, sides) == cells {
            Net::Sided(v, sides)
        } else {
            Net::Cells(Box::new(cells))
        }
    }

    /// The same net with indices of type `J`, if they fit.
    pub(crate) fn narrow<J: Index>(&self) -> Option<Net<J>> {
        let narrow = |v: &[u32; 16]| -> Option<[J; 16]> {
            let mut out = [J::narrow(0)?; 16];
            for (o, &x) in out.iter_mut().zip(v) {
                *o = J::narrow(x)?;
            }
            Some(out)
        };
        Some(match self {
            Net::Plain(v) => Net::Plain(narrow(v)?),
            Net::Sided(v, sides) => Net::Sided(narrow(v)?, *sides),
            Net::Cells(c) => Net::Cells(c.clone()),
        })
    }
}

impl<I: Index> Net<I> {
    /// The control points `cp[i][j]` for vertex positions `pos` (`i` along `u`, `j` along
    /// `v`).
    pub(crate) fn eval(&self, pos: &[[f64; 3]]) -> [[[f64; 3]; 4]; 4] {
        let mut cp = [[[0.0; 3]; 4]; 4];
        self.eval_into(pos, &mut cp);
        cp
    }

    /// [`eval`](Self::eval) into `cp`, every point overwritten: where the net is not
    /// inlined into its caller, a returned net would be copied again (a `memmove` per
    /// evaluation).
    pub(crate) fn eval_into(&self, pos: &[[f64; 3]], cp: &mut [[[f64; 3]; 4]; 4]) {
        let cp = cp.as_flattened_mut();
        match self {
            Net::Plain(v) => {
                // A loop of copies: nested `array::from_fn` built each point in a
                // temporary and read it back across two stores (a stalled store
                // forward per point, a quarter of evaluating a tree of creases).
                for (c, &k) in cp.iter_mut().zip(v) {
                    *c = pos[k.get()];
                }
            }
            Net::Sided(v, sides) => {
                // As `Cell::eval` on each cell (`Net::new` checked that the table's
                // terms are the cells'), without making the cells.
                for (c, t) in cp.iter_mut().zip(sided_terms(*sides)) {
                    let mut acc = [0.0; 3];
                    for (&k, &w) in t.at.iter().zip(&t.weights).take(usize::from(t.len)) {
                        let p = &pos[v[usize::from(k)].get()];
                        (0..3).for_each(|d| acc[d] += w * p[d]);
                    }
                    *c = acc;
                }
            }
            Net::Cells(cells) => {
                for (c, cell) in cp.iter_mut().zip(cells.as_flattened()) {
                    *c = cell.eval(pos);
                }
            }
        }
    }

    /// The cells the net stands for.
    #[cfg(test)]
    pub(crate) fn cells(&self) -> [[Cell; 4]; 4] {
        match self {
            Net::Plain(v) => sided_cells(&wide(v), [false; 4]),
            Net::Sided(v, sides) => table_cells(&wide(v), *sides),
            Net::Cells(c) => **c,
        }
    }
}

/// Indices `v` as `u32`.
#[cfg(test)]
fn wide<I: Index>(v: &[I; 16]) -> [u32; 16] {
    v.map(|x| x.get() as u32)
}

/// The terms of one cell of a [`Net::Sided`]: weights on entries `at` of its vertex list.
#[derive(Clone, Copy, Debug, Default)]
struct Terms {
    at: [u8; 4],
    weights: [f64; 4],
    len: u8,
}

/// The terms of the cells of a [`Net::Sided`] with sharp `sides`, cell `[i][j]` at
/// `4 i + j`: those of [`sided_cells`] on the vertex list `0, 1, …, 15`, made once per
/// set of sides. They are those of a net's own cells unless two of the vertices a phantom
/// cell combines are the same (the cell then has fewer terms), which [`Net::new`] checks
/// ([`table_cells`]). Made once, not at each evaluation: the 16 cells are 900 bytes,
/// costly to build next to the evaluation of a shape with boundaries through its trees.
fn sided_terms(sides: [bool; 4]) -> &'static [Terms; 16] {
    static TABLE: OnceLock<[[Terms; 16]; 16]> = OnceLock::new();
    let table = TABLE.get_or_init(|| {
        std::array::from_fn(|set| {
            let sides = std::array::from_fn(|b| set >> b & 1 == 1);
            let cells = sided_cells(&std::array::from_fn(|k| k as u32), sides);
            std::array::from_fn(|k| {
                let c = &cells[k / 4][k % 4];
                Terms {
                    at: c.verts.map(|v| v as u8),
                    weights: c.weights,
                    len: c.len as u8,
                }
            })
        })
    });
    let set = (0..4).filter(|&b| sides[b]).fold(0, |set, b| set | 1 << b);
    &table[set]
}

/// The cells [`sided_terms`] stands for with the vertex list `v`.
fn table_cells(v: &[u32; 16], sides: [bool; 4]) -> [[Cell; 4]; 4] {
    let terms = sided_terms(sides);
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let t = &terms[4 * i + j];
            let mut c = Cell {
                len: usize::from(t.len),
                ..Cell::default()
            };
            for n in 0..c.len {
                (c.verts[n], c.weights[n]) = (v[usize::from(t.at[n])], t.weights[n]);
            }
            c
        })
    })
}

/// The cells of a [`Net::Sided`]: vertex `v[4 i + j]` in cell `[i][j]`, then the phantom
/// cells across the sharp `sides` ([`fill_phantoms`]).
fn sided_cells(v: &[u32; 16], sides: [bool; 4]) -> [[Cell; 4]; 4] {
    let mut cells = std::array::from_fn(|i| std::array::from_fn(|j| Cell::vertex(v[4 * i + j])));
    fill_phantoms(&mut cells, sides);
    cells
}

/// The control points of quad `f`, if it is regular (see the module docs), as
/// combinations of vertices of `t`: `cells[i][j]`, `i` along `u`, `j` along `v`.
pub(crate) fn regular_patch_cells(t: &Topology, f: usize) -> Option<[[Cell; 4]; 4]> {
    if t.is_hole(f) {
        return None;
    }
    patch_cells(
        t,
        f,
        |k| regular_corner(t, f, k, Sharp::LIMIT),
        Sharp::LIMIT,
    )
}

/// [`regular_patch_cells`] for refinement through the levels for which `sharp` is made
/// ([`Sharp::for_levels`]): the same net, also on a hole, and with the semi-sharp edges
/// and vertices that stay sharp through those levels taken as infinitely sharp. A hole
/// has no limit surface, but holes only hide faces: the refined vertices inside one
/// follow the same rules as anywhere else, so the net gives them too.
pub(crate) fn refinement_patch_cells(
    t: &Topology,
    f: usize,
    sharp: Sharp,
) -> Option<[[Cell; 4]; 4]> {
    patch_cells(t, f, |k| regular_corner(t, f, k, sharp), sharp)
}

/// The 4×4 control net of quad `f` with the corner analysis `corner`, with phantom points
/// across the sides that `sharp` takes as infinitely sharp, if every corner passes
/// `corner` (on holes too: the callers that need a limit surface check for holes).
pub(crate) fn patch_cells(
    t: &Topology,
    f: usize,
    corner: impl Fn(usize) -> Option<Corner>,
    sharp: Sharp,
) -> Option<[[Cell; 4]; 4]> {
    let fv = t.face_vertices(f);
    if fv.len() != 4 {
        return None;
    }
    let mut cp = [[Cell::default(); 4]; 4];
    let mut put = |k: usize, off: (i32, i32), v: u32| {
        let (i, j) = net_cell(k, off);
        cp[i][j] = Cell::vertex(v);
    };
    for k in 0..4 {
        put(k, (0, 0), fv[k]);
    }
    for k in 0..4 {
        match corner(k)? {
            Corner::Closed(ring) => {
                for (off, v) in closed_ring(t, &ring) {
                    put(k, off, v);
                }
            }
            Corner::Sector { ccw, cw } => {
                for &(g, m) in &ccw {
                    let q = |d: usize| t.face_vertices(g)[(m + d) % 4];
                    put(k, (-1, 1), q(2));
                    put(k, (-1, 0), q(3));
                }
                for &(g, m) in &cw {
                    let q = |d: usize| t.face_vertices(g)[(m + d) % 4];
                    put(k, (0, -1), q(1));
                    put(k, (1, -1), q(2));
                }
            }
        }
    }
    let fe = t.face_edge_list(f);
    let sides = [0, 1, 2, 3].map(|k| sharp.edge(t, fe[k] as usize) == Feature::Sharp);
    fill_phantoms(&mut cp, sides);
    Some(cp)
}

/// The cell of a quad's 4 × 4 net that holds the point at offset `off` from its corner
/// `k`, the offset in the corner's own frame: corner `k` sits at cell
/// `[(1, 1), (2, 1), (2, 2), (1, 2)][k]`, and its frame is corner 0's turned `k` quarter
/// turns counter-clockwise (`u → v`), so that `(−1, −1)` is always diagonally away from
/// the quad.
fn net_cell(k: usize, off: (i32, i32)) -> (usize, usize) {
    const CORNER: [(i32, i32); 4] = [(1, 1), (2, 1), (2, 2), (1, 2)];
    let (mut x, mut y) = off;
    for _ in 0..k {
        (x, y) = (-y, x);
    }
    ((CORNER[k].0 + x) as usize, (CORNER[k].1 + y) as usize)
}

/// The 16 control points of quad `f` as vertices (`net[4 i + j]`, `i` along `u`, as
/// [`Net::Plain`]), read from the topology alone, for a quad whose net is plain: every
/// corner a smooth manifold vertex of four quads. Each corner `c` brings itself and the
/// three other vertices of the face diagonally across it, the face two steps from `f` in
/// `c`'s counter-clockwise ring of four (the [`Topology`] module docs): `(−1, 0)`,
/// `(−1, −1)` and `(0, −1)` in `c`'s frame ([`net_cell`]); the four corners' diagonal faces
/// cover the net. `None` when a corner does not have four faces around it, or its diagonal
/// face is not a quad.
///
/// The same net as [`regular_patch_cells`] finds by walking each corner's edges, with a
/// fraction of the reads: a limit surface keeps nothing for such a face and gathers its
/// net when it is evaluated (its builder checks that both agree).
pub(crate) fn plain_net(t: &Topology, f: usize) -> Option<[u32; 16]> {
    /// `net_cell(k, off)` as `4 i + j`, for the offsets `(0, 0)`, `(−1, 0)`, `(−1, −1)`,
    /// `(0, −1)` of the corner itself and its diagonal face's next three vertices.
    const CELLS: [[usize; 4]; 4] = [[5, 1, 0, 4], [9, 8, 12, 13], [10, 14, 15, 11], [6, 7, 3, 2]];
    let fv = t.face_vertices(f);
    if fv.len() != 4 {
        return None;
    }
    let mut net = [0; 16];
    for (k, &c) in fv.iter().enumerate() {
        let (faces, locals) = (t.vertex_faces(c as usize), t.vertex_face_locals(c as usize));
        if faces.len() != 4 {
            return None;
        }
        let i = (0..4).find(|&i| faces[i] as usize == f && usize::from(locals[i]) == k)?;
        let (g, m) = (
            faces[(i + 2) % 4] as usize,
            usize::from(locals[(i + 2) % 4]),
        );
        let gv = t.face_vertices(g);
        if gv.len() != 4 {
            return None;
        }
        for (d, &cell) in CELLS[k].iter().enumerate() {
            net[cell] = gv[(m + d) % 4];
        }
    }
    Some(net)
}

/// The five points beyond the quad around a smooth valence-4 corner whose other faces are
/// `ring` ([`Corner::Closed`]), each with its offset from the corner in the corner's frame
/// ([`net_cell`]).
fn closed_ring(t: &Topology, ring: &[(usize, usize); 3]) -> [((i32, i32), u32); 5] {
    let q = |(g, m): (usize, usize), d: usize| t.face_vertices(g)[(m + d) % 4];
    [
        ((-1, 1), q(ring[0], 2)),
        ((-1, 0), q(ring[0], 3)),
        ((-1, -1), q(ring[1], 2)),
        ((0, -1), q(ring[1], 3)),
        ((1, -1), q(ring[2], 2)),
    ]
}

/// The faces around a regular corner, as [`regular_corner`] finds them: each item is
/// `(face, position of the corner in it)`.
pub(crate) enum Corner {
    /// A smooth interior vertex of valence 4: the three other faces, counter-clockwise
    /// from the face.
    Closed([(usize, usize); 3]),
    /// A sector bounded by infinitely sharp edges: the faces counter-clockwise and
    /// clockwise from the face (one of them for a crease, none for a corner).
    Sector {
        /// Counter-clockwise neighbours.
        ccw: Vec<(usize, usize)>,
        /// Clockwise neighbours.
        cw: Vec<(usize, usize)>,
    },
}

/// Whether corner `k` of quad `f` is regular (see the module docs), with the edges and
/// vertices that `sharp` takes as infinitely sharp, and its neighbours.
pub(crate) fn regular_corner(t: &Topology, f: usize, k: usize, sharp: Sharp) -> Option<Corner> {
    let c = t.face_vertices(f)[k] as usize;
    let tag = t.vertex_tag(c);
    // A non-manifold vertex can still bound a regular sector: the walk below only crosses
    // edges with exactly two faces, and non-manifold edges are infinitely sharp.
    let vertex = sharp.vertex(t, c);
    if vertex == Feature::Softening {
        return None;
    }
    // Walk the sector: counter-clockwise across the edge entering `c` in each face,
    // clockwise across the edge leaving it, stopping at infinitely sharp edges. The walk
    // takes at most four steps; the sector's size rules most corners out before the checks
    // below that look at every edge of `c` (whose valence may be large).
    let (ccw, closed) = walk(t, f, c, true, sharp);
    if closed && ccw.len() != 3 {
        return None;
    }
    let cw = if closed {
        Vec::new()
    } else {
        walk(t, f, c, false, sharp).0
    };
    if !closed && 1 + ccw.len() + cw.len() > 2 {
        return None;
    }
    let edges = t.vertex_edges(c).iter().map(|&e| sharp.edge(t, e as usize));
    if edges.clone().any(|e| e == Feature::Softening) {
        return None;
    }
    let inf_edges = edges.filter(|&e| e == Feature::Sharp).count();
    let quads =
        |faces: &[(usize, usize)]| faces.iter().all(|&(g, _)| t.face_vertices(g).len() == 4);
    if closed {
        let ok = tag.rule == Rule::Smooth && inf_edges == 0 && ccw.len() == 3 && quads(&ccw);
        return ok.then(|| Corner::Closed([ccw[0], ccw[1], ccw[2]]));
    }
    let sector = 1 + ccw.len() + cw.len();
    let ok = match tag.rule {
        Rule::Crease => inf_edges == 2 && sector == 2,
        Rule::Corner => sector == 1 && (vertex == Feature::Sharp || inf_edges > 2),
        Rule::Smooth | Rule::Dart => false,
    };
    (ok && quads(&ccw) && quads(&cw)).then_some(Corner::Sector { ccw, cw })
}

/// Faces around vertex `c` reached from face `f` by crossing, repeatedly, the edge that
/// enters `c` (`ccw`) or leaves it (`!ccw`), as long as that edge is not sharp (as
/// `sharp` sees it) and has two faces; at most four steps. Each item is `(face, position of c in
/// it)`; `f` itself is not listed. The flag tells whether the walk came back to `f` (a closed
/// fan). (Also used by the regularity certificate, which reads the same neighbourhoods.)
pub(crate) fn walk(
    t: &Topology,
    f: usize,
    c: usize,
    ccw: bool,
    sharp: Sharp,
) -> (Vec<(usize, usize)>, bool) {
    let mut out = Vec::with_capacity(4);
    let mut g = f;
    for _ in 0..5 {
        let gv = t.face_vertices(g);
        let n = gv.len();
        let Some(m) = gv.iter().position(|&x| x as usize == c) else {
            break;
        };
        let e = t.face_edge_list(g)[if ccw { (m + n - 1) % n } else { m }] as usize;
        let ef = t.edge_face_list(e);
        if sharp.edge(t, e) == Feature::Sharp || ef.len() != 2 {
            break;
        }
        let next = if ef[0] as usize == g { ef[1] } else { ef[0] } as usize;
        if next == f {
            return (out, true);
        }
        let Some(mn) = t.face_vertices(next).iter().position(|&x| x as usize == c) else {
            break;
        };
        out.push((next, mn));
        g = next;
    }
    (out, false)
}

/// Fills the phantom rows and columns across `f`'s infinitely sharp sides: side 0
/// (`v0 → v1`) is row `j = 0`, side 1 column `i = 3`, side 2 row `j = 3`, side 3 column
/// `i = 0`. A phantom column is `P₋₁ = 2 P₀ − P₁` along `u` on every real row; then a
/// phantom row is extrapolated along `v` on every column, which makes a cell in two
/// phantom sides the tensor-product extrapolation `4 P₀₀ − 2 P₁₀ − 2 P₀₁ + P₁₁`.
fn fill_phantoms(cp: &mut [[Cell; 4]; 4], sharp: [bool; 4]) {
    let ext = Cell::extrapolate;
    for j in 0..4 {
        if (j == 0 && sharp[0]) || (j == 3 && sharp[2]) {
            continue;
        }
        if sharp[3] {
            cp[0][j] = ext(&cp[1][j], &cp[2][j]);
        }
        if sharp[1] {
            cp[3][j] = ext(&cp[2][j], &cp[1][j]);
        }
    }
    for col in cp.iter_mut() {
        if sharp[0] {
            col[0] = ext(&col[1], &col[2]);
        }
        if sharp[2] {
            col[3] = ext(&col[2], &col[1]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Crease, Options};

    /// A net narrowed to 8-bit indices (as configuration trees keep them) gives the same
    /// control points, sharp sides included; one with an index past 8 bits stays as it is.
    #[test]
    fn narrow_nets_give_the_same_points() {
        let pos: Vec<[f64; 3]> = (0..20)
            .map(|i| {
                let x = f64::from(i);
                [x, x.sin(), x * x]
            })
            .collect();
        let v: [u32; 16] = std::array::from_fn(|k| 19 - k as u32);
        for net in [Net::Plain(v), Net::Sided(v, [true, false, false, true])] {
            let narrow: Net<u8> = net.narrow().expect("fits");
            assert_eq!(narrow.eval(&pos), net.eval(&pos));
            assert_eq!(narrow.cells(), net.cells());
        }
        let mut far = v;
        far[5] = 300;
        assert!(Net::Plain(far).narrow::<u8>().is_none());
    }

    /// At a boundary, a boundary corner and along an infinitely sharp crease, a patch's
    /// net keeps vertex indices and sharp sides, and gives the control points of its
    /// cells, bit for bit.
    #[test]
    fn sided_nets_evaluate_as_their_cells() {
        let mut mesh = crate::mesh::test_grid(6, 5, |x, y| {
            [
                x + 0.1 * y.sin(),
                y + 0.05 * x * x,
                0.3 * (0.7 * x + 0.4 * y).sin(),
            ]
        });
        for i in 0..6 {
            let (v0, v1) = (3 * 7 + i, 3 * 7 + i + 1);
            mesh.tags.creases.push(Crease {
                v0,
                v1,
                sharpness: 10.0,
            });
        }
        let (t, _) = Topology::from_mesh(&mesh, &Options::default()).expect("topology");
        let pos = mesh.positions();
        let (mut sided, mut plain) = (0, 0);
        for f in 0..t.num_faces() {
            let Some(cells) = regular_patch_cells(&t, f) else {
                continue;
            };
            let net = Net::new(cells);
            match net {
                Net::Plain(_) => plain += 1,
                Net::Sided(..) => sided += 1,
                Net::Cells(_) => panic!("face {f}: cells kept"),
            }
            assert_eq!(
                net.eval(pos),
                cells.map(|col| col.map(|c| c.eval(pos))),
                "face {f}"
            );
        }
        assert!(
            sided >= 20 && plain >= 4,
            "{sided} sided, {plain} plain nets"
        );
    }

    /// Under every set of sharp sides, a net of distinct vertices is kept as its sides
    /// and evaluates bit for bit as its cells; one whose phantom cell combines a vertex
    /// with itself (a degenerate face) keeps its cells, as the table's terms are not its
    /// cells' there.
    #[test]
    fn sided_terms_are_the_cells_of_every_set_of_sides() {
        let pos: Vec<[f64; 3]> = (0..20)
            .map(|i| {
                let x = f64::from(i) * 0.37;
                [x.sin(), x.cos() * 3.0, -x]
            })
            .collect();
        let v: [u32; 16] = std::array::from_fn(|k| 3 + k as u32);
        for set in 1..16 {
            let sides: [bool; 4] = std::array::from_fn(|b| set >> b & 1 == 1);
            let cells = sided_cells(&v, sides);
            let net = Net::new(cells);
            assert!(
                matches!(net, Net::Sided(_, s) if s == sides),
                "sides {sides:?}"
            );
            let want = cells.map(|col| col.map(|c| c.eval(&pos)));
            assert_eq!(net.eval(&pos), want, "sides {sides:?}");
            let narrow: Net<u8> = net.narrow().expect("fits");
            assert_eq!(narrow.eval(&pos), want, "sides {sides:?}");
        }
        // Side 3 sharp: cell [0][1] is 2 v[5] - v[9]; with v[9] = v[5] it is v[5] alone.
        let mut same = v;
        same[9] = same[5];
        let sides = [false, false, false, true];
        let cells = sided_cells(&same, sides);
        assert_eq!(cells[0][1].len, 1);
        let net = Net::new(cells);
        assert!(matches!(net, Net::Cells(_)));
        assert_eq!(net.eval(&pos), cells.map(|col| col.map(|c| c.eval(&pos))));
    }
}
