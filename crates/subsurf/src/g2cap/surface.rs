//! [`G2Surface`]: the Catmull-Clark limit surface of a mesh with a G2 cap
//! ([`G2Cap`]) at every cappable extraordinary vertex, evaluable at `(face, u, v)`.
//!
//! # Isolation and data
//! After `L` Catmull-Clark steps (`L = 2`, or 3 when the mesh has non-quad faces: their
//! centres and corners are then four level-`L` edges apart) an extraordinary vertex is
//! surrounded by `n` faces of side `h = 2⁻ᴸ` of a base quad's parameter square (`2¹⁻ᴸ` of
//! an `n`-gon's sub-face), and every face next to them is a regular bicubic patch. The
//! cap replaces the surface on those `n` corner squares. Its input, the bicubic patches
//! across the outer edges, is recovered exactly from the [`LimitSurface`] (the exact
//! Catmull-Clark evaluator, which performs this isolating refinement locally) by
//! interpolation at 4×4 points of each neighbouring square, and checked at further
//! points: if a neighbour is not bicubic to `1e-9` of the cap's size (a crease, boundary
//! or another extraordinary vertex too close), the vertex keeps Catmull-Clark.
//! Only this outer ring enters the cap, so a different scheme for the regular part
//! only changes these bicubic patches.
//!
//! # The mixed (shape-adjustable) surface
//! [`G2Surface::new`] with [`Scheme::Adjustable`] caps the limit surface of mixed subdivision ([`MixedSurface`]:
//! `k` steps of the adjustable scheme with parameter `c`, then Catmull-Clark; [Tang et al. 2017]).
//! Its regular part is the bicubic B-spline of the `c`-refined net, but only *per face of
//! the refined mesh*: for `c ≠ ½` that net is not the Catmull-Clark refinement of a coarser
//! one, so a square larger than a refined face holds several bicubic pieces. The caps
//! therefore sit on squares of side `2⁻ᴸ` with `L ≥ k + 1` (`L = max(2, k + 1)`, or
//! `max(3, k + 1)` with non-quad faces), one Catmull-Clark step inside the refined faces at
//! the vertex, where — exactly as for Catmull-Clark at `L = 2` — every neighbouring square
//! is one bicubic patch of the refined net (the refined mesh has only quads, and the
//! vertices next to an extraordinary vertex are regular). Everything else is unchanged:
//! the outer bicubics are recovered from the mixed surface, evaluated at the input's
//! `(face, u, v)` through [`MixedSurface::eval_point`], and the caps are solved from them.
//!
//! `c = ½` (and `k = 0`) *is* Catmull-Clark, and [`G2Surface::new`] with [`Scheme::Adjustable`] then builds
//! exactly [`G2Surface::new`]'s surface, from the Catmull-Clark evaluator. (Through the
//! refined mesh the same surface differs only by rounding: the outer bicubics by
//! `~2·10⁻¹⁶`, the caps by `~3·10⁻¹³` — [`CapSolver`] is well conditioned; the tests
//! check that the general path converges to the Catmull-Clark caps as `c → ½`.)
//!
//! # Addressing
//! As [`LimitSurface`]: quad faces with `(0,0)` at vertex 0, `u` toward vertex 1; an
//! `n`-gon through its sub-faces. A cap patch sits at corner `k` of a (sub-)face; its
//! coordinates `(s, t)` map to the face's by `(u, v) = oₖ + h·Lₖ (s, t)` with `Lₖ` the
//! rotation by `k·90°` (corner 0: `(hs, ht)`, 1: `(1-ht, hs)`, 2: `(1-hs, 1-ht)`,
//! 3: `(ht, 1-hs)`), so that `s` runs along the face edge leaving the corner and `t`
//! along the edge entering it. Derivatives are returned in the face's `(u, v)`.

use super::bezier::BezierPatch;
use super::cap::{G2Cap, OuterPatches};
use super::solver::CapSolver;
use super::G2Error;
use crate::limit::{Derivatives, EvalError, LimitSurface, SurfacePoint};
use crate::mesh::{Options, PolyMesh, Rule, Topology};
use crate::mixed::MixedSurface;
use crate::scheme::adjustable::Adjustable;
use crate::scheme::Scheme;
use rayon::prelude::*;
use std::collections::HashMap;

/// Options of [`G2Surface::new`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct G2SurfaceOptions {
    /// The scheme of the surrounding surface: Catmull-Clark, or the shape-adjustable scheme
    /// ([`Scheme::Adjustable`]: the caps join the mixed surface, [`MixedSurface`]). NURSS is
    /// refused ([`G2Error::Scheme`]).
    pub scheme: Scheme,
    /// The rules' options (boundary interpolation etc.) of the surrounding surface.
    pub options: Options,
    /// Isolation levels `L` (≥ 2; `None`: 2, or 3 with non-quad faces; with `k` adjustable
    /// steps at least `k + 1`).
    pub levels: Option<u32>,
    /// Stop building the Catmull-Clark limit surface as soon as the neighbourhoods of
    /// irregular faces it finds would take its estimate over this many bytes
    /// ([`LimitSurface::new_within`]; [`G2Error::TooLarge`]). Not applied to the mixed
    /// surface, whose build is bounded by its refined mesh.
    pub max_memory: Option<u64>,
}

/// Where one cap patch lies: corner `corner` of sub-face `subface` of base face `face`,
/// covering the corner square of side `size` of that (sub-)face's parameter domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchRef {
    /// Base face.
    pub face: u32,
    /// Sub-face (0 for quads).
    pub subface: u32,
    /// Corner 0..4 of the (sub-)face at the extraordinary vertex.
    pub corner: u8,
    /// Side `h` of the square in the (sub-)face's parameters.
    pub size: f64,
}

impl PatchRef {
    /// Face parameters of cap coordinates `(s, t)`.
    pub fn to_face(&self, s: f64, t: f64) -> (f64, f64) {
        let h = self.size;
        match self.corner {
            0 => (h * s, h * t),
            1 => (1.0 - h * t, h * s),
            2 => (1.0 - h * s, 1.0 - h * t),
            _ => (h * t, 1.0 - h * s),
        }
    }

    /// Cap coordinates of face parameters `(u, v)` (inverse of [`to_face`](Self::to_face)).
    pub fn to_cap(&self, u: f64, v: f64) -> (f64, f64) {
        let h = self.size;
        match self.corner {
            0 => (u / h, v / h),
            1 => (v / h, (1.0 - u) / h),
            2 => ((1.0 - u) / h, (1.0 - v) / h),
            _ => ((1.0 - v) / h, u / h),
        }
    }

    /// `J = ∂(s, t)/∂(u, v)` as `[[∂s/∂u, ∂s/∂v], [∂t/∂u, ∂t/∂v]]`.
    fn jacobian(&self) -> [[f64; 2]; 2] {
        let g = 1.0 / self.size;
        match self.corner {
            0 => [[g, 0.0], [0.0, g]],
            1 => [[0.0, g], [-g, 0.0]],
            2 => [[-g, 0.0], [0.0, -g]],
            _ => [[0.0, -g], [g, 0.0]],
        }
    }

    /// Derivatives in cap coordinates → derivatives in face coordinates.
    pub fn cap_to_face(&self, d: &Derivatives) -> Derivatives {
        transform(d, self.jacobian())
    }

    /// Derivatives in face coordinates → derivatives in cap coordinates.
    pub fn face_to_cap(&self, d: &Derivatives) -> Derivatives {
        let j = self.jacobian();
        // The inverse of a scaled rotation: transpose over the squared scale.
        let g2 = j[0][0] * j[0][0] + j[0][1] * j[0][1];
        let inv = [[j[0][0] / g2, j[1][0] / g2], [j[0][1] / g2, j[1][1] / g2]];
        transform(d, inv)
    }

    fn point(&self, s: f64, t: f64) -> SurfacePoint {
        let (u, v) = self.to_face(s, t);
        SurfacePoint {
            face: self.face,
            subface: self.subface,
            u: u.clamp(0.0, 1.0),
            v: v.clamp(0.0, 1.0),
        }
    }
}

/// Chain rule for `Q(x) = P(J x)`-type linear reparametrisations: with
/// `J = ∂(s,t)/∂(u,v)`, returns the `(u, v)` derivatives of a surface given by its
/// `(s, t)` derivatives `d`.
fn transform(d: &Derivatives, j: [[f64; 2]; 2]) -> Derivatives {
    let (a, b, c, e) = (j[0][0], j[0][1], j[1][0], j[1][1]);
    let mut r = Derivatives {
        p: d.p,
        ..Default::default()
    };
    for k in 0..3 {
        r.du[k] = a * d.du[k] + c * d.dv[k];
        r.dv[k] = b * d.du[k] + e * d.dv[k];
        r.duu[k] = a * a * d.duu[k] + 2.0 * a * c * d.duv[k] + c * c * d.dvv[k];
        r.duv[k] = a * b * d.duu[k] + (a * e + c * b) * d.duv[k] + c * e * d.dvv[k];
        r.dvv[k] = b * b * d.duu[k] + 2.0 * b * e * d.duv[k] + e * e * d.dvv[k];
    }
    r
}

/// One cap of a [`G2Surface`].
#[derive(Clone, Debug)]
pub struct CapInfo {
    /// The extraordinary vertex (input vertex index), or `None` for the centre of a face.
    pub vertex: Option<usize>,
    /// For the centre of an `n`-gon: its face.
    pub face_centre: Option<usize>,
    /// Where each patch lies, in order (patch `i` shares its edge `u = 0` with the edge
    /// `v = 0` of patch `i + 1`).
    pub slots: Vec<PatchRef>,
    /// The bi-septic patches.
    pub cap: G2Cap,
}

/// An extraordinary vertex (or face centre) that keeps the Catmull-Clark surface, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Uncapped {
    /// The vertex, or `None` for a face centre.
    pub vertex: Option<usize>,
    /// The face, for a face centre.
    pub face: Option<usize>,
    /// The valence.
    pub valence: usize,
    /// Why it is not capped.
    pub reason: &'static str,
}

/// The G2 surface of a mesh: Catmull-Clark (bicubic B-spline after isolation) with a G2
/// cap at every interior smooth extraordinary vertex of valence 3..=16 and at the centre
/// of every interior `n`-gon ([`new`](Self::new)); or the same for the mixed
/// (shape-adjustable) surface ([`new`](Self::new) with [`Scheme::Adjustable`]). See the
/// module docs for the layout.
#[derive(Clone, Debug)]
pub struct G2Surface {
    limit: LimitSurface,
    /// The mixed surface underneath, for [`G2Surface::new`] with [`Scheme::Adjustable`].
    mixed: Option<MixedSurface>,
    levels: u32,
    caps: Vec<CapInfo>,
    uncapped: Vec<Uncapped>,
    /// (face, subface) → (cap, patch) of the caps at its corners.
    lookup: HashMap<(u32, u32), Vec<(usize, usize)>>,
    size: f64,
}

/// A candidate: vertex or face centre with its ordered slots.
struct Candidate {
    vertex: Option<usize>,
    face: Option<usize>,
    slots: Vec<PatchRef>,
}

impl G2Surface {
    /// Builds the surface of `mesh`: the surface of `options.scheme` outside the caps, and
    /// the caps joined to it G2. With [`Scheme::Adjustable`] (`k = mixed.steps` steps of
    /// the shape-adjustable scheme with parameter `c`, then Catmull-Clark) the surrounding
    /// surface is the mixed surface ([`MixedSurface`]: the bicubic B-spline of the
    /// `c`-refined net), evaluated at the input's `(face, u, v)`, and the isolation level is
    /// raised to at least `k + 1` (see the module docs); with `c = ½` or `k = 0` it
    /// is the Catmull-Clark surface and the result is exactly Catmull-Clark's (with no
    /// [`mixed`](Self::mixed) surface).
    ///
    /// # Errors
    /// [`G2Error::Mesh`] for an invalid mesh (or a refined mesh beyond 32-bit indices);
    /// [`G2Error::Scheme`] for NURSS; [`G2Error::TooLarge`] over `options.max_memory`;
    /// [`G2Error::Inconsistent`] if a cap's constraints cannot be met (not expected).
    pub fn new(mesh: &PolyMesh, options: &G2SurfaceOptions) -> Result<Self, G2Error> {
        let mixed = match options.scheme {
            Scheme::CatmullClark => None,
            Scheme::Adjustable(m) if m.steps == 0 || m.scheme == Adjustable::CATMULL_CLARK => None,
            Scheme::Adjustable(m) => Some(MixedSurface::new(mesh, options.options, m)?),
            s => return Err(G2Error::Scheme(s.name())),
        };
        let max_bytes = options.max_memory.filter(|_| mixed.is_none());
        Self::build(mesh, options, mixed, max_bytes)
    }

    fn build(
        mesh: &PolyMesh,
        options: &G2SurfaceOptions,
        mixed: Option<MixedSurface>,
        max_bytes: Option<u64>,
    ) -> Result<Self, G2Error> {
        let limit = match max_bytes {
            None => LimitSurface::new(mesh, options.options)?,
            Some(max) => {
                LimitSurface::new_within(mesh, options.options, max).map_err(|e| match e {
                    crate::limit::BuildError::Mesh(m) => G2Error::Mesh(m),
                    e => G2Error::TooLarge(e),
                })?
            }
        };
        let (topo, _) = Topology::from_mesh(mesh, &options.options)?;
        let has_ngon = (0..topo.num_faces()).any(|f| topo.face_vertices(f).len() != 4);
        // Caps must lie inside one face of the c-refined mesh (module docs).
        let min_levels = mixed
            .as_ref()
            .map_or(2, |m| m.mixed().steps.saturating_add(1).max(2));
        let levels = options
            .levels
            .unwrap_or(if has_ngon { 3 } else { 2 })
            .max(min_levels)
            .clamp(2, 20);
        let size = mesh
            .bounding_box()
            .map(|(lo, hi)| crate::geom::norm(&crate::geom::sub(&hi, &lo)))
            .unwrap_or(1.0)
            .max(f64::MIN_POSITIVE);
        let (candidates, mut uncapped) = candidates(&topo, levels);
        // One solver per valence.
        let mut valences: Vec<usize> = candidates.iter().map(|c| c.slots.len()).collect();
        valences.sort_unstable();
        valences.dedup();
        let solvers: HashMap<usize, CapSolver> = valences
            .par_iter()
            .map(|&n| CapSolver::new(n).map(|s| (n, s)))
            .collect::<Result<_, _>>()?;
        let base = |p: SurfacePoint| base_eval(&limit, mixed.as_ref(), p);
        let built: Vec<Result<Result<CapInfo, Uncapped>, G2Error>> = candidates
            .par_iter()
            .map(|c| build_cap(&base, c, &solvers[&c.slots.len()]))
            .collect();
        let mut caps = Vec::new();
        for b in built {
            match b? {
                Ok(c) => caps.push(c),
                Err(u) => uncapped.push(u),
            }
        }
        let mut lookup: HashMap<(u32, u32), Vec<(usize, usize)>> = HashMap::new();
        for (ci, c) in caps.iter().enumerate() {
            for (pi, s) in c.slots.iter().enumerate() {
                lookup
                    .entry((s.face, s.subface))
                    .or_default()
                    .push((ci, pi));
            }
        }
        Ok(Self {
            limit,
            mixed,
            levels,
            caps,
            uncapped,
            lookup,
            size,
        })
    }

    /// The Catmull-Clark limit surface of the input mesh (outside the caps the two agree,
    /// unless the surface was built with [`new`](Self::new) with [`Scheme::Adjustable`]: then see
    /// [`eval_uncapped`](Self::eval_uncapped)). Its faces and sub-faces are the domain.
    pub fn limit(&self) -> &LimitSurface {
        &self.limit
    }

    /// The mixed surface underneath, for a surface built with
    /// [`new`](Self::new) with [`Scheme::Adjustable`].
    pub fn mixed(&self) -> Option<&MixedSurface> {
        self.mixed.as_ref()
    }

    /// The surface without caps at a point: the Catmull-Clark limit surface, or the mixed
    /// surface for [`new`](Self::new) with [`Scheme::Adjustable`]. Outside the caps it equals
    /// [`eval_point`](Self::eval_point).
    ///
    /// # Errors
    /// As [`LimitSurface::eval_point`].
    pub fn eval_uncapped(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        base_eval(&self.limit, self.mixed.as_ref(), p)
    }

    /// The isolation level `L` used.
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// The caps.
    pub fn caps(&self) -> &[CapInfo] {
        &self.caps
    }

    /// Extraordinary vertices and face centres left with the Catmull-Clark surface.
    pub fn uncapped(&self) -> &[Uncapped] {
        &self.uncapped
    }

    /// The diagonal of the mesh's bounding box (the length scale of the report).
    pub fn size(&self) -> f64 {
        self.size
    }

    /// The cap patch containing a point, with its cap coordinates: `(cap, patch, s, t)`.
    pub fn locate(&self, p: SurfacePoint) -> Option<(usize, usize, f64, f64)> {
        const EPS: f64 = 1e-12;
        for &(ci, pi) in self.lookup.get(&(p.face, p.subface))? {
            let (s, t) = self.caps[ci].slots[pi].to_cap(p.u, p.v);
            if (-EPS..=1.0 + EPS).contains(&s) && (-EPS..=1.0 + EPS).contains(&t) {
                return Some((ci, pi, s.clamp(0.0, 1.0), t.clamp(0.0, 1.0)));
            }
        }
        None
    }

    /// Position and first and second derivatives (in the face's `(u, v)`) at a point.
    ///
    /// # Errors
    /// As [`LimitSurface::eval_point`] (no such face, hole, parameter outside `[0, 1]²`).
    pub fn eval_point(&self, p: SurfacePoint) -> Result<Derivatives, G2Error> {
        if !(0.0..=1.0).contains(&p.u) || !(0.0..=1.0).contains(&p.v) {
            return Err(crate::limit::EvalError::BadParameter { u: p.u, v: p.v }.into());
        }
        if let Some((ci, pi, s, t)) = self.locate(p) {
            let slot = &self.caps[ci].slots[pi];
            let d = self.caps[ci].cap.patches()[pi].eval(s, t);
            return Ok(slot.cap_to_face(&d));
        }
        Ok(self.eval_uncapped(p)?)
    }

    /// [`eval_point`](Self::eval_point) at `(u, v)` of quad `face` (sub-face 0).
    ///
    /// # Errors
    /// As [`eval_point`](Self::eval_point).
    pub fn eval(&self, face: u32, u: f64, v: f64) -> Result<Derivatives, G2Error> {
        self.eval_point(SurfacePoint {
            face,
            subface: 0,
            u,
            v,
        })
    }

    /// Evaluates many points in parallel; results in the same order.
    pub fn eval_many(&self, points: &[SurfacePoint]) -> Vec<Result<Derivatives, G2Error>> {
        points.par_iter().map(|&p| self.eval_point(p)).collect()
    }
}

/// The surface without caps: the mixed surface if there is one, else Catmull-Clark.
fn base_eval(
    limit: &LimitSurface,
    mixed: Option<&MixedSurface>,
    p: SurfacePoint,
) -> Result<Derivatives, EvalError> {
    match mixed {
        Some(m) => m.eval_point(p),
        None => limit.eval_point(p),
    }
}

/// The surface a cap is fitted to, evaluable at input points.
type Base<'a> = dyn Fn(SurfacePoint) -> Result<Derivatives, EvalError> + Sync + 'a;

/// Cappable extraordinary vertices and face centres with their ordered slots, and the
/// ones that are not cappable.
fn candidates(topo: &Topology, levels: u32) -> (Vec<Candidate>, Vec<Uncapped>) {
    let hq = 0.5f64.powi(levels as i32);
    let mut out = Vec::new();
    let mut skipped = Vec::new();
    let found = (0..topo.num_vertices())
        .filter_map(|v| vertex_candidate(topo, v, hq))
        .chain((0..topo.num_faces()).filter_map(|f| face_candidate(topo, f, 2.0 * hq)));
    for c in found {
        match c {
            Ok(c) => out.push(c),
            Err(u) => skipped.push(u),
        }
    }
    (out, skipped)
}

/// Why extraordinary vertex `v` with `n` faces cannot be capped, if it cannot: on a
/// boundary, sharp, of a valence without caps, or next to a hole.
fn uncappable_vertex(topo: &Topology, v: usize, n: usize) -> Option<&'static str> {
    let tag = topo.vertex_tag(v);
    if tag.boundary || tag.non_manifold {
        Some("boundary or non-manifold vertex")
    } else if tag.rule != Rule::Smooth
        || tag.semi_sharp
        || tag.inf_sharp
        || tag.semi_sharp_edges
        || tag.inf_sharp_edges
    {
        Some("sharp vertex or incident crease")
    } else if !(3..=super::MAX_CAP_VALENCE).contains(&n) {
        Some("valence outside 3..=16")
    } else if topo
        .vertex_faces(v)
        .iter()
        .any(|&f| topo.is_hole(f as usize))
    {
        Some("next to a hole")
    } else {
        None
    }
}

/// Vertex `v` as a cap's centre when it is extraordinary (not of valence 4, not isolated):
/// its slots in order (quad corners of size `hq`, sub-faces of other faces of twice
/// that), or why it cannot be capped.
fn vertex_candidate(topo: &Topology, v: usize, hq: f64) -> Option<Result<Candidate, Uncapped>> {
    let faces = topo.vertex_faces(v);
    let n = faces.len();
    if n == 4 || n == 0 {
        return None;
    }
    let uncapped = |reason| Uncapped {
        vertex: Some(v),
        face: None,
        valence: n,
        reason,
    };
    if let Some(reason) = uncappable_vertex(topo, v, n) {
        return Some(Err(uncapped(reason)));
    }
    // Slots with their leaving (s) and entering (t) edges, keyed by the far vertex.
    let mut slots = Vec::with_capacity(n);
    for (&f, &l) in faces.iter().zip(topo.vertex_face_locals(v)) {
        let fv = topo.face_vertices(f as usize);
        let m = fv.len();
        let l = l as usize;
        let next = fv[(l + 1) % m];
        let prev = fv[(l + m - 1) % m];
        let slot = if m == 4 {
            PatchRef {
                face: f,
                subface: 0,
                corner: l as u8,
                size: hq,
            }
        } else {
            PatchRef {
                face: f,
                subface: l as u32,
                corner: 0,
                size: 2.0 * hq,
            }
        };
        slots.push((slot, next, prev));
    }
    Some(match chain(&slots) {
        Some(ordered) => Ok(Candidate {
            vertex: Some(v),
            face: None,
            slots: ordered,
        }),
        None => Err(uncapped("faces around the vertex do not form one fan")),
    })
}

/// The centre of face `f` as a cap's centre when it is not a quad: its sub-faces of size
/// `hs` in order, or why it cannot be capped (a hole, too many sides).
fn face_candidate(topo: &Topology, f: usize, hs: f64) -> Option<Result<Candidate, Uncapped>> {
    let m = topo.face_vertices(f).len();
    if m == 4 {
        return None;
    }
    if topo.is_hole(f) || m > super::MAX_CAP_VALENCE {
        return Some(Err(Uncapped {
            vertex: None,
            face: Some(f),
            valence: m,
            reason: if topo.is_hole(f) {
                "hole"
            } else {
                "valence outside 3..=16"
            },
        }));
    }
    // Sub-face j, corner 2 (the centre): s toward the midpoint of edge j-1, t toward
    // that of edge j, so patch j+1 follows patch j.
    let slots = (0..m)
        .map(|j| PatchRef {
            face: f as u32,
            subface: j as u32,
            corner: 2,
            size: hs,
        })
        .collect();
    Some(Ok(Candidate {
        vertex: None,
        face: Some(f),
        slots,
    }))
}

/// Orders slots `(slot, s-end, t-end)` so that each slot's t-edge is the next one's
/// s-edge (`Pᵢ(0, t) = Pᵢ₊₁(t, 0)`).
fn chain(slots: &[(PatchRef, u32, u32)]) -> Option<Vec<PatchRef>> {
    let n = slots.len();
    let mut order = Vec::with_capacity(n);
    let mut used = vec![false; n];
    let mut cur = 0;
    for _ in 0..n {
        if used[cur] {
            return None;
        }
        used[cur] = true;
        order.push(slots[cur].0);
        let t_end = slots[cur].2;
        match slots
            .iter()
            .enumerate()
            .find(|(k, s)| !used[*k] && s.1 == t_end)
        {
            Some((k, _)) => cur = k,
            None if order.len() == n && slots[0].1 == t_end => break,
            None => return None,
        }
    }
    (order.len() == n).then_some(order)
}

/// Interpolates the bicubic surface on the square `[s0, s0+1] × [t0, t0+1]` of cap
/// coordinates of `slot` and checks it at other points; `Err(misfit)` if not bicubic.
fn neighbour(
    limit: &Base<'_>,
    slot: &PatchRef,
    s0: f64,
    t0: f64,
    scale: f64,
) -> Result<BezierPatch, f64> {
    let eval = |s: f64, t: f64| -> Option<[f64; 3]> {
        limit(slot.point(s0 + s, t0 + t)).ok().map(|d| d.p)
    };
    let mut ok = true;
    let patch = BezierPatch::interpolate(3, |s, t| {
        eval(s, t).unwrap_or_else(|| {
            ok = false;
            [f64::NAN; 3]
        })
    });
    let patch = match (patch, ok) {
        (Some(p), true) => p,
        _ => return Err(f64::INFINITY),
    };
    let mut misfit = 0.0f64;
    for &(s, t) in &[
        (0.13, 0.71),
        (0.5, 0.5),
        (0.91, 0.07),
        (0.02, 0.98),
        (1.0, 0.0),
    ] {
        let Some(q) = eval(s, t) else {
            return Err(f64::INFINITY);
        };
        let p = patch.derivative(s, t, 0, 0);
        for k in 0..3 {
            misfit = misfit.max((p[k] - q[k]).abs() / scale);
        }
    }
    if misfit <= 1e-9 {
        Ok(patch)
    } else {
        Err(misfit)
    }
}

fn build_cap(
    limit: &Base<'_>,
    c: &Candidate,
    solver: &CapSolver,
) -> Result<Result<CapInfo, Uncapped>, G2Error> {
    let n = c.slots.len();
    let uncapped = |reason| Uncapped {
        vertex: c.vertex,
        face: c.face,
        valence: n,
        reason,
    };
    // Length scale: the extent of the cap's corner positions.
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for s in &c.slots {
        for &(a, b) in &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            match limit(s.point(a, b)) {
                Ok(d) => {
                    for k in 0..3 {
                        lo[k] = lo[k].min(d.p[k]);
                        hi[k] = hi[k].max(d.p[k]);
                    }
                }
                Err(_) => return Ok(Err(uncapped("no surface next to the vertex"))),
            }
        }
    }
    let scale = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    if !(scale > 0.0 && scale.is_finite()) {
        return Ok(Err(uncapped("degenerate control points")));
    }
    let mut outer = Vec::with_capacity(n);
    for s in &c.slots {
        let v = neighbour(limit, s, 0.0, 1.0, scale);
        let u = neighbour(limit, s, 1.0, 0.0, scale);
        match (v, u) {
            (Ok(across_v), Ok(across_u)) => outer.push(OuterPatches { across_v, across_u }),
            _ => {
                return Ok(Err(uncapped(
                    "a neighbouring patch is not bicubic (feature too close)",
                )))
            }
        }
    }
    let cap = G2Cap::with_solver(solver, &outer)?;
    Ok(Ok(CapInfo {
        vertex: c.vertex,
        face_centre: c.face,
        slots: c.slots.clone(),
        cap,
    }))
}

impl crate::limit::Surface for G2Surface {
    fn num_faces(&self) -> usize {
        self.limit().num_faces()
    }

    fn num_subfaces(&self, f: usize) -> usize {
        self.limit().num_subfaces(f)
    }

    fn has_surface(&self, f: usize) -> bool {
        self.limit().has_surface(f)
    }

    /// [`G2Surface::eval_point`]; its only errors are those of the Catmull-Clark evaluator.
    fn evaluate(&self, p: SurfacePoint) -> Result<Derivatives, crate::limit::EvalError> {
        self.eval_point(p).map_err(|e| match e {
            G2Error::Eval(e) => e,
            _ => crate::limit::EvalError::BadParameter { u: p.u, v: p.v },
        })
    }
}
