//! Local neighbourhoods: the part of a level that determines the limit surface over one
//! face, cut out as a small mesh of its own so that it can be refined on its own.
//!
//! The limit surface over a face `f` depends on the faces around `f`'s vertices, its
//! *1-ring*. That is also enough to refine `f` exactly any number of levels: the 1-ring of
//! each child of `f` is made of children (at `f`'s vertices) of 1-ring faces, and their
//! vertices are the vertex points of `f`'s vertices, the edge points of the edges at them
//! and the face points of the faces at them, all of whose parents' neighbourhoods lie in
//! the 1-ring. The rules and sharpness of those elements would need one ring more to be
//! derived, but they are not derived: the cut-out is a [`Topology::subset`], whose edges,
//! tags, sharpness and rules are copied from the level, so it refines exactly as the whole
//! level would around `f`. Elements on the cut-out's rim have incomplete neighbourhoods,
//! but they never influence `f`'s children. (Checked bit for bit against cut-outs of the
//! 2-ring on every OpenSubdiv regression shape.)
//!
//! # Chaikin's rule
//! With Chaikin's decay ([`CreaseMethod::Chaikin`]) one rim element does: the child of a
//! semi-sharp edge `(v, w)` at its end `w` takes its sharpness from all the semi-sharp
//! edges at `w` (`¾ s + ¼ avg − 1`), and whether both children of the edge stay sharp
//! decides the rule, so the position, of the edge's midpoint, a vertex of `f`'s children
//! when `v` is a corner of `f`. So under that rule the cut-out also holds the faces around
//! the far end `w` of every semi-sharp edge at a corner of `f` ([`cut_out_unbounded`]).
//! That is enough at every level: the corners of a child of `f` are a corner's child
//! `v′`, the edge midpoints and the face point; the semi-sharp edges at them are halves of
//! edges at `v`, whose far ends are the midpoints (around which the cut-out holds every
//! face's child) and the children of `f`'s other corners. Without the faces around `w` a
//! limit point on a 3 × 3 torus with creases of sharpness 3.2, 1 and 2 was 5e-4 off the
//! limit of refinement. The surface over `f` still depends on the positions of the 1-ring
//! only (the extra faces bring topology, and points that reach no child of `f`). A shared
//! region (below) takes one ring more under this rule: a face `g` that reaches the
//! high-valence vertex lies within two rings of it, the far ends of `g`'s edges within
//! three, and the faces around them within four.
//!
//! # Corners: sectors only
//! At an infinitely sharp vertex `v` (tagged so, or made so as a non-manifold vertex) the
//! corner rule holds at every level: `v` stays put and reads no face. What then reaches
//! `f`'s children from around `v` are the edge points of the edges at `v` that are not
//! infinitely sharp (from their two faces) and the face points of those faces, and
//! nothing crosses an infinitely sharp edge (its points are midpoints, its children
//! sharp). So the cut-out holds, at such a corner, only `f`'s *sector* there: the faces
//! reached from `f` around `v` across edges that are not infinitely sharp (boundary and
//! non-manifold edges are). The children of the sector are the sector of `f`'s child at
//! `v`'s child, so this holds at every level; the limit at `v` itself is read from `f`
//! alone ([`super::corner`]). Not when a semi-sharp edge meets `v`: its decay (Chaikin's
//! rule) and whether it still softens the corner read every edge at `v`; and without an
//! infinitely sharp edge at `v` (nor a non-manifold `v`) the sector is all of `v`'s
//! faces, which are then taken as at any vertex ([`is_sectored`]). Around a
//! non-manifold vertex, whose faces all reach it, this is what keeps cut-outs small: in
//! OpenSubdiv's `catmark_nonman_quadpole360` each of 360 faces has a sector of two, where
//! the region of the whole pole (below) kept 10 MB of refined topology.
//!
//! # High valence: shared regions
//! Around a vertex `w` of valence `n` every face's 1-ring holds all `n` faces of `w`, so
//! one cut-out per face would cost `O(n²)` time and memory unless the faces share their
//! configurations (see [`HIGH_VALENCE`]). When a face's 1-ring reaches a vertex of more
//! than [`HIGH_VALENCE`] faces (a quarter of that on a boundary or a non-manifold vertex),
//! the face instead uses the *region* of that vertex, shared by all faces that reach it:
//! the faces within three rings of `w` (four under Chaikin's rule, see above;
//! `F₁` = the faces of `w`, `Fₖ₊₁` = the faces
//! sharing a vertex with a face of `Fₖ`). It holds the 1-ring of every such face `g`: `w`
//! is a vertex of a face `h` in `g`'s 1-ring, so `g` is in `h`'s 1-ring, within `F₂`, and
//! `g`'s 1-ring within `F₃`. A shared region is refined once (the refinement is kept and
//! shared, and so are the regions cut from it one level down and the analyses of its
//! corners), so the work around `w` is `O(n)` per level. [`Topology::subset`] keeps the
//! order of faces and edges around every vertex whose neighbourhood matters, so a region
//! gives the same values, bit for bit, as a face's own cut-out.
//!
//! # Large faces: shared regions too
//! The surface over a face `g` next to an `n`-gon `h` depends on all of `h`'s corners
//! (through `h`'s face point), and so does each of `h`'s own `n` sub-faces: one cut-out
//! per face would again cost `O(n²)`, and a configuration tree of `h` more (its refinement
//! rows read all `n` corners from each of its `O(n)` refined points). So a face of more
//! than [`LARGE_FACE`] corners is the seed of a region too ([`Seed::Face`]), shared by the
//! faces whose 1-ring holds it (`h` and the faces that share a vertex with it): the faces
//! within two rings of `h` (`F₁` = the faces around `h`'s corners, `F₂` the faces sharing
//! a vertex with one of `F₁`; three rings under Chaikin's rule, for the far ends of the
//! semi-sharp edges at the corners of `F₁`), which hold the 1-ring of every face of `F₁`.
//! Refined once, `h` becomes `n` quads around its face point, a vertex of valence `n`: in
//! the region of a large face, vertices of more than [`LARGE_FACE`] faces are seeds too
//! (`Reach::in_face_region`), so the sub-faces then share the region of that centre, and
//! the work around `h` is `O(n)` per level, as around a vertex of high valence.
//!
//! # Re-posing: shapes and points
//! A region is a [`Shape`] (its topology and everything derived from the topology alone:
//! the refined shape, the shapes of the regions cut from it, what each of its faces is, a
//! patch's control net as vertex indices or an irregular face's cut, and the
//! eigen-analyses of its corners) and the points of that shape. A surface keeps the shapes
//! of its base level's regions across re-posing (`LimitSurface::set_positions`), so a new
//! pose only gathers each region's points, interpolates them level by level as far as its
//! evaluations descend and evaluates the patches' nets: `O(n)` per level, as before, but
//! without building any topology. (Before, re-posing built the regions again: in a profile
//! of a re-posed evaluation of OpenSubdiv's `catmark_nonman_quadpole64`, 40 % of the time
//! went to building subsets and refining topology, 20 % to finding each face's patch
//! again.)

use super::surface::Shared;
use super::tree::{Tree, TreeCache};
use crate::mesh::{CreaseMethod, Options, Topology};
use crate::refine::patch::{regular_patch_cells, Net};
use crate::refine::{interpolate, refine_topology};
use std::collections::{HashMap, HashSet};
use std::sync::{Arc, Mutex, OnceLock};

/// A vertex with more faces than this makes the faces whose 1-ring reaches it share a
/// region (see the module docs); so does a boundary or non-manifold vertex with more than
/// a quarter of this.
///
/// Below it, each face's cut-out is a configuration of its own tree
/// ([`super::tree`]), so the faces around a vertex of valence `n` cost `O(n)` each, in
/// time and memory, unless they share configurations. Around an interior manifold vertex
/// they usually do (the cut-outs are compared up to where the vertex's cycle of faces
/// starts: a symmetric pole of any valence is one or two configurations), around a
/// boundary or non-manifold vertex they do not (its faces are ordered from the boundary),
/// hence the lower bound there. Measured on OpenSubdiv's pole shapes (`BENCHMARKS.md`): a
/// re-posed evaluation through trees takes half the time of one through regions at
/// valence 64, as a region keeps its topology across positions but interpolates its
/// points level by level again, where a tree keeps its refinement as weights.
pub(super) const HIGH_VALENCE: usize = 128;

/// A face of more than this many corners (an eighth of [`HIGH_VALENCE`]) shares a region
/// with the faces whose 1-ring holds it (see the module docs, "Large faces").
///
/// Below it, the face is the root of a configuration tree ([`super::tree`]) whose
/// refinement rows read all of its corners from each of its `O(n)` refined points and
/// whose `n` sub-faces each cut out the `n` faces around its centre: `O(n²)` per level,
/// which a configuration shared by few faces does not repay (a lone 128-gon took 0.5 s to
/// tessellate at rate 16 so, 0.02 s in a region).
pub(super) const LARGE_FACE: usize = HIGH_VALENCE / 8;

/// Whether vertex `v` of `t` has too many faces for per-face cut-outs (see
/// [`HIGH_VALENCE`]; `high_valence` is its value, or `usize::MAX` in tests).
pub(super) fn is_high_valence(t: &Topology, v: usize, high_valence: usize) -> bool {
    t.vertex_faces(v).len() > fan_limit(t, v, high_valence)
}

/// Whether face `f` of `t` has too many corners for per-face cut-outs: more than
/// `large_face` (see [`LARGE_FACE`] and the module docs, "Large faces").
pub(super) fn is_large_face(t: &Topology, f: usize, large_face: usize) -> bool {
    t.face_vertices(f).len() > large_face
}

/// What a shared region is cut around (module docs): a vertex of high valence, or a large
/// face.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Seed {
    /// A vertex of more than [`HIGH_VALENCE`] faces (a quarter of that on a boundary or
    /// at a non-manifold vertex).
    Vertex(u32),
    /// A face of more than [`LARGE_FACE`] corners.
    Face(u32),
}

/// The most faces of `v` (or of one face's sectors at `v`, see [`is_sectored`]) that a
/// face's own cut-out takes: `high_valence`, a quarter of it on a boundary or at a
/// non-manifold vertex.
fn fan_limit(t: &Topology, v: usize, high_valence: usize) -> usize {
    let tag = t.vertex_tag(v);
    if tag.boundary || tag.non_manifold {
        high_valence / 4
    } else {
        high_valence
    }
}

/// Whether a face's cut-out needs only the face's own sectors at vertex `v` (module docs,
/// "Corners"): `v` is infinitely sharp, so its rule is the corner rule at every level, no
/// semi-sharp edge meets it (whose decay and softening read every edge at `v`), and an
/// infinitely sharp edge (a boundary or non-manifold one included) may bound a sector
/// (without one, the sector is every face of `v`).
fn is_sectored(t: &Topology, v: usize) -> bool {
    let tag = t.vertex_tag(v);
    tag.inf_sharp && !tag.semi_sharp_edges && (tag.inf_sharp_edges || tag.non_manifold)
}

/// How far the cut-outs of a level reach: where faces share regions, and whether they
/// hold the far ends of semi-sharp edges (see the module docs, "Chaikin's rule").
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Reach {
    /// Valence above which faces share regions (normally [`HIGH_VALENCE`]; `usize::MAX`
    /// in tests: every face on its own).
    pub high_valence: usize,
    /// Corners above which a face and the faces around it share a region (normally
    /// [`LARGE_FACE`]; `usize::MAX` in tests).
    pub large_face: usize,
    /// Semi-sharp edges decay by Chaikin's rule
    /// ([`CreaseMethod::Chaikin`]).
    pub chaikin: bool,
}

impl Default for Reach {
    /// Every face on its own, uniform decay: for cut-outs that are never cut again
    /// (the faces around one corner, for its analysis).
    fn default() -> Self {
        Reach {
            high_valence: usize::MAX,
            large_face: usize::MAX,
            chaikin: false,
        }
    }
}

impl Reach {
    /// The default [`HIGH_VALENCE`] and [`LARGE_FACE`] with the crease rule of `options`.
    pub(super) fn new(options: &Options) -> Self {
        Self::with_high_valence(options, HIGH_VALENCE)
    }

    /// Regions around vertices of more than `high_valence` faces and faces of more than an
    /// eighth of that many corners ([`HIGH_VALENCE`] and [`LARGE_FACE`]; `usize::MAX`:
    /// none), with the crease rule of `options`.
    pub(super) fn with_high_valence(options: &Options, high_valence: usize) -> Self {
        Reach {
            high_valence,
            large_face: high_valence / (HIGH_VALENCE / LARGE_FACE),
            chaikin: options.crease_method == CreaseMethod::Chaikin,
        }
    }

    /// The reach in the region of a large face: there vertices of more than
    /// [`large_face`](Self::large_face) faces share regions too, so that once the face is
    /// refined its `n` sub-faces share the region of its centre, a vertex of valence `n`
    /// (module docs, "Large faces").
    fn in_face_region(self) -> Self {
        Reach {
            high_valence: self.high_valence.min(self.large_face),
            ..self
        }
    }
}

/// Value cached per corner of a shared region (see [`Shape::eigen`]).
pub(super) type CornerCache<T> = Mutex<HashMap<(u32, u32), Arc<OnceLock<T>>>>;

/// The part of a cut-out (or of a refined cut-out) that does not depend on the positions:
/// its topology and, for a region shared around a high-valence vertex, everything derived
/// from it alone: its refinement, the regions cut from that and the eigen-analyses of its
/// corners. A [`LimitSurface`](super::LimitSurface) keeps the shapes of its shared regions
/// across [`set_positions`](super::LimitSurface::set_positions), so re-posing a face near
/// such a vertex only interpolates the region's points, level by level.
#[derive(Debug, Default)]
pub(super) struct Shape {
    /// The cut-out topology.
    pub topo: Topology,
    /// How far cut-outs of it reach.
    reach: Reach,
    /// Shared by many faces: then its refinement, the regions cut from that and corner
    /// analyses are cached; a face's own cut-out is refined afresh each time.
    shared: bool,
    /// For a region cut around a vertex: the faces of the level it was cut from, sorted,
    /// with their index here.
    faces: Vec<(u32, u32)>,
    /// For a region cut around a vertex: the vertex of the level it was cut from of each
    /// of its vertices.
    verts: Vec<u32>,
    /// The refined shape (shared regions only).
    refined: OnceLock<Arc<Shape>>,
    /// Shapes of the regions cut from this one, by vertex (see [`region_cut`]).
    regions: ShapeCache,
    /// Eigen-analyses of corners, by (vertex, first face of the sector).
    pub(super) eigen: CornerCache<Option<Arc<super::corner::Eigen>>>,
    /// Per face of a shared shape, what it is (see [`LevelRef::kinds`]); empty otherwise.
    kinds: Box<[OnceLock<Box<FaceKind>>]>,
    /// The surface's configuration trees, for the irregular faces of a shared shape that
    /// do not reach its high-valence vertex (see [`FaceKind::Tree`]).
    trees: Option<Arc<TreeCache>>,
}

/// Shapes of the regions cut around the high-valence vertices of one level, by vertex.
#[derive(Debug, Default)]
pub(super) struct ShapeCache(Mutex<HashMap<Seed, Arc<OnceLock<Arc<Shape>>>>>);

/// A cut-out (or a whole refined cut-out) with positions: a [`Shape`] and its points.
#[derive(Debug, Default)]
pub(super) struct Region {
    /// The topology and what derives from it.
    pub shape: Arc<Shape>,
    /// Positions of its vertices.
    pub pos: Vec<[f64; 3]>,
    /// The refined region (shared regions only).
    refined: OnceLock<Arc<Region>>,
    /// Regions cut from this one, by vertex (see [`region_cut`]).
    regions: RegionCache,
    /// What points at its vertices of high valence read (by vertex, second key 0).
    pub(super) high: CornerCache<Arc<super::corner::HighCorner>>,
}

/// The value of `key` in `cache`, computed by `make` the first time.
pub(super) fn cached<T: Clone>(
    cache: &CornerCache<T>,
    key: (u32, u32),
    make: impl FnOnce() -> T,
) -> T {
    cell(cache, key).get_or_init(make).clone()
}

/// The cell of `key` in a map behind a mutex (a poisoned lock is taken as it is: cells are
/// only ever inserted).
pub(super) fn cell<K: std::hash::Hash + Eq, T, S: std::hash::BuildHasher>(
    cache: &Mutex<HashMap<K, Arc<OnceLock<T>>, S>>,
    key: K,
) -> Arc<OnceLock<T>> {
    super::lock(cache).entry(key).or_default().clone()
}

/// Regions cut around high-valence vertices of one level, by vertex.
#[derive(Debug, Default)]
pub(super) struct RegionCache(Mutex<HashMap<Seed, Arc<OnceLock<Arc<Region>>>>>);

/// A face of a region.
#[derive(Clone, Debug)]
pub(super) struct Local {
    /// The region.
    pub region: Arc<Region>,
    /// The face of interest in it (its vertex order is the original face's).
    pub face: usize,
}

/// A level to cut from: its topology, positions and the caches of its shared regions.
#[derive(Clone, Copy)]
pub(super) struct LevelRef<'a> {
    /// Topology.
    pub topo: &'a Topology,
    /// Positions.
    pub pos: &'a [[f64; 3]],
    /// Shapes of the shared regions cut from it (kept across positions).
    pub shapes: &'a ShapeCache,
    /// Shared regions already cut from it (these positions).
    pub cache: &'a RegionCache,
    /// Per face, what it is, found once and kept across positions (a shared region's
    /// faces); empty: found afresh.
    pub kinds: &'a [OnceLock<Box<FaceKind>>],
    /// Configuration trees for its irregular faces whose 1-ring has no high-valence
    /// vertex, if any (the base level, shared regions); `None`: own cut-outs.
    pub trees: Option<&'a Arc<TreeCache>>,
    /// How far cut-outs of it reach.
    pub reach: Reach,
}

impl<'a> LevelRef<'a> {
    /// The base level of a surface, with what its faces share.
    pub(super) fn new(
        topo: &'a Topology,
        pos: &'a [[f64; 3]],
        shared: &'a Shared,
        cache: &'a RegionCache,
        reach: Reach,
    ) -> Self {
        Self {
            topo,
            pos,
            shapes: &shared.regions,
            cache,
            kinds: &[],
            trees: Some(&shared.trees),
            reach,
        }
    }
}

impl Shape {
    /// A shape of its own (a face's cut-out, not shared).
    fn own(topo: Topology, reach: Reach) -> Self {
        Self {
            topo,
            reach,
            ..Self::default()
        }
    }

    /// A shared shape.
    fn shared(topo: Topology, reach: Reach, trees: Option<Arc<TreeCache>>) -> Self {
        let kinds = (0..topo.num_faces()).map(|_| OnceLock::new()).collect();
        Self {
            topo,
            reach,
            shared: true,
            kinds,
            trees,
            ..Self::default()
        }
    }

    /// A shape to be evaluated with many sets of points (unit vectors, to find an
    /// evaluation's weights): shared, so that the analyses of its corners and its
    /// refinements are computed once for all of them.
    pub(super) fn probed(topo: Topology) -> Arc<Self> {
        Arc::new(Self::shared(topo, Reach::default(), None))
    }

    /// The shape refined one level: computed once for a shared shape, afresh otherwise.
    fn refined(&self, options: &Options) -> Arc<Shape> {
        let make = || {
            let topo = refine_topology(&self.topo, options, true);
            Arc::new(if self.shared {
                Shape::shared(topo, self.reach, self.trees.clone())
            } else {
                Shape::own(topo, self.reach)
            })
        };
        if self.shared {
            self.refined.get_or_init(make).clone()
        } else {
            make()
        }
    }
}

impl Region {
    /// A whole level as a region of its own, not shared.
    pub(super) fn whole(topo: Topology, pos: Vec<[f64; 3]>, reach: Reach) -> Self {
        Self::new(Arc::new(Shape::own(topo, reach)), pos)
    }

    /// Shape `shape` with points `pos`.
    pub(super) fn new(shape: Arc<Shape>, pos: Vec<[f64; 3]>) -> Self {
        Self {
            shape,
            pos,
            ..Self::default()
        }
    }

    /// This region as a level to cut from.
    pub(super) fn level(&self) -> LevelRef<'_> {
        LevelRef {
            topo: &self.shape.topo,
            pos: &self.pos,
            shapes: &self.shape.regions,
            cache: &self.regions,
            kinds: &self.shape.kinds,
            trees: self.shape.trees.as_ref(),
            reach: self.shape.reach,
        }
    }

    /// The net of face `f`, if the region keeps what its faces are (a shared region) and
    /// `f` has been found to be a regular patch.
    pub(super) fn patch_net(&self, f: usize) -> Option<&Net> {
        match self.shape.kinds.get(f)?.get()?.as_ref() {
            FaceKind::Patch(net) => Some(net),
            _ => None,
        }
    }

    /// Whether this region is shared by many faces (and caches its work).
    pub(super) fn is_shared(&self) -> bool {
        self.shape.shared
    }

    /// The region refined one level (full topology, positions by the level's rules):
    /// computed once for a shared region (whose refined shape is kept across positions),
    /// afresh otherwise.
    pub(super) fn refined(&self, options: &Options) -> Arc<Region> {
        let make = || {
            let child = self.shape.refined(options);
            let mut cpos = vec![[0.0; 3]; child.topo.num_vertices()];
            interpolate(&self.shape.topo, &child.topo, options, &self.pos, &mut cpos);
            Arc::new(Region::new(child, cpos))
        };
        if self.is_shared() {
            self.refined.get_or_init(make).clone()
        } else {
            make()
        }
    }
}

impl Local {
    /// The region's topology.
    pub(super) fn topo(&self) -> &Topology {
        &self.region.shape.topo
    }

    /// The region's positions.
    pub(super) fn pos(&self) -> &[[f64; 3]] {
        &self.region.pos
    }

    /// Index of the face's child at its corner `j` in the refined region.
    pub(super) fn child_face(&self, j: usize) -> usize {
        self.topo().face_offsets()[self.face] as usize + j
    }

    /// The face's child at its corner `k`, in the region refined one level.
    pub(super) fn child(&self, k: usize, options: &Options) -> Local {
        Local {
            face: self.child_face(k),
            region: self.region.refined(options),
        }
    }
}

/// What a face of a level is, as far as its limit surface goes: found from the topology
/// alone, so a shared region finds it once for all positions.
#[derive(Debug)]
pub(super) enum FaceKind {
    /// A hole: no surface.
    Hole,
    /// A regular patch with this control net.
    Patch(Net),
    /// Irregular, in the shared region of this high-valence vertex or large face.
    Region(Seed),
    /// Irregular, with its own cut-out: these faces (its 1-ring).
    Own(Vec<u32>),
    /// An irregular quad whose 1-ring has no high-valence vertex, in a level that has
    /// configuration trees (a shared region of a surface): the tree of its configuration
    /// and its cut-out's vertices, so that its local refinement is kept as weights across
    /// positions, like a base face's.
    Tree(Arc<Tree>, Arc<[u32]>),
}

impl FaceKind {
    /// What face `f` of `level` is.
    pub(super) fn find(level: LevelRef<'_>, f: usize) -> FaceKind {
        if level.topo.is_hole(f) {
            return FaceKind::Hole;
        }
        if let Some(cells) = regular_patch_cells(level.topo, f) {
            return FaceKind::Patch(Net::new(cells));
        }
        match (cut_out(level.topo, f, level.reach), level.trees) {
            (Ok(faces), Some(trees)) if level.topo.face_vertices(f).len() == 4 => {
                let (sub, verts) = level.topo.subset_canonical(&faces);
                FaceKind::Tree(trees.get(sub), verts.into())
            }
            (Ok(faces), _) => FaceKind::Own(faces),
            (Err(w), _) => FaceKind::Region(w),
        }
    }
}

/// The cut-out of `faces` of `level`, the face of interest first.
pub(super) fn own_cut(level: LevelRef<'_>, faces: &[u32]) -> Local {
    let (topo, verts) = level.topo.subset(faces);
    let pos = verts.iter().map(|&v| level.pos[v as usize]).collect();
    Local {
        region: Arc::new(Region::whole(topo, pos, level.reach)),
        face: 0,
    }
}

/// Face `f` of `level` in the shared region of `seed` (a vertex or face its 1-ring
/// reaches).
pub(super) fn region_cut(level: LevelRef<'_>, f: usize, seed: Seed) -> Local {
    let region = cell(&level.cache.0, seed)
        .get_or_init(|| {
            let shape = cell(&level.shapes.0, seed)
                .get_or_init(|| Arc::new(seed_region(level, seed)))
                .clone();
            let pos = shape.verts.iter().map(|&v| level.pos[v as usize]).collect();
            Arc::new(Region::new(shape, pos))
        })
        .clone();
    let faces = &region.shape.faces;
    match faces.binary_search_by_key(&(f as u32), |&(g, _)| g) {
        Ok(i) => Local {
            face: faces[i].1 as usize,
            region,
        },
        // Unreachable by the argument in the module docs; fall back to the face's own
        // (large) cut-out rather than fail.
        Err(_) => own_cut(
            level,
            &cut_out_unbounded(level.topo, f, level.reach.chaikin),
        ),
    }
}

/// Faces of the cut-out of `f` ([`cut_out_unbounded`]), `f` first, each once; `Err` with
/// the seed of a shared region as soon as the cut-out would hold a face of more than
/// `reach.large_face` corners ([`is_large_face`]: `f` itself, or a face of its 1-ring)
/// or reach a vertex of more than `reach.high_valence` faces among the 1-ring's vertices
/// (any such vertex or face gives a region that holds the cut-out). Where
/// [`is_sectored`], it is the sector at that vertex of the face met that counts. The
/// faces added for Chaikin's rule are not checked: a high-valence vertex among them costs
/// its faces in this cut-out, and the region of such a vertex would not hold the cut-outs
/// of all faces that reach it so.
pub(super) fn cut_out(t: &Topology, f: usize, reach: Reach) -> Result<Vec<u32>, Seed> {
    let hv = reach.high_valence;
    if is_large_face(t, f, reach.large_face) {
        return Err(Seed::Face(f as u32));
    }
    // Whether corner `k` of face `g` reaches too many faces: all of its vertex's, or
    // `g`'s sector there where [`is_sectored`] (walked only if the vertex has too many).
    let big = |g: usize, k: usize| {
        let v = t.face_vertices(g)[k] as usize;
        is_high_valence(t, v, hv)
            && (!is_sectored(t, v) || sector(t, g, k, fan_limit(t, v, hv)).is_none())
    };
    // The corners first; the sectors of those where [`is_sectored`] are walked, and
    // bounded, as the ring is listed.
    let plain_big = |&&v: &&u32| !is_sectored(t, v as usize) && is_high_valence(t, v as usize, hv);
    if let Some(&w) = t.face_vertices(f).iter().find(plain_big) {
        return Err(Seed::Vertex(w));
    }
    let mut faces = ring_faces(t, f, hv).map_err(Seed::Vertex)?;
    for &g in &faces.list[1..] {
        let g = g as usize;
        if is_large_face(t, g, reach.large_face) {
            return Err(Seed::Face(g as u32));
        }
        if let Some(k) = (0..t.face_vertices(g).len()).find(|&k| big(g, k)) {
            return Err(Seed::Vertex(t.face_vertices(g)[k]));
        }
    }
    if reach.chaikin {
        add_far_ends(t, f, &mut faces);
    }
    Ok(faces.list)
}

/// The faces whose topology and points determine the surface over face `f` and its local
/// refinement, `f` first, each once: its 1-ring (with only its sectors at a corner where
/// [`is_sectored`]), and with `chaikin`, after it the faces around the far end of each
/// semi-sharp edge at a corner (module docs, "Chaikin's rule").
pub(super) fn cut_out_unbounded(t: &Topology, f: usize, chaikin: bool) -> Vec<u32> {
    let Ok(mut faces) = ring_faces(t, f, usize::MAX) else {
        unreachable!("no sector has more than usize::MAX faces")
    };
    if chaikin {
        add_far_ends(t, f, &mut faces);
    }
    faces.list
}

/// Faces listed once each, in the order first added: found by a linear search while they
/// are few (a cut-out has a few dozen), by a map from face to place once there are more
/// than [`FaceList::SEARCHED`] (the 1-ring of an `n`-gon has `O(n)` faces, and a linear
/// search per face added made its cut-out `O(n²)`: 4 s for a 65 535-gon).
#[derive(Default)]
struct FaceList {
    list: Vec<u32>,
    /// Face → its place in `list`, once `list` is longer than [`FaceList::SEARCHED`].
    places: Option<HashMap<u32, usize>>,
}

impl FaceList {
    /// Most faces searched linearly.
    const SEARCHED: usize = 32;

    /// Where face `g` is in the list.
    fn position(&self, g: u32) -> Option<usize> {
        match &self.places {
            Some(places) => places.get(&g).copied(),
            None => self.list.iter().position(|&x| x == g),
        }
    }

    /// Appends face `g` unless it is listed.
    fn add(&mut self, g: u32) {
        if self.position(g).is_some() {
            return;
        }
        self.list.push(g);
        match &mut self.places {
            Some(places) => {
                places.insert(g, self.list.len() - 1);
            }
            None if self.list.len() > Self::SEARCHED => {
                let places = self.list.iter().enumerate().map(|(i, &x)| (x, i));
                self.places = Some(places.collect());
            }
            None => {}
        }
    }
}

/// Faces of the 1-ring of `f`, `f` first: around each corner from `f` on, so that faces
/// whose neighbourhoods differ only by where a corner's cycle starts list them in the same
/// order (see `Topology::subset_canonical`). At a corner where [`is_sectored`], only the
/// faces of `f`'s sector there ([`sector`]); `Err` with that corner if they are more
/// than [`fan_limit`] allows with `high_valence`.
fn ring_faces(t: &Topology, f: usize, high_valence: usize) -> Result<FaceList, u32> {
    let mut faces = FaceList::default();
    faces.add(f as u32);
    for (k, &v) in t.face_vertices(f).iter().enumerate() {
        if is_sectored(t, v as usize) {
            let limit = fan_limit(t, v as usize, high_valence);
            for g in sector(t, f, k, limit).ok_or(v)? {
                faces.add(g);
            }
            continue;
        }
        let around = t.vertex_faces(v as usize);
        let start = around.iter().position(|&g| g == f as u32).unwrap_or(0);
        for &g in around[start..].iter().chain(&around[..start]) {
            faces.add(g);
        }
    }
    Ok(faces)
}

/// The faces of the sector of `f` at its corner `k`, vertex `v`, in the order met: the
/// corners at `v` reached from `f`'s by crossing, repeatedly, an edge at `v` that is not
/// infinitely sharp (nor, therefore, a boundary or a non-manifold edge) into the other of
/// its two faces, at the corner that edge bounds there. Such edges join the corners at
/// `v` in paths and cycles, so the walk goes one way from `f` until a sharp edge or back
/// to `f`, then the other way: `O(sector)`, and the list depends on the sector's shape
/// alone. Where an edge does not tell the corner (an edge from `v` to itself, two faces
/// running it the same way, or a walk longer than `v` has corners), all of `v`'s faces
/// instead. `None` if more than `limit` corners (or, in that fallback, faces).
fn sector(t: &Topology, f: usize, k: usize, limit: usize) -> Option<Vec<u32>> {
    let v = t.face_vertices(f)[k];
    let around = t.vertex_faces(v as usize);
    // The corner of the other face of edge `e` of face `g` that `e` bounds, if it is
    // crossed and tells one; `Err` if it is crossed and does not.
    let across = |g: usize, e: u32| -> Result<Option<(usize, usize)>, ()> {
        if t.edge_tag(e as usize).inf_sharp {
            return Ok(None);
        }
        let h = match *t.edge_face_list(e as usize) {
            [a, b] if a != b => (if a as usize == g { b } else { a }) as usize,
            _ => return Err(()),
        };
        let (hv, he) = (t.face_vertices(h), t.face_edge_list(h));
        let n = hv.len();
        let mut at = (0..n).filter(|&j| hv[j] == v && (he[j] == e || he[(j + n - 1) % n] == e));
        match (at.next(), at.next()) {
            (Some(j), None) => Ok(Some((h, j))),
            _ => Err(()),
        }
    };
    let mut corners = vec![(f, k)];
    let walked = (|| -> Result<bool, ()> {
        // First across the edges entering `v` (`enter`), then across those leaving it.
        for enter in [true, false] {
            let (mut g, mut i) = (f, k);
            loop {
                let (gv, ge) = (t.face_vertices(g), t.face_edge_list(g));
                let e = ge[if enter {
                    (i + gv.len() - 1) % gv.len()
                } else {
                    i
                }];
                let Some((h, j)) = across(g, e)? else { break };
                if (h, j) == (f, k) {
                    // Round `v` and back: the whole cycle, walked one way.
                    return Ok(true);
                }
                corners.push((h, j));
                if corners.len() > limit {
                    return Ok(false);
                }
                if corners.len() > around.len() {
                    return Err(());
                }
                // In `h` (oriented as `g`) the edge crossed leaves `v` if it entered it in
                // `g`; the walk goes on across the other edge at that corner.
                let (hv, he) = (t.face_vertices(h), t.face_edge_list(h));
                if (he[(j + hv.len() - 1) % hv.len()] == e) == enter {
                    return Err(());
                }
                (g, i) = (h, j);
            }
        }
        Ok(true)
    })();
    match walked {
        Ok(true) => Some(corners.iter().map(|&(g, _)| g as u32).collect()),
        Ok(false) => None,
        Err(()) => (around.len() <= limit).then(|| around.to_vec()),
    }
}

/// Appends to the 1-ring `faces` of `f` the faces around the far end `w` of each
/// semi-sharp edge at a corner of `f` (`w` not a corner), around `w` from its face listed
/// first so far (for the reason of [`ring_faces`]).
fn add_far_ends(t: &Topology, f: usize, faces: &mut FaceList) {
    let corners = t.face_vertices(f);
    // The corners as a set when they are many (an `n`-gon's).
    let corner_set: Option<HashSet<u32>> =
        (corners.len() > FaceList::SEARCHED).then(|| corners.iter().copied().collect());
    let is_corner = |w: u32| match &corner_set {
        Some(set) => set.contains(&w),
        None => corners.contains(&w),
    };
    for &v in corners {
        for &e in t.vertex_edges(v as usize) {
            if !t.edge_tag(e as usize).semi_sharp {
                continue;
            }
            let [a, b] = t.edge_vertices(e as usize);
            let w = if a == v { b } else { a };
            if is_corner(w) {
                continue;
            }
            let around = t.vertex_faces(w as usize);
            let start = around
                .iter()
                .enumerate()
                .filter_map(|(i, &g)| faces.position(g).map(|at| (at, i)))
                .min()
                .map_or(0, |(_, i)| i);
            for &g in around[start..].iter().chain(&around[..start]) {
                faces.add(g);
            }
        }
    }
}

/// The shape of the shared region of `seed`: the faces within three rings of a vertex
/// (four under Chaikin's rule), within two rings of a face (three under Chaikin's rule;
/// module docs).
fn seed_region(level: LevelRef<'_>, seed: Seed) -> Shape {
    let t = level.topo;
    let chaikin = level.reach.chaikin as usize;
    // The vertices the first ring is around, and the rings after it.
    let (start, rings): (&[u32], usize) = match &seed {
        Seed::Vertex(w) => (std::slice::from_ref(w), 2 + chaikin),
        Seed::Face(h) => (t.face_vertices(*h as usize), 1 + chaikin),
    };
    let mut seen: HashSet<u32> = HashSet::new();
    let mut faces: Vec<u32> = Vec::new();
    let mut visited: HashSet<u32> = HashSet::new();
    for &w in start {
        visited.insert(w);
        for &g in t.vertex_faces(w as usize) {
            if seen.insert(g) {
                faces.push(g);
            }
        }
    }
    let mut from = 0;
    for _ in 0..rings {
        let end = faces.len();
        for i in from..end {
            for &v in t.face_vertices(faces[i] as usize) {
                if !visited.insert(v) {
                    continue;
                }
                for &g in t.vertex_faces(v as usize) {
                    if seen.insert(g) {
                        faces.push(g);
                    }
                }
            }
        }
        from = end;
    }
    let (topo, verts) = t.subset(&faces);
    let mut map: Vec<(u32, u32)> = faces
        .iter()
        .enumerate()
        .map(|(i, &g)| (g, i as u32))
        .collect();
    map.sort_unstable();
    let reach = match seed {
        Seed::Vertex(_) => level.reach,
        Seed::Face(_) => level.reach.in_face_region(),
    };
    Shape {
        verts,
        faces: map,
        ..Shape::shared(topo, reach, level.trees.cloned())
    }
}
