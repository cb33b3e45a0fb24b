//! The limit surface at an irregular corner of a face: its exact position and tangent
//! plane (where the parametric derivatives are degenerate, see
//! [`LimitSurface`](super::LimitSurface)).
//!
//! Everything here is computed as a [`CornerLimit`], whose vectors are *linear* in the
//! control points: the limit position, two vectors spanning the tangent plane and the
//! face's edge directions at the corner. Only [`CornerLimit::finish`] (the projection of the
//! edge directions onto the tangent plane) is not linear. This split lets the
//! configuration trees of [`super::tree`] precompute a corner once, as weights on the
//! control points, for every face with the same neighbourhood.

use super::bspline::Derivatives;
use super::local::{Local, Reach, Region, HIGH_VALENCE};
use crate::geom::{self, V3};
use crate::hash::FxHasher;
use crate::mesh::{Options, Topology};
use crate::refine::interpolate;
use crate::refine::patch::{regular_corner, Sharp};
use crate::scheme::catmark::{self, VertexMask};
use std::collections::HashMap;
use std::hash::BuildHasherDefault;
use std::sync::{Arc, Mutex, OnceLock};

/// How [`CornerLimit::finish`] turns a corner's vectors into `(du, dv)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) enum TangentMode {
    /// `t1`, `t2` are the tangents along the face's two edges at the corner (the smooth
    /// limit masks, rotated to the face).
    #[default]
    Masks,
    /// `t1`, `t2` span the tangent plane; the edge directions `a`, `b` are projected onto it.
    Plane,
    /// No tangent plane is known: the edge directions `a`, `b` themselves.
    Edges,
}

/// The limit at a corner of a face, linear in the control points until [`Self::finish`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct CornerLimit {
    /// Limit position.
    pub p: V3,
    /// Direction along the face's edge `k` (toward corner `k + 1`), at the level where the
    /// tangent plane was found.
    pub a: V3,
    /// Direction toward the face's corner `k − 1`, at that level.
    pub b: V3,
    /// First tangent (see [`TangentMode`]).
    pub t1: V3,
    /// Second tangent.
    pub t2: V3,
    /// How the tangents are formed.
    pub mode: TangentMode,
    /// The corner index `k` in the frame of the face the vectors belong to (0 once an
    /// `n`-gon has been split into quads).
    pub k: usize,
}

impl CornerLimit {
    /// A corner without a tangent plane: the edge directions `along` at corner `k`.
    fn edges(k: usize, along: (V3, V3)) -> Self {
        CornerLimit {
            a: along.0,
            b: along.1,
            mode: TangentMode::Edges,
            k,
            ..CornerLimit::default()
        }
    }

    /// The vectors that are linear in the control points, in a fixed order
    /// (`p, a, b, t1, t2`).
    pub(super) fn vectors(&self) -> [V3; 5] {
        [self.p, self.a, self.b, self.t1, self.t2]
    }

    /// The same mode and frame with other vectors (in [`Self::vectors`]' order).
    pub(super) fn with_vectors(&self, v: [V3; 5]) -> Self {
        CornerLimit {
            p: v[0],
            a: v[1],
            b: v[2],
            t1: v[3],
            t2: v[4],
            ..*self
        }
    }

    /// Position and `(du, dv)` in the face's frame (see the
    /// [`LimitSurface`](super::LimitSurface) docs): the limit position, and as `du`, `dv`
    /// the tangent vectors along the face's `u` and `v` edges, projected onto the exact
    /// tangent plane; second derivatives zero.
    pub(super) fn finish(&self) -> Derivatives {
        let (a, b) = match self.mode {
            TangentMode::Masks => (self.t1, self.t2),
            TangentMode::Plane => (
                project(self.a, self.t1, self.t2),
                project(self.b, self.t1, self.t2),
            ),
            TangentMode::Edges => (self.a, self.b),
        };
        let (du, dv) = uv_from_corner_frame(self.k, a, b);
        Derivatives {
            p: self.p,
            du,
            dv,
            ..Derivatives::default()
        }
    }
}

/// Whether corner `k` of face `face` of `t` is where the limit is taken from
/// [`corner_limit`] rather than from patches further down: it is not a regular patch
/// corner (see [`crate::refine::patch`]) and no semi-sharp vertex or edge sharpness is left at it,
/// so that its rule no longer changes under refinement.
pub(super) fn is_limit_corner(t: &Topology, face: usize, k: usize) -> bool {
    let c = t.face_vertices(face)[k] as usize;
    // From the vertex's tags, which say whether an edge at it is semi-sharp: walking its
    // edges cost `O(valence)` per point, `O(n²)` for the `n` sub-faces of an `n`-gon
    // evaluated at its centre.
    let tag = t.vertex_tag(c);
    let settled = !tag.semi_sharp && !tag.semi_sharp_edges;
    settled && regular_corner(t, face, k, Sharp::LIMIT).is_none()
}

/// What a shared region keeps of a vertex of more than [`HIGH_VALENCE`] faces at which a
/// point is evaluated, so that each point there costs `O(1)` rather than `O(valence)`
/// (the `n` sub-faces of an `n`-gon all meet at its centre, of valence `n`).
#[derive(Debug)]
pub(super) struct HighCorner {
    /// Whether [`corner_limit`] takes the smooth limit masks there.
    smooth: bool,
    /// For a vertex under the smooth rule: [`smooth_masks_at`].
    masks: Option<[[f64; 3]; 3]>,
    /// Each face's place in the vertex's cycle of faces.
    place: HashMap<u32, u32>,
}

impl HighCorner {
    /// The vertex `c` of `l`'s region.
    fn new(l: &Local, c: usize) -> Self {
        let t = l.topo();
        let faces = t.vertex_faces(c);
        let mut place = HashMap::with_capacity(faces.len());
        for (i, &g) in faces.iter().enumerate() {
            place.entry(g).or_insert(i as u32);
        }
        let rule = t.vertex_tag(c).rule;
        Self {
            smooth: takes_smooth_masks(t, c),
            masks: (rule == crate::mesh::Rule::Smooth).then(|| smooth_masks_at(l, c)),
            place,
        }
    }

    /// The entry of vertex `c` of `l`'s region, if the region is shared and `c` has more
    /// than [`HIGH_VALENCE`] faces (computed the first time).
    fn of(l: &Local, c: usize) -> Option<Arc<Self>> {
        let many = l.topo().vertex_faces(c).len() > HIGH_VALENCE;
        (l.region.is_shared() && many).then(|| {
            super::local::cached(&l.region.high, (c as u32, 0), || Arc::new(Self::new(l, c)))
        })
    }
}

/// Whether the limit at vertex `c` of `t` comes from the smooth limit masks: a smooth
/// interior manifold vertex of quads, of valence 3 or more.
fn takes_smooth_masks(t: &Topology, c: usize) -> bool {
    let tag = t.vertex_tag(c);
    let all_quads = t
        .vertex_faces(c)
        .iter()
        .all(|&g| t.face_vertices(g as usize).len() == 4);
    let n_e = t.vertex_edges(c).len();
    tag.rule == crate::mesh::Rule::Smooth
        && !tag.non_manifold
        && !tag.boundary
        && all_quads
        && n_e == t.vertex_faces(c).len()
        && n_e >= 3
}

/// Limit position and tangents at corner `k` of the cut-out's face (see the module docs).
///
/// A smooth interior vertex whose faces are quads has exact limit masks (Halstead et al.
/// 1993), used as they are. Under the corner rule (an infinitely sharp vertex, a
/// non-manifold one included, or three infinitely sharp edges or more) the vertex is its
/// own limit and no tangent plane is taken: a quad's corner returns the vertex and the
/// face's two sides at it ([`TangentMode::Edges`]), read on the face alone whatever the
/// other faces at the vertex are (a face that is not a quad is read on its child quad at
/// that corner). Any other vertex (crease, dart, valence 2, non-manifold crease) is
/// analysed numerically: with `R` the control points of the vertex's sector (the faces
/// around it between infinitely sharp edges, containing the face), one step maps `R` to
/// the same configuration one level down, `R' = S R`. The limit position
/// is `l₀ · R` with `l₀` the left eigenvector of `S` for eigenvalue 1 (`l₀ · 1 = 1`); the
/// tangent plane is spanned by `L · R` for `L` the invariant subspace of the two
/// subdominant left eigenvectors, found by subspace iteration on sum-free vectors (where
/// `Sᵀ` leaves out eigenvalue 1). The tangents are returned along the face's edges
/// projected onto that plane.
pub(super) fn corner_limit(
    l: &Local,
    k: usize,
    options: &Options,
    sectors: &SectorCache,
) -> CornerLimit {
    let t = l.topo();
    let pos = l.pos();
    let c = t.face_vertices(l.face)[k] as usize;
    let tag = t.vertex_tag(c);
    let high = HighCorner::of(l, c);
    let smooth = match &high {
        Some(h) => h.smooth,
        None => takes_smooth_masks(t, c),
    };
    if smooth {
        return smooth_corner(l, k);
    }
    let all_quads = t
        .vertex_faces(c)
        .iter()
        .all(|&g| t.face_vertices(g as usize).len() == 4);
    let n = t.face_vertices(l.face).len();
    let corner = tag.rule == crate::mesh::Rule::Corner;
    if corner && n == 4 {
        // The vertex stays put; the limit curves along the face's sides leave it toward
        // the neighbouring vertices (cubic B-spline end condition). Read on the face
        // alone, whatever the other faces at the corner are (a face's cut-out holds only
        // its own sectors at such a vertex: `local`, "Corners").
        return CornerLimit {
            p: pos[c],
            ..CornerLimit::edges(k, face_edge_dirs(l, k))
        };
    }
    if corner || !all_quads {
        // One step makes every face a quad; the corner's child has the same limit.
        let next = l.child(k, options);
        return corner_limit(&next, if n == 4 { k } else { 0 }, options, sectors);
    }
    let along = face_edge_dirs(l, k);
    match tag.rule {
        crate::mesh::Rule::Crease => {
            // The crease curve is the cubic B-spline of the crease polygon: its limit point is
            // ⅔ c + ⅙ (a + b) whatever lies around it. The tangent plane of the face's side
            // comes from the sector's eigen-analysis.
            let ends = crease_neighbours(t, c);
            let p = match ends {
                Some((a, b)) => {
                    let (pa, pb, pc) = (pos[a], pos[b], pos[c]);
                    [0, 1, 2].map(|i| (4.0 * pc[i] + pa[i] + pb[i]) / 6.0)
                }
                None => pos[c],
            };
            let d = eigen_corner_settled(l, k, options, sectors)
                .unwrap_or(CornerLimit::edges(k, along));
            CornerLimit { p, ..d }
        }
        _ => eigen_corner_settled(l, k, options, sectors).unwrap_or_else(|| smooth_corner(l, k)),
    }
}

/// [`eigen_corner`] at corner `k`, refining up to three levels first if the corner's
/// neighbourhood only becomes self-similar further down (faces that share several
/// vertices, as around valence-2 vertices, separate after a step).
fn eigen_corner_settled(
    l: &Local,
    k: usize,
    options: &Options,
    sectors: &SectorCache,
) -> Option<CornerLimit> {
    let mut owned: Option<Local> = None;
    for _ in 0..4 {
        let cur = owned.as_ref().unwrap_or(l);
        if let Some(d) = eigen_corner(cur, k, options, sectors) {
            return Some(d);
        }
        owned = Some(cur.child(k, options));
    }
    None
}

/// The far ends of the two sharp edges of a crease vertex.
fn crease_neighbours(t: &Topology, c: usize) -> Option<(usize, usize)> {
    let sharp: Vec<f32> = t
        .vertex_edges(c)
        .iter()
        .map(|&e| t.edge_sharpness(e as usize))
        .collect();
    if sharp.iter().filter(|&&x| x > 0.0).count() != 2 {
        return None;
    }
    let (i, j) = crate::scheme::crease::crease_ends(&sharp);
    let ends: Vec<u32> = t.vertex_neighbours(c).collect();
    Some((ends[i] as usize, ends[j] as usize))
}

/// The first face and the control points of the sector of face `l.face` at its corner `k`: the corner, then
/// for each sector face (walking from one bounding edge to the other) its three other
/// vertices, without repeats. Children of these points, listed the same way one level
/// down, correspond one to one.
fn sector_ring(t: &Topology, face: usize, k: usize) -> Option<(usize, Vec<u32>)> {
    let c = t.face_vertices(face)[k];
    // Walk clockwise to the sector's first face, then counter-clockwise across it.
    let step = |g: usize, ccw: bool| -> Option<usize> {
        let gv = t.face_vertices(g);
        let m = gv.iter().position(|&x| x == c)?;
        let n = gv.len();
        let e = t.face_edge_list(g)[if ccw { (m + n - 1) % n } else { m }] as usize;
        let ef = t.edge_face_list(e);
        if t.edge_tag(e).inf_sharp || ef.len() != 2 {
            return None;
        }
        Some(if ef[0] as usize == g { ef[1] } else { ef[0] } as usize)
    };
    let max = t.vertex_faces(c as usize).len();
    let mut start = face;
    for _ in 0..max {
        match step(start, false) {
            Some(g) if g != face => start = g,
            _ => break,
        }
    }
    let mut ring = vec![c];
    // Around a high-valence vertex, look repeats up in a set (the same order, O(1) each).
    let mut seen = (max > HIGH_VALENCE).then(|| std::collections::HashSet::from([c]));
    let mut g = start;
    for _ in 0..max {
        let gv = t.face_vertices(g);
        let m = gv.iter().position(|&x| x == c)?;
        for d in 1..4 {
            let x = gv[(m + d) % 4];
            let new = match seen.as_mut() {
                Some(seen) => seen.insert(x),
                None => !ring.contains(&x),
            };
            if new {
                ring.push(x);
            }
        }
        match step(g, true) {
            Some(next) if next != start => g = next,
            _ => break,
        }
    }
    Some((start, ring))
}

/// The eigen-analysis of a corner's sector (see [`corner_limit`]): the sector's control
/// points and the weights of the limit position and of two tangents spanning the tangent
/// plane. The same for every face of the sector, so a shared region computes it once.
#[derive(Debug)]
pub(super) struct Eigen {
    ring: Vec<u32>,
    w: Arc<SectorWeights>,
}

/// The weights of an eigen-analysis, in the order of its sector's points.
#[derive(Debug)]
pub(super) struct SectorWeights {
    l0: Vec<f64>,
    w1: Vec<f64>,
    w2: Vec<f64>,
}

/// Eigen-analyses of corner sectors by the structure of the faces around the corner
/// ([`Topology::corner_structure_key`], the face and the corner), shared by every corner
/// of a surface with the same neighbourhood (most darts, crease bends and corners of a
/// mesh look alike): each is the analysis on those faces alone, with the points of their
/// sector, or `None` where that fails.
#[derive(Debug, Default)]
pub(super) struct SectorCache(Mutex<SectorMap>);

type SectorMap = HashMap<Vec<u32>, Arc<OnceLock<Option<Sector>>>, BuildHasherDefault<FxHasher>>;

/// A cached analysis: the sector's points in the faces around the corner, and weights.
type Sector = (Vec<u32>, Arc<SectorWeights>);

fn eigen_corner(
    l: &Local,
    k: usize,
    options: &Options,
    sectors: &SectorCache,
) -> Option<CornerLimit> {
    let (start, ring) = sector_ring(l.topo(), l.face, k)?;
    let analyse = || eigen_analysis(l, k, start, ring, options, sectors).map(Arc::new);
    let e = if l.region.is_shared() {
        let c = l.topo().face_vertices(l.face)[k];
        super::local::cached(&l.region.shape.eigen, (c, start as u32), analyse)
    } else {
        analyse()
    }?;
    let pos = l.pos();
    let combine = |w: &[f64]| {
        let mut acc = [0.0; 3];
        for (wi, &x) in w.iter().zip(&e.ring) {
            let p = &pos[x as usize];
            (0..3).for_each(|i| acc[i] += wi * p[i]);
        }
        acc
    };
    // (No `l₀` for a high-valence crease vertex, whose caller takes the crease curve's point.)
    let p = if e.w.l0.is_empty() {
        pos[l.topo().face_vertices(l.face)[k] as usize]
    } else {
        combine(&e.w.l0)
    };
    Some(CornerLimit {
        p,
        t1: combine(&e.w.w1),
        t2: combine(&e.w.w2),
        mode: TangentMode::Plane,
        ..CornerLimit::edges(k, face_edge_dirs(l, k))
    })
}

/// The subdivision matrix `S` of the sector `ring` of corner `k` and its eigen-analysis.
///
/// The children of the ring's points (the corner's vertex point, the edge points of its
/// edges, the face points of its faces) depend only on the faces around the corner, and
/// on the rules of the corner and its edges. `S` is therefore first computed on just those
/// faces, cut out of the region: the same stencils, so the same matrix, at the cost of the
/// corner's valence instead of the region's size, and looked up in `sectors` by the
/// structure of those faces, so that corners alike are analysed once. Should that fail
/// (the neighbourhood only becomes self-similar further down, see
/// [`eigen_corner_settled`]), the whole region is used.
fn eigen_analysis(
    l: &Local,
    k: usize,
    start: usize,
    ring: Vec<u32>,
    options: &Options,
    sectors: &SectorCache,
) -> Option<Eigen> {
    let t = l.topo();
    let c = t.face_vertices(l.face)[k] as usize;
    let whole = |ring: Vec<u32>| {
        let w = sector_eigen(l, k, &ring, options)?;
        Some(Eigen {
            ring,
            w: Arc::new(w),
        })
    };
    // With a semi-sharp edge at the corner (which callers analyse only once none is left,
    // see `Topology::corner_structure_key`) the faces around it would not be enough.
    if (t.vertex_edges(c).iter()).any(|&e| t.edge_tag(e as usize).semi_sharp) {
        return whole(ring);
    }
    let faces = t.vertex_faces(c);
    let face = faces.iter().position(|&g| g as usize == l.face)?;
    let (sub, verts) = t.subset(faces);
    let sub_c = verts.iter().position(|&v| v as usize == c)?;
    // Keyed by the sector (its first face and the corner in it), which every face of a
    // sector bounded by sharp edges shares with the same ring.
    let first = faces.iter().position(|&g| g as usize == start)?;
    let corner = t
        .face_vertices(start)
        .iter()
        .position(|&v| v as usize == c)?;
    let mut key = Vec::new();
    sub.corner_structure_key(sub_c, &mut key);
    key.extend([first as u32, corner as u32]);
    let cell = super::local::cell(&sectors.0, key);
    let sector = cell.get_or_init(|| {
        let pos = vec![[0.0; 3]; sub.num_vertices()];
        let tiny = Local {
            region: Arc::new(Region::whole(sub, pos, Reach::default())),
            face,
        };
        let (_, sub_ring) = sector_ring(tiny.topo(), face, k)?;
        let w = sector_eigen(&tiny, k, &sub_ring, options)?;
        Some((sub_ring, Arc::new(w)))
    });
    match sector {
        Some((sub_ring, w))
            if sub_ring
                .iter()
                .map(|&x| verts[x as usize])
                .eq(ring.iter().copied()) =>
        {
            Some(Eigen { ring, w: w.clone() })
        }
        _ => whole(ring),
    }
}

/// [`eigen_analysis`] on the region as it is.
fn sector_eigen(l: &Local, k: usize, ring: &[u32], options: &Options) -> Option<SectorWeights> {
    let t = l.topo();
    let childl = l.child(k, options);
    let child = childl.topo();
    let (_, child_ring) = sector_ring(child, childl.face, k)?;
    let m = ring.len();
    if child_ring.len() != m {
        return None;
    }
    // Column b of S (S[a][b]: value at child_ring[a] when ring[b] is 1 and every other
    // vertex 0), as (a, S[a][b]) for the non-zero entries, a ascending.
    let mut cols: Vec<Vec<(usize, f64)>> = Vec::with_capacity(m);
    let mut unit = vec![[0.0]; t.num_vertices()];
    let mut out = vec![[0.0]; child.num_vertices()];
    for &x in ring {
        unit[x as usize] = [1.0];
        interpolate(t, child, options, &unit, &mut out);
        unit[x as usize] = [0.0];
        let col = child_ring
            .iter()
            .enumerate()
            .map(|(a, &y)| (a, out[y as usize][0]))
            .filter(|&(_, w)| w != 0.0)
            .collect();
        cols.push(col);
    }
    // Up to the sector of a vertex of HIGH_VALENCE faces, dense as it always was. Above,
    // S is applied sparsely (it has O(m) non-zeros; O(m) per step instead of O(m²)), and a
    // crease vertex skips the dominant eigenvector (O(m³)): its limit position comes from
    // the crease curve (see `corner_limit`), not from `l₀`.
    let high = m > 2 * HIGH_VALENCE + 1;
    let crease = t.vertex_tag(ring[0] as usize).rule == crate::mesh::Rule::Crease;
    let dense = || {
        let mut s = vec![vec![0.0; m]; m];
        for (b, col) in cols.iter().enumerate() {
            for &(a, w) in col {
                s[a][b] = w;
            }
        }
        s
    };
    let l0 = if high && crease {
        Vec::new()
    } else {
        dominant_left_eigenvector(&dense())?
    };
    let (w1, w2) = if high {
        subdominant_left_subspace(m, |w, i| cols[i].iter().map(|&(a, x)| x * w[a]).sum())
    } else {
        let s = dense();
        subdominant_left_subspace(m, |w, j| (0..m).map(|i| s[i][j] * w[i]).sum())
    };
    Some(SectorWeights { l0, w1, w2 })
}

/// `l` with `l S = l`, `Σ l = 1`: solves `(Sᵀ − I) l = 0` with the last equation replaced
/// by the normalisation (Gaussian elimination, partial pivoting).
fn dominant_left_eigenvector(s: &[Vec<f64>]) -> Option<Vec<f64>> {
    let m = s.len();
    let mut a: Vec<Vec<f64>> = (0..m)
        .map(|i| {
            let mut row: Vec<f64> = (0..m)
                .map(|j| s[j][i] - if i == j { 1.0 } else { 0.0 })
                .collect();
            row.push(0.0);
            row
        })
        .collect();
    a[m - 1] = vec![1.0; m + 1];
    for col in 0..m {
        let piv = (col..m).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[piv][col].abs() < 1e-14 {
            return None;
        }
        a.swap(col, piv);
        for r in 0..m {
            if r != col {
                let f = a[r][col] / a[col][col];
                if f != 0.0 {
                    for c in col..=m {
                        a[r][c] -= f * a[col][c];
                    }
                }
            }
        }
    }
    Some((0..m).map(|i| a[i][m] / a[i][i]).collect())
}

/// Two vectors spanning the left invariant subspace of `S` for its two largest
/// eigenvalues after 1: subspace iteration on sum-free vectors (which `Sᵀ` maps to
/// sum-free vectors, since `S 1 = 1`), orthonormalised each step. `column_dot(w, j)` is
/// `Σᵢ S[i][j] wᵢ`, entry `j` of `Sᵀ w`, for `S` of size `m`.
fn subdominant_left_subspace(
    m: usize,
    column_dot: impl Fn(&[f64], usize) -> f64,
) -> (Vec<f64>, Vec<f64>) {
    let center = |v: &mut Vec<f64>| {
        let mean = v.iter().sum::<f64>() / m as f64;
        v.iter_mut().for_each(|x| *x -= mean);
    };
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let normalize = |v: &mut Vec<f64>| {
        let n = dot(v, v).sqrt();
        if n > 0.0 {
            v.iter_mut().for_each(|x| *x /= n);
        }
    };
    let mut w1: Vec<f64> = (0..m).map(|i| (i as f64 * 1.3).cos()).collect();
    let mut w2: Vec<f64> = (0..m).map(|i| (i as f64 * 0.7 + 0.4).sin()).collect();
    let apply = |w: &[f64]| -> Vec<f64> { (0..m).map(|j| column_dot(w, j)).collect() };
    for _ in 0..200 {
        w1 = apply(&w1);
        w2 = apply(&w2);
        center(&mut w1);
        center(&mut w2);
        normalize(&mut w1);
        let d = dot(&w2, &w1);
        w2.iter_mut().zip(&w1).for_each(|(x, y)| *x -= d * y);
        normalize(&mut w2);
    }
    (w1, w2)
}

/// Tangents along edge `k` of a face and toward its corner `k - 1`, as `(du, dv)`.
fn uv_from_corner_frame(k: usize, a: [f64; 3], b: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let neg = |x: [f64; 3]| [-x[0], -x[1], -x[2]];
    match k {
        0 => (a, b),
        1 => (neg(b), a),
        2 => (neg(a), neg(b)),
        _ => (b, neg(a)),
    }
}

/// The exact limit position and tangents of a smooth interior vertex with quads around it,
/// from the limit masks, rotated so that the face comes first.
///
/// Above [`HIGH_VALENCE`] faces (in a shared region) the masks are applied once per vertex:
/// the smooth tangent masks at rotation `i` (the face listed `i`-th first) are
/// `t₁ᵢ = Σⱼ w(j − i)·xⱼ` and `t₂ᵢ = t₁,ᵢ₊₁`, with `w` cosines in `θ = 2π/n`, so
/// `t₁ᵢ = cos(iθ) C + sin(iθ) S` with `C`, `S` the cosine and sine masks applied at
/// rotation 0: equal to the direct sums up to rounding, in `O(1)` per face instead of `O(n)`.
fn smooth_corner(l: &Local, k: usize) -> CornerLimit {
    let t = l.topo();
    let pos = l.pos();
    let c = t.face_vertices(l.face)[k] as usize;
    let faces = t.vertex_faces(c);
    let edges = t.vertex_edges(c);
    let nf = faces.len();
    let rule = t.vertex_tag(c).rule;
    let high = HighCorner::of(l, c);
    if let Some((h, [p, cm, sm])) = high.as_ref().and_then(|h| Some((h, h.masks?))) {
        let start = h.place.get(&(l.face as u32)).map_or(0, |&i| i as usize);
        let theta = 2.0 * std::f64::consts::PI / nf as f64;
        let at = |i: usize| {
            let (sn, cs) = ((i % nf) as f64 * theta).sin_cos();
            [0, 1, 2].map(|x| cs * cm[x] + sn * sm[x])
        };
        return CornerLimit {
            p,
            t1: at(start),
            t2: at(start + 1),
            mode: TangentMode::Masks,
            ..CornerLimit::edges(k, ([0.0; 3], [0.0; 3]))
        };
    }
    let start = faces
        .iter()
        .position(|&g| g as usize == l.face)
        .unwrap_or(0);
    let rot = |i: usize, n: usize| (i + start) % n.max(1);
    let ends: Vec<u32> = t.vertex_neighbours(c).collect();
    let ends: Vec<u32> = (0..edges.len())
        .map(|i| ends[rot(i, edges.len())])
        .collect();
    let locals = t.vertex_face_locals(c);
    let opposite: Vec<u32> = (0..nf)
        .map(|i| {
            let g = faces[rot(i, nf)] as usize;
            let fv = t.face_vertices(g);
            fv[(locals[rot(i, nf)] as usize + 2) % fv.len()]
        })
        .collect();
    let sharp = vec![0.0f32; edges.len()];
    let (mut pm, mut t1, mut t2) = (
        VertexMask::default(),
        VertexMask::default(),
        VertexMask::default(),
    );
    catmark::limit_position_mask(rule, &sharp, nf, &mut pm);
    catmark::limit_tangent_masks(rule, &sharp, nf, &mut t1, &mut t2);
    let apply = |m: &VertexMask| {
        let mut acc = [0.0; 3];
        let mut add = |w: f64, p: &[f64; 3]| (0..3).for_each(|i| acc[i] += w * p[i]);
        add(m.vertex, &pos[c]);
        if m.has_edges {
            ends.iter()
                .zip(&m.edges)
                .for_each(|(&x, &w)| add(w, &pos[x as usize]));
        }
        if m.has_faces {
            opposite
                .iter()
                .zip(&m.faces)
                .for_each(|(&x, &w)| add(w, &pos[x as usize]));
        }
        acc
    };
    CornerLimit {
        p: apply(&pm),
        t1: apply(&t1),
        t2: apply(&t2),
        mode: TangentMode::Masks,
        ..CornerLimit::edges(k, ([0.0; 3], [0.0; 3]))
    }
}

/// For a smooth interior vertex `c` of `n` quads: its limit position and the cosine and
/// sine tangent masks (OpenSubdiv's smooth tangent mask and its quarter-period shift)
/// applied at rotation 0, `[P, C, S]`. `C` is the first tangent of the face listed first
/// around `c`.
fn smooth_masks_at(l: &Local, c: usize) -> [[f64; 3]; 3] {
    let (t, pos) = (l.topo(), l.pos());
    let faces = t.vertex_faces(c);
    let n = faces.len();
    let locals = t.vertex_face_locals(c);
    let theta = 2.0 * std::f64::consts::PI / n as f64;
    let (cs, chs) = (theta.cos(), (0.5 * theta).cos());
    let lambda = 5.0 / 16.0 + (cs + chs * (2.0 * (9.0 + cs)).sqrt()) / 16.0;
    let fscale = 1.0 / (4.0 * lambda - 1.0);
    let sharp = vec![0.0f32; t.vertex_edges(c).len()];
    let mut pm = VertexMask::default();
    catmark::limit_position_mask(crate::mesh::Rule::Smooth, &sharp, n, &mut pm);
    let (mut p, mut cm, mut sm) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    (0..3).for_each(|x| p[x] = pm.vertex * pos[c][x]);
    for (i, x) in t.vertex_neighbours(c).enumerate() {
        let (si, ci) = (i as f64 * theta).sin_cos();
        let q = &pos[x as usize];
        let we = if pm.has_edges { pm.edges[i] } else { 0.0 };
        (0..3).for_each(|a| {
            p[a] += we * q[a];
            cm[a] += 4.0 * ci * q[a];
            sm[a] += 4.0 * si * q[a];
        });
    }
    for i in 0..n {
        let g = faces[i] as usize;
        let fv = t.face_vertices(g);
        let q = &pos[fv[(locals[i] as usize + 2) % fv.len()] as usize];
        let (si, ci) = (i as f64 * theta).sin_cos();
        let (si1, ci1) = ((i + 1) as f64 * theta).sin_cos();
        let wf = if pm.has_faces { pm.faces[i] } else { 0.0 };
        (0..3).for_each(|a| {
            p[a] += wf * q[a];
            cm[a] += fscale * (ci + ci1) * q[a];
            sm[a] += fscale * (si + si1) * q[a];
        });
    }
    [p, cm, sm]
}

/// Directions from corner `k` of the cut-out's face to its neighbours `k + 1` and `k - 1`.
fn face_edge_dirs(l: &Local, k: usize) -> (V3, V3) {
    let fv = l.topo().face_vertices(l.face);
    let n = fv.len();
    let pos = l.pos();
    let c = &pos[fv[k] as usize];
    (
        geom::sub(&pos[fv[(k + 1) % n] as usize], c),
        geom::sub(&pos[fv[(k + n - 1) % n] as usize], c),
    )
}

/// The least-squares projection of `e` onto the plane spanned by `t1`, `t2` (or `e` when
/// they are parallel).
fn project(e: V3, t1: V3, t2: V3) -> V3 {
    let (g11, g12, g22) = (
        geom::dot(&t1, &t1),
        geom::dot(&t1, &t2),
        geom::dot(&t2, &t2),
    );
    let det = g11 * g22 - g12 * g12;
    if det.abs() <= f64::MIN_POSITIVE {
        return e;
    }
    let (r1, r2) = (geom::dot(&e, &t1), geom::dot(&e, &t2));
    let x = (g22 * r1 - g12 * r2) / det;
    let y = (g11 * r2 - g12 * r1) / det;
    [0, 1, 2].map(|i| x * t1[i] + y * t2[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Crease;

    /// A wavy 8 × 8 grid of quads with infinitely sharp edges that end inside it (darts),
    /// meet in threes (corners) and turn (crease bends), several of each.
    fn sharp_grid() -> Topology {
        let n = 9u32;
        let mut mesh = crate::mesh::test_grid(n - 1, n - 1, |x, y| {
            [x + 0.1 * y.sin(), y, 0.3 * (0.7 * x + 0.4 * y).sin()]
        });
        let v = |i: u32, j: u32| j * n + i;
        let sharp = [
            (v(1, 1), v(2, 1)),
            (v(5, 1), v(6, 1)),
            (v(1, 4), v(2, 4)),
            (v(2, 4), v(2, 5)),
            (v(5, 4), v(6, 4)),
            (v(6, 4), v(6, 5)),
            (v(4, 4), v(5, 4)),
            (v(5, 4), v(5, 5)),
            (v(2, 6), v(3, 6)),
            (v(6, 6), v(7, 6)),
        ];
        for (v0, v1) in sharp {
            mesh.tags.creases.push(Crease {
                v0,
                v1,
                sharpness: 10.0,
            });
        }
        let options = Options::default();
        Topology::from_mesh(&mesh, &options).expect("topology").0
    }

    /// Every analysed corner of the grid gets, through the shared cache, the weights of an
    /// analysis of its own cut-out, bit for bit, and corners alike share one analysis.
    #[test]
    fn cached_sector_analyses_are_those_of_each_corner() {
        let t = sharp_grid();
        let options = Options::default();
        let sectors = SectorCache::default();
        let mut analysed = 0;
        for f in 0..t.num_faces() {
            let Ok(faces) = super::super::local::cut_out(&t, f, Reach::default()) else {
                unreachable!("no high valence here");
            };
            let (sub, verts) = t.subset(&faces);
            let pos = verts.iter().map(|_| [0.0; 3]).collect();
            let l = Local {
                region: Arc::new(Region::whole(sub, pos, Reach::default())),
                face: 0,
            };
            for k in 0..4 {
                let c = l.topo().face_vertices(0)[k] as usize;
                if !is_limit_corner(l.topo(), 0, k) || l.topo().vertex_tag(c).boundary {
                    continue;
                }
                let (start, ring) = sector_ring(l.topo(), 0, k).expect("sector");
                let own = sector_eigen(&l, k, &ring, &options).expect("own analysis");
                let cached = eigen_analysis(&l, k, start, ring.clone(), &options, &sectors)
                    .expect("cached analysis");
                assert_eq!(cached.ring, ring, "face {f} corner {k}");
                assert_eq!(cached.w.l0, own.l0, "face {f} corner {k}");
                assert_eq!(cached.w.w1, own.w1, "face {f} corner {k}");
                assert_eq!(cached.w.w2, own.w2, "face {f} corner {k}");
                analysed += 1;
            }
        }
        let kept = sectors.0.lock().map(|m| m.len()).unwrap_or(0);
        assert!(analysed >= 40, "{analysed} corners analysed");
        assert!(
            kept * 2 < analysed,
            "{kept} analyses kept for {analysed} corners"
        );
    }

    /// The sparse application of `Sᵀ` used above [`HIGH_VALENCE`] gives the subspace of the
    /// dense one: the same sums without their zero terms.
    #[test]
    fn sparse_and_dense_subspace_iteration_agree() {
        let m = 41;
        // A row-stochastic band matrix (S 1 = 1), as a subdivision matrix is.
        let mut s = vec![vec![0.0; m]; m];
        for (i, row) in s.iter_mut().enumerate() {
            let w = [0.125, 0.75, 0.125];
            for (d, &x) in w.iter().enumerate() {
                row[(i + m + d - 1) % m] += x * (1.0 + 0.01 * (i % 3) as f64 * (d as f64 - 1.0));
            }
            let sum: f64 = row.iter().sum();
            row.iter_mut().for_each(|x| *x /= sum);
        }
        let cols: Vec<Vec<(usize, f64)>> = (0..m)
            .map(|b| {
                (0..m)
                    .map(|a| (a, s[a][b]))
                    .filter(|&(_, x)| x != 0.0)
                    .collect()
            })
            .collect();
        let dense = subdominant_left_subspace(m, |w, j| (0..m).map(|i| s[i][j] * w[i]).sum());
        let sparse =
            subdominant_left_subspace(m, |w, i| cols[i].iter().map(|&(a, x)| x * w[a]).sum());
        for (a, b) in [(&dense.0, &sparse.0), (&dense.1, &sparse.1)] {
            for (x, y) in a.iter().zip(b.iter()) {
                assert!((x - y).abs() < 1e-12, "{x} vs {y}");
            }
        }
        assert!(dense.0.iter().any(|x| x.abs() > 0.01));
    }
}
